// qrm/estimation/chebae.hpp: Chebyshev amplitude estimation, ChebAE (Rall and Fuller 2023,
// "Amplitude Estimation from Quantum Signal Processing", arXiv:2207.08628).
//
// With A|0> = x|good> + ..., x = sqrt(a) = sin theta, k Grover iterations give
// P_k = sin^2((2k+1) theta) = T_d(x)^2, the square of the Chebyshev polynomial of odd degree
// d = 2k + 1. ChebAE keeps an interval [x_lo, x_hi] for x. Each step it looks for the largest odd
// degree d >= ratio * (current degree) for which T_d(x)^2 is monotone on the whole interval
// (no extremum inside: floor(2 d acos(x_hi) / pi) = floor(2 d acos(x_lo) / pi)); a new degree
// starts a new tally. The Clopper-Pearson interval for P_k is mapped back through the monotone
// branch of T_d^2 that holds the interval's midpoint and intersected with [x_lo, x_hi]. It stops
// when the interval for a = x^2 has half-width at most epsilon.
//
// The guarantee, and where this differs from the reference code (qiskit-community/ChebAE): a
// tally is tested again after every batch, so the failure probability must cover every test.
// The reference tests at one level alpha / T throughout and, near the end ("late"), after every
// single shot; we measured that to miss more often than promised (6.6% of 4000 runs at a = 0.5
// for alpha = 5%, epsilon = 0.005). Here the j-th test of a degree's tally (j = 0, 1, ...) comes
// after shots * 2^j runs (each batch doubles the tally) at level alpha / (T 2^(j+1)), so the
// levels of one degree sum to at most alpha / T, and of all degrees to alpha: the interval
// covers with probability at least 1 - alpha (test_estimation_stats measures it).
// T bounds the number of degrees used: a degree d is only chosen while the theta-interval is at
// most pi / (2 d) wide, and until the stop the a-interval is wider than 2 epsilon, so the
// x-interval is wider than epsilon and d < pi / (2 epsilon); degrees grow by the ratio, so
// T = 1 + ceil(log(pi / (2 epsilon)) / log ratio).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "../support/random.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

struct chebae_options {
  double epsilon = 0.01;     // target half-width of the interval for a, in (0, 0.5]
  double alpha = 0.05;       // the interval fails with probability at most alpha
  std::uint64_t shots = 100; // runs of a degree's first batch (later batches double its tally)
  double ratio = 2;          // each new degree is at least this times the last (the paper's r)
  bool exact_probabilities = false;
  std::uint64_t max_batches = 10000000;  // safety stop (never reached for sane inputs)
};

namespace detail {

// The largest odd d >= min_degree with T_d^2 monotone on [x_lo, x_hi], if any.
template <int = 0>
inline std::optional<std::uint64_t> chebae_next_degree(double x_lo, double x_hi, double min_degree) {
  using std::numbers::pi;
  const double t_lo = std::acos(std::clamp(x_hi, 0.0, 1.0)), t_hi = std::acos(std::clamp(x_lo, 0.0, 1.0));
  if (!(t_hi > t_lo)) return std::nullopt;
  const double most = std::min(std::floor((pi / 2) / (t_hi - t_lo)), 9.0e15);
  auto d = static_cast<std::uint64_t>(most);
  if (d % 2 == 0) ++d;
  for (; static_cast<double>(d) >= min_degree && d >= 1; d -= 2) {
    if (std::floor(2 * static_cast<double>(d) * t_lo / pi) == std::floor(2 * static_cast<double>(d) * t_hi / pi))
      return d;
    if (d < 2) break;
  }
  return std::nullopt;
}

// The x on the monotone branch of T_d^2 that holds x_mid with T_d(x)^2 = p.
template <int = 0>
inline double chebae_invert(double x_mid, std::uint64_t d, double p) {
  using std::numbers::pi;
  const double dd = static_cast<double>(d);
  const double c = pi / (2 * dd);  // branches of cos^2(d theta) are [t c, (t + 1) c]
  const double t = std::floor(std::acos(std::clamp(x_mid, 0.0, 1.0)) / c);
  const double root = std::acos(std::clamp(2 * p - 1, -1.0, 1.0)) / (2 * dd);  // in [0, c]
  const double within = std::fmod(t, 2.0) == 0 ? root : 2 * c - root;         // decreasing, then increasing
  return std::cos(within + pi * std::floor(t / 2) / dd);
}

}  // namespace detail

// chebyshev_amplitude_estimation(oracle, options, g): ChebAE on any amplitude_oracle.
template <amplitude_oracle O>
estimation_result chebyshev_amplitude_estimation(O& oracle, const chebae_options& opt, rng& g) {
  using std::numbers::pi;
  if (!(opt.epsilon > 0.0 && opt.epsilon <= 0.5))
    throw std::invalid_argument("chebyshev_amplitude_estimation: epsilon must be in (0, 0.5], got " +
                                std::to_string(opt.epsilon));
  detail::check_alpha(opt.alpha, "chebyshev_amplitude_estimation");
  detail::check_shots(opt.shots, "chebyshev_amplitude_estimation");
  if (!(opt.ratio > 1.0))
    throw std::invalid_argument("chebyshev_amplitude_estimation: ratio must be above 1, got " + std::to_string(opt.ratio));
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "chebae";
  r.exact_probabilities = opt.exact_probabilities;
  detail::shot_sampler s(g, opt.exact_probabilities, r);

  const double degrees = 1 + std::ceil(std::log(pi / (2 * opt.epsilon)) / std::log(opt.ratio));
  double x_lo = 0, x_hi = 1, hits = 0, runs = 0;
  std::uint64_t degree = 1, batches = 0;
  int test = 0;  // tests of this degree's tally so far
  while (x_hi * x_hi - x_lo * x_lo > 2 * opt.epsilon) {
    if (++batches > opt.max_batches || test > 60) {
      r.warning = "chebae stopped before reaching epsilon (batch limit)";
      break;
    }
    if (const auto next = detail::chebae_next_degree(x_lo, x_hi, opt.ratio * static_cast<double>(degree))) {
      degree = *next;
      hits = runs = 0;
      test = 0;
    }
    const auto n = runs == 0 ? opt.shots : static_cast<std::uint64_t>(runs);
    hits += s.draw(oracle, (degree - 1) / 2, n);
    runs += static_cast<double>(n);
    const double level = opt.alpha / (degrees * std::ldexp(1.0, test + 1));
    ++test;
    const auto [p_lo, p_hi] = detail::clopper_pearson(hits, runs, level);
    const double mid = 0.5 * (x_lo + x_hi);
    double a = detail::chebae_invert(mid, degree, p_lo), b = detail::chebae_invert(mid, degree, p_hi);
    if (a > b) std::swap(a, b);
    // 1e-15: the inversion's rounding must not exclude the truth at an end of the interval.
    x_lo = std::max(x_lo, a - 1e-15);
    x_hi = std::min(x_hi, b + 1e-15);
    if (x_hi < x_lo) x_hi = x_lo;
  }
  x_lo = std::clamp(x_lo, 0.0, 1.0);
  x_hi = std::clamp(x_hi, x_lo, 1.0);
  r.confidence_interval = {x_lo * x_lo, x_hi * x_hi};
  r.estimate = r.raw_estimate = 0.5 * (r.confidence_interval[0] + r.confidence_interval[1]);
  r.confidence = 1.0 - opt.alpha;
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
