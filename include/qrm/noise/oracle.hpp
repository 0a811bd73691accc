// qrm/noise/oracle.hpp: what an estimator asks a noisy quantum computer (qrm::amplitude_oracle).
//
// noisy_oracle(problem, model, options): p_k = P(the good qubits read good) after Q^k A, run as
// quantum trajectories with the model's noise (gate level: A and Q decomposed into single-qubit
// gates and CNOTs, noise after every gate and relaxation on the schedule; logical level: one
// Pauli channel per logical op), readout errors included. The estimators draw their shots from
// these probabilities as from any oracle, so the same code measures them ideal or noisy.
// Every trajectory runs A and then Q again and again, recording p after each; `prepare(K)` runs
// them to K at once (an estimator that asks for a larger power later makes the oracle run them
// again to twice the power, so the trajectories are the same and results do not depend on the
// order of questions). By default the trajectories run A and Q fused once, with the errors that
// fire folded into the blocks they fall in (fused_trajectories.hpp): the same errors and states to
// rounding, several times faster at gate level. The ideal model runs one trajectory: p_k is then
// the probability a plain run of the decomposed circuits on the dense backend gives, bit for bit
// with fuse = false, to rounding (1e-12) fused.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../circuit/decompose.hpp"
#include "../estimation/grover.hpp"
#include "../estimation/oracle.hpp"
#include "../estimation/problem.hpp"
#include "channels.hpp"
#include "fused_trajectories.hpp"
#include "model.hpp"
#include "trajectories.hpp"

namespace qrm {

// gates: trajectories of the decomposed circuit; logical: trajectories of the logical circuit;
// global: no simulation of errors at all (global_noise_oracle below).
enum class noise_level : unsigned char { gates, logical, global };

struct noisy_oracle_options : trajectory_options {
  noise_level level = noise_level::gates;
  decompose_options decompose;  // how A and Q are lowered (gate level), or costed (logical level)
  bool fuse = true;  // run fused gates between the errors (fused_noisy_circuit); false: gate by gate
};

// noisy_grover_circuits: A and Q of a problem with their noise (see the header comment).
struct noisy_grover_circuits {
  noisy_circuit a, grover;
  std::size_t width = 0;  // qubits a trajectory needs (the decomposition's ancillas included)
};

template <int = 0>
inline noisy_circuit noisy_circuit_of(const program& p, const noise_model& m, const noisy_oracle_options& o) {
  if (o.level == noise_level::gates) return gate_level_noise(decompose(p, o.decompose).circuit, m);
  if (o.level == noise_level::global)
    throw std::invalid_argument("noise_level::global simulates no circuit; use global_noise_oracle");
  return logical_level_noise(p, m, o.decompose);
}

// The depolarizing error probability of one run of p: what its decomposition's gate counts imply.
template <int = 0>
inline double implied_program_error(const program& p, const noise_model& m, decompose_options o = {}) {
  const decomposed_counts c = decomposed_metrics(p, o);
  return implied_error(m, c.single_qubit_count, c.cnot_count + 6 * c.toffoli_count);
}

template <int = 0>
inline noisy_grover_circuits noisy_grover_circuits_of(const estimation_problem& e, const noise_model& m,
                                                      const noisy_oracle_options& o) {
  detail::check_good(e.good, e.a.width(), "noisy_oracle");
  noisy_grover_circuits c{noisy_circuit_of(e.a, m, o), noisy_circuit_of(grover_operator(e), m, o), 0};
  c.width = std::max(c.a.width(), c.grover.width());
  return c;
}

// A class template only so that its members are compiled where used (see qrm.hpp).
template <int = 0>
class basic_noisy_oracle {
 public:
  basic_noisy_oracle(estimation_problem e, noise_model m, noisy_oracle_options o = {})
      : e_(std::move(e)), m_(std::move(m)), o_(o), c_(noisy_grover_circuits_of(e_, m_, o_)) {
    if (m_.is_ideal()) o_.trajectories = 1;  // every trajectory would be the same
    if (o_.fuse) fused_ = {fused_noisy_circuit(c_.a), fused_noisy_circuit(c_.grover)};
  }

  const estimation_problem& problem() const { return e_; }
  const noise_model& model() const { return m_; }
  const noisy_grover_circuits& circuits() const { return c_; }
  std::size_t trajectories() const { return o_.trajectories; }

  // Runs every trajectory through Q^kmax A (nothing if that was done already).
  void prepare(std::uint64_t kmax) {
    if (!curve_.empty() && kmax < curve_.size()) return;
    const std::size_t n = o_.trajectories, ks = static_cast<std::size_t>(kmax) + 1;
    std::vector<double> p(n * ks);  // trajectory-major
    for_each_trajectory(o_, c_.width, [&](std::size_t t, trajectory_state& s, rng& g) {
      run(s, c_.a, fused_ ? &fused_->first : nullptr, g);
      p[t * ks] = read(s);
      for (std::size_t k = 1; k < ks; ++k) {
        run(s, c_.grover, fused_ ? &fused_->second : nullptr, g);
        p[t * ks + k] = read(s);
      }
    });
    grover_iterations_ += static_cast<std::uint64_t>(n) * kmax;
    curve_.assign(ks, {});
    std::vector<double> column(n);
    for (std::size_t k = 0; k < ks; ++k) {
      for (std::size_t t = 0; t < n; ++t) column[t] = p[t * ks + k];
      curve_[k] = mean_over_trajectories(std::span<const double>(column));
    }
  }

  // p_k with its standard error over trajectories.
  trajectory_mean probability_with_error(std::uint64_t k) {
    if (k >= curve_.size()) prepare(std::max<std::uint64_t>(k, 2 * curve_.size()));
    return curve_[static_cast<std::size_t>(k)];
  }
  double probability(std::uint64_t k) {
    return detail::checked_probability(probability_with_error(k).mean, "noisy_oracle");
  }

