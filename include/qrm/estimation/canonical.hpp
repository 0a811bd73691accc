// qrm/estimation/canonical.hpp: canonical, phase-estimation based amplitude estimation (Brassard,
// Hoyer, Mosca, Tapp 2000) with m evaluation qubits, and maximum-likelihood post-processing.
//
// A|0> splits into the two eigenvectors of Brassard's Q = -A S0 A^dagger S_chi with eigenvalues
// exp(+-2i theta), a = sin^2 theta. Phase estimation with M = 2^m evaluation qubits therefore
// returns y in [0, M) with the closed-form law
//   P(y) = (F(y/M - theta/pi) + F(y/M + theta/pi)) / 2,   F(d) = sin^2(M pi d) / (M^2 sin^2(pi d)),
// (F is the Fejer kernel, F(0) = 1). qrm's grover_operator omits Brassard's -1; in a phase
// estimation circuit that sign is a controlled phase and must be put back (it shifts y by M/2).
//
// How the oracle is used: the law above needs only theta, so this estimator asks the oracle for
// p_0 = a once and samples y from the closed form. For a simulated_oracle that a comes from
// simulating A (not from simulating the phase-estimation circuit, which would need controlled
// powers of Q and an inverse QFT). The calls reported are those the circuit would make per shot:
// M - 1 applications of Q and 2M - 1 of A (or A^dagger).
//
// Post-processing: the plain QAE estimate is sin^2(pi y*/M) for the most frequent folded outcome
// y* (raw_estimate); the estimate is the maximiser of sum_y n_y log P(y | theta) over [0, pi/2]
// (grid and refinement, as qiskit's MLE does between the bubbles next to y*), and the interval is
// the likelihood-ratio interval: the hull of {theta : 2 (L_max - L(theta)) <= z^2}, z the normal
// quantile at 1 - alpha/2 (the chi-square quantile with one degree of freedom), mapped through
// sin^2. The hull matters: when theta sits near a grid point pi y / M, few outcomes land on the
// neighbours that tell its two sides apart, the likelihood has two nearly equal modes, and an
// interval around one of them misses the truth about half of the time.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "../backends/measure.hpp"
#include "../support/random.hpp"
#include "detail/maximize.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

struct canonical_options {
  unsigned evaluation_qubits = 5;  // m in [1, 12]; M = 2^m phase outcomes (post-processing costs ~32 M^2)
  std::uint64_t shots = 100;
  double alpha = 0.05;
  bool exact_probabilities = false;
};

namespace detail {
// Fejer kernel F(d) = (sin(M pi d) / (M sin(pi d)))^2, with its limit 1 where sin(pi d) = 0.
template <int = 0>
inline double fejer(double d, double M) {
  const double den = M * std::sin(std::numbers::pi * d);
  if (std::fabs(den) < 1e-300) return 1.0;
  const double q = std::sin(M * std::numbers::pi * d) / den;
  return std::min(1.0, q * q);
}
}  // namespace detail

// The phase-register law P(y), y in [0, 2^m), for a given theta.
template <int = 0>
inline std::vector<double> canonical_phase_distribution(double theta, unsigned m) {
  if (m < 1 || m > 20)
    throw std::invalid_argument("canonical_phase_distribution: m must be in [1, 20], got " + std::to_string(m));
  const double M = std::ldexp(1.0, static_cast<int>(m));
  const double w = theta / std::numbers::pi;
  std::vector<double> p(static_cast<std::size_t>(M));
  double total = 0;
  for (std::size_t y = 0; y < p.size(); ++y) {
    const double x = static_cast<double>(y) / M;
    p[y] = 0.5 * (detail::fejer(x - w, M) + detail::fejer(x + w, M));
    total += p[y];
  }
  for (double& v : p) v /= total;  // the kernel sums to 1 exactly; this removes rounding only
  return p;
}

// canonical_amplitude_estimation(oracle, options, g): QPE-based AE with MLE post-processing.
template <amplitude_oracle O>
estimation_result canonical_amplitude_estimation(O& oracle, const canonical_options& opt, rng& g) {
  using std::numbers::pi;
  detail::check_alpha(opt.alpha, "canonical_amplitude_estimation");
  detail::check_shots(opt.shots, "canonical_amplitude_estimation");
  if (opt.evaluation_qubits < 1 || opt.evaluation_qubits > 12)
    throw std::invalid_argument("canonical_amplitude_estimation: evaluation_qubits must be in [1, 12], got " +
                                std::to_string(opt.evaluation_qubits));
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "canonical";
  r.exact_probabilities = opt.exact_probabilities;
  const unsigned m = opt.evaluation_qubits;
  const double M = std::ldexp(1.0, static_cast<int>(m));
  const auto Mi = static_cast<std::uint64_t>(M);

  const double a = detail::checked_probability(oracle.probability(0), "canonical_amplitude_estimation");
  const std::vector<double> law = canonical_phase_distribution(detail::amplitude_angle(a), m);
  std::vector<double> counts(law.size());
  if (opt.exact_probabilities) {
    for (std::size_t y = 0; y < law.size(); ++y) counts[y] = law[y] * static_cast<double>(opt.shots);
  } else {
    const auto c = sample_counts(law, opt.shots, g);
    for (std::size_t y = 0; y < law.size(); ++y) counts[y] = static_cast<double>(c[y]);
  }
  r.phase_counts = counts;
  r.shots = opt.shots;
  r.a_calls = (2 * Mi - 1) * opt.shots;
  r.grover_calls = (Mi - 1) * opt.shots;
  r.rounds.push_back({Mi - 1, opt.shots, static_cast<double>(opt.shots) - counts[0], 0.0});

  // Plain QAE: the most frequent outcome folded onto j in [0, M/2] (y and M - y give the same a).
  std::size_t best_j = 0;
  double best_count = -1;
  for (std::size_t j = 0; j <= Mi / 2; ++j) {
    const double c = counts[j] + ((j != 0 && j != Mi / 2) ? counts[Mi - j] : 0.0);
    if (c > best_count) best_count = c, best_j = j;
  }
  r.raw_estimate = std::pow(std::sin(pi * static_cast<double>(best_j) / M), 2);

  auto loglik = [&](double theta) {
    const double w = theta / pi;
    double l = 0;
    for (std::size_t y = 0; y < counts.size(); ++y) {
      if (counts[y] <= 0) continue;
      const double x = static_cast<double>(y) / M;
      const double p = 0.5 * (detail::fejer(x - w, M) + detail::fejer(x + w, M));
      l += counts[y] * std::log(std::max(p, 1e-300));
    }
    return l;
  };
  // The law's features are pi/M wide in theta; 64 grid points per feature separate the modes.
  const auto points = static_cast<std::size_t>(std::max(2000.0, 32.0 * M));
  const auto [theta, best] = detail::grid_maximize(loglik, 0.0, pi / 2, points);
  const double z = detail::normal_quantile(1.0 - opt.alpha / 2.0);
  const auto [lo, hi] = detail::superlevel_hull(loglik, theta, best - 0.5 * z * z, 0.0, pi / 2, points);
  r.estimate = std::pow(std::sin(theta), 2);
  r.confidence_interval = detail::amplitude_interval(lo, hi, pi / 2);
  r.confidence = 1.0 - opt.alpha;
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
