// qrm/estimation/fae.hpp: Faster Amplitude Estimation (Nakaji 2020), the variant the paper uses,
// exactly as the widely used implementation (qiskit-algorithms) runs it, so that an
// exact-probability run is reproducible digit for digit (tests/reference/fae_from_spec.py ports these rules independently):
//   shots N1 = floor(1944 ln(2/delta)), N2 = floor(972 ln(2/delta)); K_j = 2^(j+1) + 2;
//   c(k) = 1 - 2 p^(k) estimates cos(2(2k+1) theta); Chernoff interval c +- sqrt(12 ln(2/delta)/N)
//   clipped to [-1, 1]; theta interval starts at [0, asin(1/4)].
//   Stage 1 (round j, power 2^(j-1), N1 shots): theta interval = [acos(c_hi), acos(c_lo)] / K_j;
//     if 2^(j+1) theta_hi >= 3 pi/8 and j < maxiter: j0 = j, v = 2^j (theta_lo + theta_hi), stage 2.
//   Stage 2 (round j, N2 shots at powers k1 = 2^(j-1) and k2 = 2^(j-1) + 2^(j0-1)):
//     s = (c1 cos v - c2) / sin v, rho = atan2(s, c1), n = trunc((K_j theta_hi - rho + pi/3) / 2 pi),
//     theta interval = [2 pi n + rho - pi/3, 2 pi n + rho + pi/3] / K_j.
//   Estimate = sin^2(mid theta), times 16 with rescale ((4 sin theta)^2).
//
// Our additions, none of which changes the numbers above:
// - rescale is real: the oracle's A gets an ancilla rotated by Ry(2 asin(1/4)) (a -> a/16).
// - The interval is derived from the final theta interval honestly: theta is first clipped to its
//   domain ([0, asin(1/4)] with rescale, [0, pi/2] without; the reference maps the raw ends, which
//   can exclude a = 0 when theta_lo < 0), then mapped through the monotone (scale sin theta)^2.
//   Its nominal coverage is 1 - (2 maxiter - j0) delta (a union bound over the Chernoff intervals).
// - The estimate is projected onto [0, 1]; raw_estimate keeps the reference value.
// - Without rescale the method silently returns the wrong branch for a > 1/4 (K_1 theta > pi).
//   We refuse instead: a k = 0 check of N1 shots runs first; if its Clopper-Pearson interval
//   (level delta) lies above 1/4 the call throws std::domain_error, if it straddles 1/4 the result
//   carries a warning. In exact-probability mode the check reads p_0 exactly and refuses p_0 > 1/4.
//   The check's cost is reported in check_a_calls / check_shots, not in a_calls, so a_calls stays
//   the algorithm's own count.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>

#include "../support/random.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

// With rescale, A's amplitude is multiplied by this (a -> a / 16) through an ancilla rotated by
// Ry(2 asin(1/4)) (rescaled_problem).
inline constexpr double fae_rescale_scale = 0.25;

// fae_above_quarter: FAE without rescale met P(good) above 1/4 (a std::domain_error whose what()
// says so); low and high bound P(good): its k = 0 check of `shots` shots, or low = high = P(good)
// with exact probabilities (shots = 0). Callers that report in their own terms catch this type.
struct fae_above_quarter : std::domain_error {
  double low, high;
  std::uint64_t shots;
  fae_above_quarter(const std::string& what, double lo, double hi, std::uint64_t n)
      : std::domain_error(what), low(lo), high(hi), shots(n) {}
};

struct fae_options {
  double delta = 0.01;   // failure probability of each Chernoff interval
  unsigned maxiter = 5;  // rounds l; the largest Grover power is 2^(l-1)
  bool rescale = true;
  bool exact_probabilities = false;
};

