// qrm/estimation/result.hpp: what every estimator returns, and the shot sampler they share.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/random.hpp"
#include "oracle.hpp"

namespace qrm {

// One measured batch: `shots` runs of a circuit with Grover power `power`, `hits` of them good.
// (qcoin: power = coin iterations n and `reference` = the coin's reference l; canonical: one
// record with power = M - 1, hits = shots whose phase outcome y is not 0.) In exact-probability
// mode `hits` is shots * p, a fraction.
struct round_record {
  std::uint64_t power = 0;
  std::uint64_t shots = 0;
  double hits = 0;
  double reference = 0;
};

// estimation_result: one estimator run.
struct estimation_result {
  std::string estimator;
  double estimate = 0;      // in [0, 1]
  double raw_estimate = 0;  // the algorithm's own value before projecting onto [0, 1] (FAE with
                            // rescale can exceed 1; canonical: the plain QAE grid estimate)
  std::array<double, 2> confidence_interval{0.0, 1.0};
  double confidence = 0;                 // the interval's nominal coverage, e.g. 0.95
  std::optional<double> standard_error;  // where the method defines one (mc, mlae)
  std::optional<double> damping;         // noise-aware MLAE: the fitted decay per application of A
  std::uint64_t a_calls = 0;             // applications of A (or A^dagger): 2k+1 per shot of Q^k A
  std::uint64_t grover_calls = 0;        // applications of Q: k per shot of Q^k A
  std::uint64_t shots = 0;
  std::vector<round_record> rounds;
  std::uint64_t check_a_calls = 0;  // FAE without rescale: the k = 0 domain check (not in a_calls)
  std::uint64_t check_shots = 0;
  std::vector<double> phase_counts;  // canonical: counts of each phase-register outcome y
  double seconds = 0;
  bool exact_probabilities = false;
  std::string warning;  // non-empty when the result should not be trusted as is
};

namespace detail {

// Probabilities closer than this to 0 or 1 are sampled as exactly 0 or 1. qrm::binomial returns
// without drawing for p in {0, 1}, so without the snap an analytic oracle (p = 0 exactly) and a
// simulated one (p = 1e-17 from rounding) would consume the generator differently and every later
// count would differ. The change in the sampled law is at most shots * 1e-13 in total variation.
inline constexpr double sampling_snap = 1e-13;

// Draws (or, in exact mode, computes) the hits of each round and keeps the books.
class shot_sampler {
 public:
  shot_sampler(rng& g, bool exact, estimation_result& out) : g_(g), exact_(exact), out_(out) {}

  // Hits among `shots` runs of Q^k A.
  template <class O>
  double draw(O& oracle, std::uint64_t k, std::uint64_t shots) {
    const double p = checked_probability(oracle.probability(k), "estimator");
    const double h = hits(p, shots);
    out_.rounds.push_back({k, shots, h, 0.0});
    out_.shots += shots;
    out_.a_calls += (2 * k + 1) * shots;
    out_.grover_calls += k * shots;
    return h;
  }

  // Hits for probability p (no bookkeeping).
  template <int = 0>
  double hits(double p, std::uint64_t shots) {
    if (exact_) return p * static_cast<double>(shots);
    double q = p;
    if (q < sampling_snap) q = 0.0;
    if (q > 1.0 - sampling_snap) q = 1.0;
    return static_cast<double>(binomial(shots, q, g_));
  }

  rng& generator() { return g_; }
  bool exact() const { return exact_; }

 private:
  rng& g_;
  bool exact_;
  estimation_result& out_;
};

// Wall-clock timer for result.seconds.
class stopwatch {
 public:
  stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  std::chrono::steady_clock::time_point t0_;
};

// a = (scale * sin theta)^2 over a theta interval clipped to [0, theta_max], where theta_max is
// the angle with (scale * sin theta_max)^2 = 1 (pi/2 for scale 1, asin(1/4) for scale 4). The map
// is monotone there, and the ends of the domain map to exactly 0 and 1, so a truth of exactly 0 or
// 1 is not excluded by a rounding of sin.
template <int = 0>
inline std::array<double, 2> amplitude_interval(double theta_lo, double theta_hi, double theta_max,
                                                double scale = 1.0) {
  if (theta_lo > theta_hi) std::swap(theta_lo, theta_hi);
  auto map = [&](double t) {
    if (t <= 0.0) return 0.0;
    if (t >= theta_max) return 1.0;
    const double s = scale * std::sin(t);
    return std::clamp(s * s, 0.0, 1.0);
  };
  return {map(theta_lo), map(theta_hi)};
}

// Final checks every estimator runs: nothing non-finite escapes, the interval is ordered and in
// [0, 1], the estimate is projected onto [0, 1].
template <int = 0>
inline void finish(estimation_result& r, const stopwatch& sw) {
  auto bad = [](double x) { return !std::isfinite(x); };
  if (bad(r.estimate) || bad(r.raw_estimate) || bad(r.confidence_interval[0]) || bad(r.confidence_interval[1]) ||
      (r.standard_error && bad(*r.standard_error)))
    throw std::logic_error(r.estimator + ": a non-finite number reached the result (estimate " +
                           std::to_string(r.estimate) + ", interval [" + std::to_string(r.confidence_interval[0]) +
                           ", " + std::to_string(r.confidence_interval[1]) + "]); this is a bug");
  r.estimate = std::clamp(r.estimate, 0.0, 1.0);
  auto& ci = r.confidence_interval;
  ci[0] = std::clamp(ci[0], 0.0, 1.0);
  ci[1] = std::clamp(ci[1], 0.0, 1.0);
  if (ci[0] > ci[1]) std::swap(ci[0], ci[1]);
  r.seconds = sw.seconds();
}

template <int = 0>
inline void check_alpha(double alpha, const char* who) {
  if (!(alpha > 0.0 && alpha < 1.0))
    throw std::invalid_argument(std::string(who) + ": alpha must be in (0, 1), got " + std::to_string(alpha));
}
template <int = 0>
inline void check_shots(std::uint64_t shots, const char* who) {
  if (shots == 0) throw std::invalid_argument(std::string(who) + ": shots must be positive, got 0");
}

}  // namespace detail

// Radiance from an estimate of P(out = 1): value = estimate * S * emission_scale. The Path gate
// divides by the number of path terms S, and emission above 1 is encoded as Le / emission_scale.
struct radiance_estimate {
  double value = 0;
  std::array<double, 2> confidence_interval{0.0, 0.0};
};

// to_radiance(result, S, emission_scale): the estimate and its interval mapped to radiance.
template <int = 0>
inline radiance_estimate to_radiance(const estimation_result& r, double path_terms, double emission_scale = 1.0) {
  if (!(path_terms > 0.0 && std::isfinite(path_terms)))
    throw std::invalid_argument("to_radiance: path_terms S must be positive and finite, got " +
                                std::to_string(path_terms));
  if (!(emission_scale > 0.0 && std::isfinite(emission_scale)))
    throw std::invalid_argument("to_radiance: emission_scale must be positive and finite, got " +
                                std::to_string(emission_scale));
  const double f = path_terms * emission_scale;
  return {r.estimate * f, {r.confidence_interval[0] * f, r.confidence_interval[1] * f}};
}

}  // namespace qrm
