// qrm/noise/trajectories.hpp: running a noisy circuit as quantum trajectories on the dense
// backend (complex double amplitudes: a Y error is complex even on a real circuit).
//
// One trajectory is a pure state: every gate event applies its op; a Pauli channel draws one
// uniform number and, below its probability, a uniformly chosen non-identity Pauli string (a second
// draw); dephasing applies Z below its probability; amplitude damping with gamma jumps (K1 =
// sqrt(gamma) |0><1|) with probability gamma P(qubit = 1) and otherwise applies K0 = diag(1,
// sqrt(1 - gamma)), renormalising either way. The average over trajectories of any probability is
// an unbiased estimate of the density-matrix value (the unravelling of each channel is exact).
// Damping leaves the state unnormalised until the end of the circuit (the jump draws compare
// ratios), which saves a pass per event.
// Every event consumes the same draws whatever the state, and trajectory i draws from
// rng::stream(seed, i), so results do not depend on threads or on the order trajectories run.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "../backends/dense.hpp"
#include "../support/parallel.hpp"
#include "../support/random.hpp"
#include "channels.hpp"

namespace qrm {

using trajectory_state = state_vector<std::complex<double>>;

namespace detail {
// Draws one of the 4^k - 1 non-identity Pauli strings on k qubits, uniformly, and calls f(i, P)
// for each qubit i the string does not leave alone (P = X, Y or Z).
template <class F>
void for_each_random_pauli(std::size_t k, rng& g, F&& f) {
  const std::uint64_t strings = (std::uint64_t{1} << (2 * k)) - 1;
  const std::uint64_t r = 1 + g.below(strings);
  for (std::size_t i = 0; i < k; ++i) switch ((r >> (2 * i)) & 3u) {
      case 1: f(i, gate::x()); break;
      case 2: f(i, gate::y()); break;
      case 3: f(i, gate::z()); break;
      default: break;
    }
}

template <int = 0>
inline void apply_random_pauli(trajectory_state& s, const std::vector<qubit_index>& qs, rng& g) {
  for_each_random_pauli(qs.size(), g, [&](std::size_t i, const gate1& p) { s.apply_gate1(p, qs[i], {}); });
}

// K0 = diag(1, sqrt(1 - gamma)), amplitude damping's no-jump operator (not unitary).
template <int = 0>
inline gate1 damping_no_jump(double gamma) {
  return gate::u(1.0, 0.0, 0.0, std::sqrt(1.0 - gamma));
}

// Amplitude damping of qubit q with the uniform draw u (apply_damping draws it), leaving the state
// scaled by a positive factor (normalize_state restores it): the jump probability gamma P(q = 1)
// = gamma one / total does not depend on the scale. A draw u >= gamma cannot jump whatever the
// state, so then K0 is one diagonal pass with no sums (the common case: gamma is small); below
// gamma the sums decide.
template <int = 0>
inline void apply_damping_drawn(trajectory_state& s, qubit_index q, double gamma, double u) {
  if (!(u < gamma)) {
    s.apply_gate1(damping_no_jump(gamma), q, {});
    return;
  }
  // The two halves' weights by the backend's vector reductions (a scalar loop summing into one
  // accumulator waited on every add: 19% of the superconducting preset's fused trajectories).
  const control is_one{q, true}, is_zero{q, false};
  const double one = s.probability(std::span<const control>(&is_one, 1));
  const double total = one + s.probability(std::span<const control>(&is_zero, 1));
  if (u < gamma * one / total) {
    s.apply_gate1(gate::u(0.0, 1.0 / std::sqrt(one), 0.0, 0.0), q, {});  // K1 = |0><1|, scaled
  } else {
    s.apply_gate1(damping_no_jump(gamma), q, {});
  }
}

template <int = 0>
inline void apply_damping(trajectory_state& s, qubit_index q, double gamma, rng& g) {
  apply_damping_drawn(s, q, gamma, g.uniform());
}

// Scales the state to norm 1 (after apply_damping).
template <int = 0>
inline void normalize_state(trajectory_state& s) {
  const double scale = 1.0 / std::sqrt(s.norm_squared());
  for (std::complex<double>& z : s.amplitudes()) z *= scale;
}
}  // namespace detail

// apply_noisy(state, circuit, g): one trajectory of the noisy circuit on `state`.
template <int = 0>
inline void apply_noisy(trajectory_state& s, const noisy_circuit& c, rng& g) {
  if (s.num_qubits() < c.width())
    throw std::invalid_argument("apply_noisy: the circuit needs " + std::to_string(c.width()) +
                                " qubits but the state has " + std::to_string(s.num_qubits()));
  const auto& ops = c.circuit.ops();
  bool damped = false;
  for (const noise_event& e : c.events) switch (e.kind) {
      case noise_event_kind::gate: emit_op(ops[e.op], s); break;
      case noise_event_kind::pauli:
        if (g.uniform() < e.probability) detail::apply_random_pauli(s, e.qubits, g);
        break;
      case noise_event_kind::dephasing:
        if (g.uniform() < e.probability) s.apply_gate1(gate::z(), e.qubits[0], {});
        break;
      case noise_event_kind::damping:
        detail::apply_damping(s, e.qubits[0], e.probability, g);
        damped = true;
        break;
    }
  if (damped) detail::normalize_state(s);
}

// measured_probability(state, condition, readout): the probability that measuring the condition's
// qubits reads the condition's values when each bit is misread with probability `readout`.
// readout = 0 is state.probability(condition) exactly.
template <int = 0>
inline double measured_probability(const trajectory_state& s, std::span<const control> condition, double readout) {
  if (readout == 0) return s.probability(condition);
  std::uint64_t mask = 0, value = 0;
  for (const control& c : condition) {
    mask |= std::uint64_t{1} << c.qubit;
    if (c.value) value |= std::uint64_t{1} << c.qubit;
  }
  std::vector<double> weight(condition.size() + 1);  // by the number of bits that disagree
  for (std::size_t d = 0; d < weight.size(); ++d)
    weight[d] = std::pow(readout, static_cast<double>(d)) *
                std::pow(1.0 - readout, static_cast<double>(condition.size() - d));
  const std::span<const std::complex<double>> a = s.amplitudes();
  double p = 0, total = 0;
  for (std::uint64_t i = 0; i < a.size(); ++i) {
    const double w = std::norm(a[i]);
    total += w;
    p += w * weight[static_cast<std::size_t>(std::popcount((i ^ value) & mask))];
  }
  return p / total;
}

// trajectory_options: how many trajectories, their seed, and the threads that share them (each
// trajectory runs on one thread; results do not depend on `threads`).
struct trajectory_options {
  std::size_t trajectories = 100;
  std::uint64_t seed = 1;
  unsigned threads = 0;  // 0: every hardware thread
};

// trajectory_mean: a probability averaged over trajectories, with its standard error (the sample
// standard deviation over sqrt(trajectories)).
struct trajectory_mean {
  double mean = 0;
  double standard_error = 0;
};

// for_each_trajectory(options, width, f): f(i, state, g) for every trajectory i, on a fresh
// |0...0> state of `width` qubits and the generator rng::stream(seed, i).
template <class F>
void for_each_trajectory(const trajectory_options& o, std::size_t width, F&& f) {
  if (o.trajectories == 0) throw std::invalid_argument("trajectories must be at least 1");
  qrm::detail::parallel_jobs(o.trajectories, o.threads, [&](std::size_t i) {
    dense_options d;
    d.threads = 1;
    trajectory_state s(width, d);
    rng g = rng::stream(o.seed, i);
    f(i, s, g);
  });
}

// mean_over_trajectories(values): mean and standard error of per-trajectory values, summed in
// index order; equal values (every trajectory without an error) give that value exactly.
template <int = 0>
inline trajectory_mean mean_over_trajectories(std::span<const double> v) {
  trajectory_mean m;
  if (v.empty()) return m;
  if (std::all_of(v.begin(), v.end(), [&](double x) { return x == v[0]; })) {
    m.mean = v[0];
    return m;
  }
  double s = 0;
  for (double x : v) s += x;
  m.mean = s / static_cast<double>(v.size());
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - m.mean) * (x - m.mean);
    m.standard_error = std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
  }
  return m;
}

}  // namespace qrm
