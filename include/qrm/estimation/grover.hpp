// qrm/estimation/grover.hpp: the pieces of amplitude amplification as run-time programs.
//
// Q = A S0 A^dagger S_chi: S_chi flips the sign of the good states, S0 the sign of |0...0>. Both
// reflections are single primitive ops (a multi-controlled diagonal gate), as a logical circuit
// would have them. Brassard et al. write Q = -A S0 A^dagger S_chi; the -1 is a global phase for
// Grover powers (it does matter inside phase estimation, see canonical.hpp).
//
// coin_program builds the "quantum coin" of Shimada and Hachisuka (see qcoin.hpp): a circuit
// whose amplitude on |0...0> is exactly +-(l - a) for a known reference l, from any A.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/ops.hpp"
#include "../circuit/program.hpp"
#include "problem.hpp"

namespace qrm {

namespace detail {
// diag(-1, 1): flips the sign of |0> on its target.
template <int = 0>
inline gate1 flip_zero() {
  return gate::u(-1.0, 0.0, 0.0, 1.0);
}
}  // namespace detail

// zero_reflection(width): S0, the sign flip of |0...0> on qubits [0, width): diag(-1, 1) on
// qubit 0 with negative controls on all the others.
template <int = 0>
inline program zero_reflection(std::size_t width) {
  if (width == 0) throw std::invalid_argument("zero_reflection: width must be positive");
  program p(width);
  std::vector<control> cs;
  for (qubit_index q = 1; q < width; ++q) cs.push_back({q, false});
  p.apply_gate1(detail::flip_zero(), 0, cs);
  return p;
}

// good_reflection(width, good, extra): S_chi, the sign flip of the states where every control in
// `good` holds (and every control in `extra`, which makes it a controlled S_chi). One op: Z (or
// diag(-1, 1) for a value-0 condition) on the first good qubit, controlled by the rest.
template <int = 0>
inline program good_reflection(std::size_t width, std::span<const control> good, std::span<const control> extra = {}) {
  detail::check_good(std::vector<control>(good.begin(), good.end()), width, "good_reflection");
  program p(width);
  std::vector<control> cs(good.begin() + 1, good.end());
  cs.insert(cs.end(), extra.begin(), extra.end());
  p.apply_gate1(good[0].value ? gate::z() : detail::flip_zero(), good[0].qubit, cs);
  return p;
}

// grover_operator(problem): Q = A S0 A^dagger S_chi as one program (S_chi runs first).
template <int = 0>
inline program grover_operator(const estimation_problem& e) {
  const std::size_t w = e.a.width();
  program q(w);
  q.append(good_reflection(w, e.good));
  q.append(e.a.adjoint());
  q.append(zero_reflection(w));
  q.append(e.a);
  return q;
}

// rescaled_problem(problem, s): A followed by Ry(2 asin s) on a fresh ancilla (qubit `width`),
// good = the old condition and ancilla = 1, so the new amplitude is a * s^2.
template <int = 0>
inline estimation_problem rescaled_problem(const estimation_problem& e, double s) {
  if (!(s > 0.0 && s <= 1.0))
    throw std::invalid_argument("rescaled_problem: scale must be in (0, 1], got " + std::to_string(s));
  const std::size_t w = e.a.width();
  estimation_problem r{program(w + 1), e.good};
  r.a.append(e.a);
  r.a.apply_gate1(gate::ry(2.0 * std::asin(s)), static_cast<qubit_index>(w), {});
  r.good.push_back({static_cast<qubit_index>(w), true});
  return r;
}

// coin_program(problem, l): a circuit C on width + 2 qubits (c = qubit width, r = width + 1) with
// <0...0| C |0...0> = l - a (for l >= 1/2) or a - l (for l < 1/2) exactly, for a known reference
// l in [0, 1] and any A. Only |l - a| matters to the coin.
//
// Why it works: <0| A^dagger S_chi A |0> = 1 - 2a (S_chi = 1 - 2 * projector on good). A qubit c
// rotated by Ry(2 gamma) runs A, S_chi, A^dagger in its |0> branch (S_chi controlled on c = 0) and
// A, A^dagger = identity in its |1> branch; undoing the rotation leaves amplitude
// cos^2(gamma) (1 - 2a) + sin^2(gamma) on |0...0>. With cos^2 gamma = 1/(2l) that is 1 - a/l; a
// reference qubit r rotated so that <0|Ry|0> = l scales it to l - a. For l < 1/2 the |0> branch
// uses -S_chi instead (a diag(-1, 1) on c), giving (a - l)/(1 - l), scaled by 1 - l to a - l.
// Costs one A and one A^dagger.
template <int = 0>
inline program coin_program(const estimation_problem& e, double l) {
  if (!(l >= 0.0 && l <= 1.0))
    throw std::invalid_argument("coin_program: reference must be in [0, 1], got " + std::to_string(l));
  const std::size_t w = e.a.width();
  const auto c = static_cast<qubit_index>(w), r = static_cast<qubit_index>(w + 1);
  const bool high = l >= 0.5;
  const double weight = high ? 1.0 / (2.0 * l) : 1.0 / (2.0 * (1.0 - l));  // cos^2 gamma, in [1/2, 1]
  const double gamma = std::acos(std::sqrt(weight));
  const double ref = high ? l : 1.0 - l;  // <0| Ry(2 beta) |0> = cos beta
  program p(w + 2);
  p.apply_gate1(gate::ry(2.0 * std::acos(ref)), r, {});
  p.apply_gate1(gate::ry(2.0 * gamma), c, {});
  p.append(e.a);
  if (!high) p.apply_gate1(detail::flip_zero(), c, {});
  const control on_c0{c, false};
  p.append(good_reflection(w + 2, e.good, std::span<const control>(&on_c0, 1)));
  p.append(e.a.adjoint());
  p.apply_gate1(gate::ry(-2.0 * gamma), c, {});
  return p;
}

// coin_iteration(problem, l): the quantum coin's iterate G = C S0 C^dagger S0 (S0 acts first) on
// C = coin_program(problem, l); n of them on |0...0> leave it with the head probability.
template <int = 0>
inline program coin_iteration(const estimation_problem& e, double l) {
  const program c = coin_program(e, l);
  const std::size_t w = c.width();
  program g(w);
  g.append(zero_reflection(w));
  g.append(c.adjoint());
  g.append(zero_reflection(w));
  g.append(c);
  return g;
}

}  // namespace qrm