  // The same problem with a * s^2 (an extra rotated ancilla, noisy like every other gate).
  basic_noisy_oracle rescaled(double s) const { return basic_noisy_oracle(rescaled_problem(e_, s), m_, o_); }

  // Head probability of the quantum coin (qcoin.hpp) after n noisy coin iterations: 1 - P(all
  // of the coin circuit's qubits read 0).
  double coin_probability(double l, std::uint64_t n) {
    const auto key = std::make_pair(l, n);
    if (auto it = coin_cache_.find(key); it != coin_cache_.end()) return it->second;
    const program g = coin_iteration(e_, l);
    const std::size_t w = g.width();
    const noisy_circuit ng = noisy_circuit_of(g, m_, o_);
    std::optional<fused_noisy_circuit> fused;
    if (o_.fuse) fused.emplace(ng);
    std::vector<control> zero;
    for (qubit_index q = 0; q < w; ++q) zero.push_back({q, false});
    std::vector<double> stay(o_.trajectories);
    for_each_trajectory(o_, ng.width(), [&](std::size_t t, trajectory_state& s, rng& r) {
      for (std::uint64_t i = 0; i < n; ++i) run(s, ng, fused ? &*fused : nullptr, r);
      stay[t] = measured_probability(s, std::span<const control>(zero), m_.readout);
    });
    const double p =
        1.0 - detail::checked_probability(mean_over_trajectories(std::span<const double>(stay)).mean, "noisy_oracle");
    coin_cache_.emplace(key, p);
    return p;
  }

  // Grover iterations simulated, summed over trajectories.
  std::uint64_t simulated_grover_iterations() const { return grover_iterations_; }

 private:
  static void run(trajectory_state& s, const noisy_circuit& c, const fused_noisy_circuit* fused, rng& g) {
    if (fused)
      apply_noisy(s, *fused, g);
    else
      apply_noisy(s, c, g);
  }
  double read(const trajectory_state& s) const {
    return measured_probability(s, std::span<const control>(e_.good), m_.readout);
  }

  estimation_problem e_;
  noise_model m_;
  noisy_oracle_options o_;
  noisy_grover_circuits c_;
  std::optional<std::pair<fused_noisy_circuit, fused_noisy_circuit>> fused_;  // A and Q, with o_.fuse
  std::vector<trajectory_mean> curve_;
  std::uint64_t grover_iterations_ = 0;
  std::map<std::pair<double, std::uint64_t>, double> coin_cache_;
};

using noisy_oracle = basic_noisy_oracle<>;

// global_noise_oracle(problem, model): the cheapest model, for circuits too wide for trajectories
// (Tanaka et al. 2021): each run of A, or of Q, either works perfectly or (with the error
// probability its decomposition implies, implied_program_error) leaves the register maximally
// mixed. So p_k = L_k sin^2((2k+1) theta) + (1 - L_k) 2^-g with L_k = (1 - e_A)(1 - e_Q)^k and g
// good qubits, then readout flips. It needs only a = P(good) from one ideal run. It ignores that
// local errors leave most of the state intact (the logical-level trajectories show the noisy
// walk drifting to its own level, not to 2^-g), so it is an approximation to be compared with
// them where both run (README).
template <int = 0>
class basic_global_noise_oracle {
 public:
  basic_global_noise_oracle(estimation_problem e, noise_model m, double a, decompose_options o = {})
      : e_(std::move(e)), m_(std::move(m)), o_(o), a_(a), theta_(detail::amplitude_angle(a)) {
    validate(m_);
    detail::check_good(e_.good, e_.a.width(), "global_noise_oracle");
    if (m_.readout > 0 && e_.good.size() > 1)
      throw std::invalid_argument("global_noise_oracle: readout errors are modelled for a single good qubit");
    fa_ = 1 - implied_program_error(e_.a, m_, o_);
    fq_ = 1 - implied_program_error(grover_operator(e_), m_, o_);
    mixed_ = std::ldexp(1.0, -static_cast<int>(e_.good.size()));
  }
  double survival_a() const { return fa_; }  // 1 - e_A
  double survival_q() const { return fq_; }  // 1 - e_Q

  double probability(std::uint64_t k) const {
    const double l = fa_ * std::pow(fq_, static_cast<double>(k));
    const double p = l * detail::amplified_probability(theta_, k) + (1 - l) * mixed_;
    return p * (1 - m_.readout) + (1 - p) * m_.readout;
  }
  // The rescaled problem's a is a s^2; its circuits (one more rotation) are costed again.
  basic_global_noise_oracle rescaled(double s) const {
    return basic_global_noise_oracle(rescaled_problem(e_, s), m_, a_ * s * s, o_);
  }
  // The quantum coin under the same model: the coin circuit G^n survives with (1 - e_G)^n.
  double coin_probability(double l, std::uint64_t n) const {
    const program g = coin_iteration(e_, l);
    const std::size_t w = g.width();
    const double survive = std::pow(1 - implied_program_error(g, m_, o_), static_cast<double>(n));
    const double ideal = detail::coin_head_probability(a_, l, n);
    const double stay = survive * (1 - ideal) + (1 - survive) * std::ldexp(1.0, -static_cast<int>(w));
    return 1 - stay;
  }

 private:
  estimation_problem e_;
  noise_model m_;
  decompose_options o_;
  double a_, theta_, fa_ = 1, fq_ = 1, mixed_ = 0.5;
};

using global_noise_oracle = basic_global_noise_oracle<>;

}  // namespace qrm
