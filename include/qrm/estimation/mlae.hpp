// qrm/estimation/mlae.hpp: Maximum-Likelihood Amplitude Estimation (Suzuki et al. 2020).
//
// `shots` runs of Q^k A for each power k of a schedule (exponential 0, 1, 2, 4, ..., 2^(m-1), or
// linear 0, 1, ..., m, or an explicit list); theta is the maximiser over [0, pi/2] of
//   L(theta) = sum_k h_k log sin^2((2k+1) theta) + (N_k - h_k) log cos^2((2k+1) theta).
// L is multimodal (each term oscillates with period pi / (2k+1)): the maximum is found on grids
// with several points per standard deviation and per period, the best grid maxima refined by
// golden section, in stages of increasing power that each search the window the previous stage
// left (see the code). The Fisher information of theta does not depend on theta: each shot at power k carries
// 4 (2k+1)^2. The interval is theta_hat +- z / sqrt(I) (z the normal quantile at 1 - alpha/2),
// clipped to [0, pi/2] and mapped through sin^2; the interval on theta, unlike the delta-method
// interval on a, keeps its width at a = 0 and a = 1.
//
// Noise-aware MLAE (`noise_aware`, after Tanaka et al. 2021, "Amplitude estimation via maximum
// likelihood on noisy quantum computer"): on a depolarized machine the Grover oscillation decays
// to 1/2, p_k = (1 - exp(-r (2k+1)) cos(2 (2k+1) theta)) / 2, with r the decay per application of
// A (Q holds two). (theta, r) maximise the likelihood of that model: the profile likelihood
// max_theta L(theta, r) on a grid of r (0 and 41 values from 1e-4 to 1, ten per decade), refined by
// golden section in log r; theta for each r by the staged search above, with each shot's
// information about theta scaled by exp(-2 r (2k+1)). The interval uses the 2x2 Fisher
// information of (theta, r) (r a nuisance parameter); `damping` in the result is r. Readout
// errors and amplitude damping pull p_k towards other values than 1/2: the model is then only
// approximate.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/random.hpp"
#include "detail/maximize.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

enum class mlae_schedule { exponential, linear };

struct mlae_options {
  mlae_schedule schedule = mlae_schedule::exponential;
  unsigned m = 5;                     // exponential: powers 0, 2^0 .. 2^(m-1); linear: 0 .. m
  std::vector<std::uint64_t> powers;  // if not empty, used instead of the schedule
  std::uint64_t shots = 100;          // shots per power
  double alpha = 0.05;
  bool exact_probabilities = false;
  bool noise_aware = false;  // fit a depolarizing decay with the amplitude (header comment)
};

// The powers an options object asks for.
template <int = 0>
inline std::vector<std::uint64_t> mlae_powers(const mlae_options& opt) {
  if (!opt.powers.empty()) return opt.powers;
  if (opt.m > 40) throw std::invalid_argument("mlae_powers: m must be at most 40, got " + std::to_string(opt.m));
  std::vector<std::uint64_t> p{0};
  for (unsigned j = 0; j < opt.m; ++j)
    p.push_back(opt.schedule == mlae_schedule::exponential ? std::uint64_t{1} << j : j + 1);
  return p;
}

namespace detail {
// log L(theta) for rounds of (power, shots, hits); terms with zero weight are skipped (0 log 0 = 0)
// and probabilities are floored at 1e-300 so a contradicted round costs a large finite penalty.
template <int = 0>
inline double bernoulli_log_likelihood(const std::vector<round_record>& rounds, double theta) {
  double l = 0;
  for (const round_record& rr : rounds) {
    const double K = 2.0 * static_cast<double>(rr.power) + 1.0;
    const double s = std::sin(K * theta), c = std::cos(K * theta);
    const double misses = static_cast<double>(rr.shots) - rr.hits;
    if (rr.hits > 0) l += rr.hits * std::log(std::max(s * s, 1e-300));
    if (misses > 0) l += misses * std::log(std::max(c * c, 1e-300));
  }
  return l;
}
// log L(theta, r) of the damped model p_k = (1 - exp(-r K) cos(2 K theta)) / 2, K = 2k + 1.
// r = 0 is bernoulli_log_likelihood itself.
template <int = 0>
inline double damped_log_likelihood(const std::vector<round_record>& rounds, double theta, double r) {
  if (r == 0) return bernoulli_log_likelihood(rounds, theta);
  double l = 0;
  for (const round_record& rr : rounds) {
    const double K = 2.0 * static_cast<double>(rr.power) + 1.0;
    const double p = 0.5 * (1.0 - std::exp(-r * K) * std::cos(2.0 * K * theta));
    const double misses = static_cast<double>(rr.shots) - rr.hits;
    if (rr.hits > 0) l += rr.hits * std::log(std::max(p, 1e-300));
    if (misses > 0) l += misses * std::log(std::max(1.0 - p, 1e-300));
  }
  return l;
}

// The staged search of the header comment for decay r: the maximiser over theta and its value.
// `sorted` holds the rounds in increasing power.
template <int = 0>
inline std::pair<double, double> mlae_staged_search(const std::vector<round_record>& sorted, double r) {
  using std::numbers::pi;
  std::vector<round_record> used;
  double fisher = 0;  // information about theta; each shot at power k carries 4 (2k+1)^2 e^(-2 r (2k+1))
  double lo = 0.0, hi = pi / 2;
  std::pair<double, double> best{0.0, 0.0};
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double K = 2.0 * static_cast<double>(sorted[i].power) + 1.0;
    fisher += 4.0 * static_cast<double>(sorted[i].shots) * K * K * std::exp(-2.0 * r * K);
    used.push_back(sorted[i]);
    if (i + 1 < sorted.size() && sorted[i + 1].power == sorted[i].power) continue;
    const double sigma_stage = 1.0 / std::sqrt(fisher);
    const double h = std::min(sigma_stage / 4.0, pi / (16.0 * K));
    const double want = std::ceil((hi - lo) / h) + 1.0;
    const auto points = static_cast<std::size_t>(std::clamp(want, 64.0, 400000.0));
    auto loglik = [&](double t) { return damped_log_likelihood(used, t, r); };
    best = grid_maximize(loglik, lo, hi, points);
    lo = std::max(0.0, best.first - 10.0 * sigma_stage);
    hi = std::min(pi / 2, best.first + 10.0 * sigma_stage);
  }
  return best;
}