namespace detail {
template <class O>
void fae_rounds(O& oracle, const fae_options& opt, shot_sampler& s, double& theta_lo, double& theta_hi, unsigned& j0) {
  using std::numbers::pi;
  const double log_term = std::log(2.0 / opt.delta);
  const auto n1 = static_cast<std::uint64_t>(std::floor(1944.0 * log_term));
  const auto n2 = static_cast<std::uint64_t>(std::floor(972.0 * log_term));
  auto cos_estimate = [&](std::uint64_t k, std::uint64_t shots) {
    return 1.0 - 2.0 * s.draw(oracle, k, shots) / static_cast<double>(shots);
  };
  theta_lo = 0.0;
  theta_hi = std::asin(fae_rescale_scale);
  bool first_stage = true;
  j0 = opt.maxiter;
  double v = 0;
  for (unsigned j = 1; j <= opt.maxiter; ++j) {
    const double two_j = std::ldexp(1.0, static_cast<int>(j));  // 2^j
    const double K = 2.0 * two_j + 2.0;
    const std::uint64_t power = std::uint64_t{1} << (j - 1);
    if (first_stage) {
      const double c = cos_estimate(power, n1);
      const double w = std::sqrt(12.0 * log_term / static_cast<double>(n1));
      const double c_lo = std::max(-1.0, c - w), c_hi = std::min(1.0, c + w);
      theta_lo = std::acos(c_hi) / K;
      theta_hi = std::acos(c_lo) / K;
      if (2.0 * two_j * theta_hi >= 3.0 * pi / 8.0 && j < opt.maxiter) {
        j0 = j;
        v = two_j * (theta_lo + theta_hi);
        first_stage = false;
      }
    } else {
      const double c1 = cos_estimate(power, n2);
      const double c2 = cos_estimate(power + (std::uint64_t{1} << (j0 - 1)), n2);
      // v lies in (0, pi) (v <= 2^(j+1) pi / K_j), so sin v > 0; the guard only keeps a
      // degenerate v from dividing by zero.
      double sv = std::sin(v);
      if (std::fabs(sv) < 1e-300) sv = 1e-300;
      const double sn = (c1 * std::cos(v) - c2) / sv;
      const double rho = std::atan2(sn, c1);
      const double n = std::trunc((K * theta_hi - rho + pi / 3.0) / (2.0 * pi));
      theta_lo = (2.0 * pi * n + rho - pi / 3.0) / K;
      theta_hi = (2.0 * pi * n + rho + pi / 3.0) / K;
    }
  }
}
}  // namespace detail

// faster_amplitude_estimation(oracle, options, g): FAE on any amplitude_oracle.
template <amplitude_oracle O>
estimation_result faster_amplitude_estimation(O& oracle, const fae_options& opt, rng& g) {
  if (!(opt.delta > 0.0 && opt.delta < 1.0))
    throw std::invalid_argument("faster_amplitude_estimation: delta must be in (0, 1), got " +
                                std::to_string(opt.delta));
  if (opt.maxiter < 1 || opt.maxiter > 40)
    throw std::invalid_argument("faster_amplitude_estimation: maxiter must be in [1, 40], got " +
                                std::to_string(opt.maxiter));
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "fae";
  r.exact_probabilities = opt.exact_probabilities;
  detail::shot_sampler s(g, opt.exact_probabilities, r);

  if (!opt.rescale) {
    const auto n1 = static_cast<std::uint64_t>(std::floor(1944.0 * std::log(2.0 / opt.delta)));
    const double p0 = detail::checked_probability(oracle.probability(0), "faster_amplitude_estimation");
    r.check_shots = n1;
    r.check_a_calls = n1;
    if (opt.exact_probabilities) {
      if (p0 > 0.25)
        throw fae_above_quarter(
            "faster_amplitude_estimation: without rescale the amplitude must be at most 1/4, but P(good) = " +
                std::to_string(p0) + "; enable rescale",
            p0, p0, 0);
    } else {
      const double h = s.hits(p0, n1);
      const auto [lo, hi] = detail::clopper_pearson(h, static_cast<double>(n1), opt.delta);
      if (lo > 0.25)
        throw fae_above_quarter(
            "faster_amplitude_estimation: without rescale the amplitude must be at most 1/4, but a k = 0 check of " +
                std::to_string(n1) + " shots puts P(good) in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                "]; enable rescale",
            lo, hi, n1);
      if (hi > 0.25)
        r.warning =
            "fae without rescale: the k = 0 check puts P(good) in [" + std::to_string(lo) + ", " + std::to_string(hi) +
            "], which reaches above 1/4 where the first round cannot tell theta from pi/3 - theta; the estimate may be "
            "on the wrong branch (enable rescale)";
    }
  }

  double theta_lo = 0, theta_hi = 0;
  unsigned j0 = opt.maxiter;
  if (opt.rescale) {
    O scaled = oracle.rescaled(fae_rescale_scale);
    detail::fae_rounds(scaled, opt, s, theta_lo, theta_hi, j0);
  } else {
    detail::fae_rounds(oracle, opt, s, theta_lo, theta_hi, j0);
  }
  const double scale = opt.rescale ? 1.0 / fae_rescale_scale : 1.0;
  const double theta = 0.5 * (theta_lo + theta_hi);
  r.raw_estimate = std::pow(scale * std::sin(theta), 2);
  r.estimate = r.raw_estimate;
  const double theta_max = opt.rescale ? std::asin(fae_rescale_scale) : std::numbers::pi / 2;
  r.confidence_interval = detail::amplitude_interval(theta_lo, theta_hi, theta_max, scale);
  r.confidence = std::max(0.0, 1.0 - (2.0 * opt.maxiter - j0) * opt.delta);
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
