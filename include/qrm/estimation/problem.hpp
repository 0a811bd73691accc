// qrm/estimation/problem.hpp: an amplitude-estimation problem (a state preparation A as a
// run-time program, and the "good" outcome as a list of controls) and two test problems.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/ops.hpp"
#include "../circuit/program.hpp"

namespace qrm {

// estimation_problem: estimate a = P(every control in `good` holds) in the state A|0...0>.
struct estimation_problem {
  program a;
  std::vector<control> good;
};

namespace detail {
// Throws unless `good` is a non-empty list of distinct qubits inside a program of `width` qubits.
template <int = 0>
inline void check_good(const std::vector<control>& good, std::size_t width, const char* who) {
  if (good.empty())
    throw std::invalid_argument(std::string(who) + ": the good condition is empty (give at least one control)");
  for (std::size_t i = 0; i < good.size(); ++i) {
    if (good[i].qubit >= width)
      throw std::invalid_argument(std::string(who) + ": good condition on qubit " + std::to_string(good[i].qubit) +
                                  " but A has " + std::to_string(width) + " qubits");
    for (std::size_t j = 0; j < i; ++j)
      if (good[j].qubit == good[i].qubit)
        throw std::invalid_argument(std::string(who) + ": qubit " + std::to_string(good[i].qubit) +
                                    " appears twice in the good condition");
  }
}

// The Ry angle that puts probability v on |1>: 2 asin(sqrt(v)).
template <int = 0>
inline double ry_angle_for(double v) {
  return 2.0 * std::asin(std::sqrt(v));
}
}  // namespace detail

// bernoulli_problem(P): one qubit rotated by Ry(2 asin sqrt P); good = that qubit is 1, so a = P.
template <int = 0>
inline estimation_problem bernoulli_problem(double p) {
  if (!(p >= 0.0 && p <= 1.0))
    throw std::invalid_argument("bernoulli_problem: probability must be in [0, 1], got " + std::to_string(p));
  estimation_problem e{program(1), {control{0, true}}};
  e.a.apply_gate1(gate::ry(detail::ry_angle_for(p)), 0, {});
  return e;
}

// sine_integral_value(n): mean over x < 2^n of sin^2((x + 1/2) / 2^n), in closed form
// 1/2 - sin(2) / (4 N sin(1/N)) with N = 2^n (sum of cosines of an arithmetic progression).
template <int = 0>
inline double sine_integral_value(unsigned n) {
  const double N = std::ldexp(1.0, static_cast<int>(n));
  return 0.5 - std::sin(2.0) / (4.0 * N * std::sin(1.0 / N));
}

// sine_integral_problem(n): a real circuit on n + 1 qubits with a = sine_integral_value(n):
// H on the n x-qubits, then Ry rotations of the out qubit (qubit n) whose angles add up to
// 2 (x + 1/2) / 2^n: one unconditional Ry(2 * (1/2) / 2^n) and, for each bit i, Ry(2 * 2^i / 2^n)
// controlled on x_i = 1. Good = out is 1.
template <int = 0>
inline estimation_problem sine_integral_problem(unsigned n) {
  if (n < 1 || n > 24)
    throw std::invalid_argument("sine_integral_problem: n must be in [1, 24], got " + std::to_string(n));
  const double N = std::ldexp(1.0, static_cast<int>(n));
  const qubit_index out = static_cast<qubit_index>(n);
  estimation_problem e{program(n + 1), {control{out, true}}};
  for (qubit_index i = 0; i < n; ++i) e.a.apply_gate1(gate::h(), i, {});
  e.a.apply_gate1(gate::ry(2.0 * 0.5 / N), out, {});
  for (qubit_index i = 0; i < n; ++i) {
    const control c{i, true};
    e.a.apply_gate1(gate::ry(2.0 * std::ldexp(1.0, static_cast<int>(i)) / N), out, std::span<const control>(&c, 1));
  }
  return e;
}

}  // namespace qrm
