// qrm/estimation/detail/stats.hpp: the few special functions the estimators need (log-gamma,
// the regularised incomplete beta function and its inverse, normal quantiles), written out here
// because std::lgamma writes a global (signgam) and results must not depend on the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace qrm::detail {

// log Gamma(x) for x > 0: shift up to x >= 15 by the recurrence, then Stirling's series (the first
// omitted term is below 1/(1188 x^9) < 2e-14 there).
template <int = 0>
inline double log_gamma(double x) {
  if (!(x > 0) || !std::isfinite(x))
    throw std::domain_error("log_gamma: argument must be positive and finite, got " + std::to_string(x));
  double shift = 0;
  while (x < 15) {
    shift += std::log(x);
    x += 1;
  }
  const double ix = 1.0 / x, ix2 = ix * ix;
  const double series = ix * (1.0 / 12 - ix2 * (1.0 / 360 - ix2 * (1.0 / 1260 - ix2 / 1680)));
  return (x - 0.5) * std::log(x) - x + 0.5 * std::log(2 * std::numbers::pi) + series - shift;
}

// Continued fraction of the incomplete beta function (modified Lentz), valid for x < (a+1)/(a+b+2).
template <int = 0>
inline double incomplete_beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300, eps = 1e-16;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double f = d;
  for (int m = 1; m <= 100000; ++m) {
    const double md = m;
    // even step
    double num = md * (b - md) * x / ((a + 2 * md - 1) * (a + 2 * md));
    d = 1.0 + num * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + num / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    f *= d * c;
    // odd step
    num = -(a + md) * (a + b + md) * x / ((a + 2 * md) * (a + 2 * md + 1));
    d = 1.0 + num * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + num / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double step = d * c;
    f *= step;
    if (std::fabs(step - 1.0) < eps) break;
  }
  return f;
}

// I_x(a, b), the regularised incomplete beta function (the CDF of Beta(a, b) at x), a, b > 0.
template <int = 0>
inline double incomplete_beta(double a, double b, double x) {
  if (!(a > 0) || !(b > 0)) throw std::domain_error("incomplete_beta: a and b must be positive");
  if (x <= 0) return 0.0;
  if (x >= 1) return 1.0;
  const double log_front = log_gamma(a + b) - log_gamma(a) - log_gamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1) / (a + b + 2)) return std::exp(log_front) * incomplete_beta_fraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * incomplete_beta_fraction(b, a, 1.0 - x) / b;
}

// The q-quantile of Beta(a, b): bisection on I_x, to full double precision (I_x is monotone).
template <int = 0>
inline double beta_quantile(double q, double a, double b) {
  if (!(q >= 0 && q <= 1)) throw std::domain_error("beta_quantile: q must be in [0, 1], got " + std::to_string(q));
  if (q == 0) return 0.0;
  if (q == 1) return 1.0;
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 2000; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (incomplete_beta(a, b, mid) < q)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Standard normal CDF.
template <int = 0>
inline double normal_cdf(double x) {
  return 0.5 * std::erfc(-x / std::numbers::sqrt2);
}

// The p-quantile of the standard normal: safeguarded Newton on the CDF, bracketed in [-40, 40].
template <int = 0>
inline double normal_quantile(double p) {
  if (!(p > 0 && p < 1)) throw std::domain_error("normal_quantile: p must be in (0, 1), got " + std::to_string(p));
  double lo = -40, hi = 40;
  double x = 0;
  for (int i = 0; i < 200; ++i) {
    const double f = normal_cdf(x) - p;
    if (f < 0)
      lo = x;
    else
      hi = x;
    const double pdf = std::exp(-0.5 * x * x) / std::sqrt(2 * std::numbers::pi);
    double next = pdf > 0 ? x - f / pdf : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - x) <= 1e-15 * (1 + std::fabs(x))) return next;
    x = next;
  }
  return x;
}

// Clopper-Pearson interval for `hits` successes in `shots` trials at level 1 - alpha. `hits` may be
// fractional (exact-probability mode uses shots * p); the beta quantiles are defined for real
// parameters, and the ends are exactly 0 and 1 at hits = 0 and hits = shots.
template <int = 0>
inline std::pair<double, double> clopper_pearson(double hits, double shots, double alpha) {
  if (!(shots > 0)) throw std::invalid_argument("clopper_pearson: shots must be positive");
  hits = std::clamp(hits, 0.0, shots);
  const double lo = hits > 0 ? beta_quantile(alpha / 2, hits, shots - hits + 1) : 0.0;
  const double hi = hits < shots ? beta_quantile(1 - alpha / 2, hits + 1, shots - hits) : 1.0;
  return {lo, hi};
}

// Wilson score interval for hits/shots at level 1 - alpha (ends exact at hits = 0 and = shots).
template <int = 0>
inline std::pair<double, double> wilson(double hits, double shots, double alpha) {
  if (!(shots > 0)) throw std::invalid_argument("wilson: shots must be positive");
  hits = std::clamp(hits, 0.0, shots);
  const double z = normal_quantile(1 - alpha / 2), z2 = z * z;
  const double p = hits / shots;
  const double denom = 1 + z2 / shots;
  const double centre = (p + z2 / (2 * shots)) / denom;
  const double half = z / denom * std::sqrt(std::max(0.0, p * (1 - p) / shots + z2 / (4 * shots * shots)));
  double lo = std::max(0.0, centre - half), hi = std::min(1.0, centre + half);
  if (hits <= 0) lo = 0.0;
  if (hits >= shots) hi = 1.0;
  return {lo, hi};
}

}  // namespace qrm::detail
