// qrm/estimation/iqae.hpp: Iterative Amplitude Estimation (Grinko, Gacon, Zoufal, Woerner 2019).
//
// theta = asin(sqrt a) is tracked in units of a full turn (t = theta / 2 pi, a = sin^2(2 pi t),
// t in [0, 1/4]). Each round picks the largest power k (scaling K = 4k + 2) for which K times the
// current t-interval lies inside one half circle, so cos(K 2 pi t) = 1 - 2 p_k can be inverted
// unambiguously; `shots` runs of Q^k A give an interval for p_k (Clopper-Pearson or
// Chernoff-Hoeffding, each at level alpha / T with T the maximal number of rounds), which maps
// back to a narrower t-interval. Stops when the t-interval is narrower than epsilon / pi, so the
// final a-interval has half-width at most epsilon, with probability at least 1 - alpha.
// Consecutive rounds at the same k pool their shots (as in the paper).
//
// Differences from the qiskit-algorithms implementation, both at its edges: the Chernoff
// interval uses the pooled frequency (qiskit pairs this round's frequency with the pooled shot
// count), and both ends of the new t-interval use the half-turn index m = floor(K t_mid) of the
// interval's midpoint (qiskit takes floor(K t_lo) and floor(K t_hi); when an end sits exactly on
// a multiple of 1/K, as after a round with zero hits, rounding can move it to the previous
// half-turn, and the interval then jumps away from the truth).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "../support/random.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

enum class iqae_interval { clopper_pearson, chernoff_hoeffding };

struct iqae_options {
  double epsilon = 0.01;  // target half-width of the interval for a, in (0, 0.5]
  double alpha = 0.05;    // the interval fails with probability at most alpha
  iqae_interval interval = iqae_interval::clopper_pearson;
  std::uint64_t shots = 100;  // shots per round
  double min_ratio = 2.0;     // smallest allowed K_next / K
  bool exact_probabilities = false;
  std::uint64_t max_rounds = 100000;  // safety stop (never reached for sane inputs)
};

namespace detail {
// Largest k (K = 4k + 2 >= min_ratio * K_old) such that K [t_lo, t_hi] lies in one half circle;
// returns the old k and side when there is none.
template <int = 0>
inline std::pair<std::uint64_t, bool> iqae_next_power(std::uint64_t k, bool upper, double t_lo, double t_hi,
                                                      double min_ratio) {
  const double old_scaling = 4.0 * static_cast<double>(k) + 2.0;
  const double width = t_hi - t_lo;
  if (!(width > 0)) return {k, upper};
  const double max_scaling_d = std::floor(1.0 / (2.0 * width));
  if (max_scaling_d < 2.0) return {k, upper};
  const auto max_scaling = static_cast<std::int64_t>(std::min(max_scaling_d, 9.0e15));
  std::int64_t scaling = max_scaling - ((max_scaling - 2) % 4);
  for (; static_cast<double>(scaling) >= min_ratio * old_scaling; scaling -= 4) {
    const double s = static_cast<double>(scaling);
    const double f_lo = s * t_lo - std::floor(s * t_lo);
    const double f_hi = s * t_hi - std::floor(s * t_hi);
    if (f_lo <= f_hi && f_hi <= 0.5 && f_lo <= 0.5) return {static_cast<std::uint64_t>((scaling - 2) / 4), true};
    if (f_hi >= 0.5 && f_hi >= f_lo && f_lo >= 0.5) return {static_cast<std::uint64_t>((scaling - 2) / 4), false};
  }
  return {k, upper};
}
}  // namespace detail

// iterative_amplitude_estimation(oracle, options, g): IQAE on any amplitude_oracle.
template <amplitude_oracle O>
estimation_result iterative_amplitude_estimation(O& oracle, const iqae_options& opt, rng& g) {
  using std::numbers::pi;
  if (!(opt.epsilon > 0.0 && opt.epsilon <= 0.5))
    throw std::invalid_argument("iterative_amplitude_estimation: epsilon must be in (0, 0.5], got " +
                                std::to_string(opt.epsilon));
  detail::check_alpha(opt.alpha, "iterative_amplitude_estimation");
  detail::check_shots(opt.shots, "iterative_amplitude_estimation");
  if (!(opt.min_ratio > 1.0))
    throw std::invalid_argument("iterative_amplitude_estimation: min_ratio must be above 1, got " +
                                std::to_string(opt.min_ratio));
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "iqae";
  r.exact_probabilities = opt.exact_probabilities;
  detail::shot_sampler s(g, opt.exact_probabilities, r);

  const double max_rounds =
      std::floor(std::log(opt.min_ratio * pi / 8.0 / opt.epsilon) / std::log(opt.min_ratio)) + 1.0;
  double t_lo = 0.0, t_hi = 0.25;
  bool upper = true;
  std::uint64_t k = 0, pooled_shots = 0;
  double pooled_hits = 0;
  std::uint64_t rounds = 0;
  while (t_hi - t_lo > opt.epsilon / pi) {
    if (++rounds > opt.max_rounds) {
      r.warning = "iqae stopped after max_rounds rounds before reaching epsilon";
      break;
    }
    const auto [next_k, next_upper] = detail::iqae_next_power(k, upper, t_lo, t_hi, opt.min_ratio);
    if (rounds == 1 || next_k != k) pooled_shots = 0, pooled_hits = 0;
    k = next_k;
    upper = next_upper;
    pooled_hits += s.draw(oracle, k, opt.shots);
    pooled_shots += opt.shots;
    const double n = static_cast<double>(pooled_shots);
    double p_min, p_max;
    if (opt.interval == iqae_interval::chernoff_hoeffding) {
      const double eps = std::sqrt(3.0 * std::log(2.0 * max_rounds / opt.alpha) / n);
      p_min = std::max(0.0, pooled_hits / n - eps);
      p_max = std::min(1.0, pooled_hits / n + eps);
    } else {
      std::tie(p_min, p_max) = detail::clopper_pearson(pooled_hits, n, opt.alpha / max_rounds);
    }
    // p_k = sin^2(K 2 pi t) = (1 - cos(2 pi K t)) / 2: invert on the known half circle.
    auto turn = [](double p) { return std::acos(std::clamp(1.0 - 2.0 * p, -1.0, 1.0)) / (2.0 * pi); };
    double f_min, f_max;
    if (upper) {
      f_min = turn(p_min);
      f_max = turn(p_max);
    } else {
      f_min = 1.0 - turn(p_max);
      f_max = 1.0 - turn(p_min);
    }
    const double K = 4.0 * static_cast<double>(k) + 2.0;
    const double m = std::floor(K * 0.5 * (t_lo + t_hi));
    const double new_lo = (m + f_min) / K, new_hi = (m + f_max) / K;
    t_lo = std::clamp(new_lo, 0.0, 0.25);
    t_hi = std::clamp(new_hi, t_lo, 0.25);
  }
  r.confidence_interval = detail::amplitude_interval(2 * pi * t_lo, 2 * pi * t_hi, pi / 2);
  r.estimate = r.raw_estimate = 0.5 * (r.confidence_interval[0] + r.confidence_interval[1]);
  r.confidence = 1.0 - opt.alpha;
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