// Standard deviation of theta from the 2x2 Fisher information of (theta, r) in the damped model,
// or NaN where it is singular.
template <int = 0>
inline double damped_theta_sigma(const std::vector<round_record>& rounds, double theta, double r) {
  double itt = 0, itr = 0, irr = 0;
  for (const round_record& rr : rounds) {
    const double K = 2.0 * static_cast<double>(rr.power) + 1.0;
    const double D = std::exp(-r * K), c = std::cos(2.0 * K * theta), s = std::sin(2.0 * K * theta);
    const double p = 0.5 * (1.0 - D * c);
    const double var = std::max(p * (1.0 - p), 1e-12);
    const double dt = D * K * s, dr = 0.5 * K * D * c;
    const double n = static_cast<double>(rr.shots);
    itt += n * dt * dt / var;
    itr += n * dt * dr / var;
    irr += n * dr * dr / var;
  }
  const double det = itt * irr - itr * itr;
  return det > 0 ? std::sqrt(irr / det) : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace detail

// maximum_likelihood_amplitude_estimation(oracle, options, g): MLAE on any amplitude_oracle.
template <amplitude_oracle O>
estimation_result maximum_likelihood_amplitude_estimation(O& oracle, const mlae_options& opt, rng& g) {
  using std::numbers::pi;
  detail::check_alpha(opt.alpha, "maximum_likelihood_amplitude_estimation");
  detail::check_shots(opt.shots, "maximum_likelihood_amplitude_estimation");
  const std::vector<std::uint64_t> powers = mlae_powers(opt);
  for (std::uint64_t k : powers)
    if (k > (std::uint64_t{1} << 40))
      throw std::invalid_argument("maximum_likelihood_amplitude_estimation: power " + std::to_string(k) +
                                  " is above 2^40");
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "mlae";
  r.exact_probabilities = opt.exact_probabilities;
  detail::shot_sampler s(g, opt.exact_probabilities, r);
  for (std::uint64_t k : powers) s.draw(oracle, k, opt.shots);

  // Search in stages of increasing power: the rounds up to power k pin theta down to a few
  // standard deviations, and the next stage (whose new term oscillates twice as fast for an
  // exponential schedule) searches only that window, on a grid with >= 4 points per standard
  // deviation and >= 16 per period of its fastest term. A single grid over [0, pi/2] would need
  // ~K_max points and miss the true mode by aliasing once K_max is large.
  std::vector<round_record> sorted = r.rounds;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const round_record& x, const round_record& y) { return x.power < y.power; });
  double fisher = 0;
  for (const round_record& rr : sorted) {
    const double K = 2.0 * static_cast<double>(rr.power) + 1.0;
    fisher += 4.0 * static_cast<double>(rr.shots) * K * K;
  }
  const std::pair<double, double> undamped = detail::mlae_staged_search(sorted, 0.0);
  double theta = undamped.first;
  double sigma = 1.0 / std::sqrt(fisher);
  if (opt.noise_aware) {
    r.estimator = "mlae_noise_aware";
    auto profile = [&](double rate) { return detail::mlae_staged_search(sorted, rate); };
    double best_rate = 0;
    std::pair<double, double> best = undamped;
    std::vector<double> grid{0.0};
    for (int j = 0; j <= 40; ++j) grid.push_back(1e-4 * std::pow(10.0, j / 10.0));
    std::size_t best_j = 0;
    for (std::size_t j = 1; j < grid.size(); ++j)
      if (const auto f = profile(grid[j]); f.second > best.second) {
        best = f;
        best_rate = grid[j];
        best_j = j;
      }
    if (best_j > 0) {  // golden section in log r between the grid neighbours
      const double a0 = std::log(grid[best_j > 1 ? best_j - 1 : 1] * (best_j > 1 ? 1.0 : 0.5));
      const double b0 = std::log(grid[std::min(best_j + 1, grid.size() - 1)]);
      const double refined =
          detail::golden_maximize([&](double lr) { return profile(std::exp(lr)).second; }, a0, b0).first;
      if (const auto f = profile(std::exp(refined)); f.second > best.second) {
        best = f;
        best_rate = std::exp(refined);
      }
    }
    theta = best.first;
    r.damping = best_rate;
    const double s_damped = detail::damped_theta_sigma(sorted, theta, best_rate);
    if (std::isfinite(s_damped)) sigma = s_damped;
  }
  const double z = detail::normal_quantile(1.0 - opt.alpha / 2.0);
  r.estimate = r.raw_estimate = std::pow(std::sin(theta), 2);
  r.confidence_interval = detail::amplitude_interval(theta - z * sigma, theta + z * sigma, pi / 2);
  r.standard_error = std::fabs(std::sin(2.0 * theta)) * sigma;  // delta method: da/dtheta = sin 2 theta
  r.confidence = 1.0 - opt.alpha;
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
