// qrm/estimation/detail/maximize.hpp: robust 1-D maximisation of a multimodal log-likelihood on
// an interval (a grid fine enough to separate the modes, then golden-section refinement of the
// best few grid maxima), and the likelihood-ratio interval around the maximum.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace qrm::detail {

// Golden-section search for a maximum of f on [lo, hi] (f unimodal there).
template <class F>
std::pair<double, double> golden_maximize(F&& f, double lo, double hi) {
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = lo, b = hi;
  double x1 = b - r * (b - a), x2 = a + r * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 200 && b - a > 1e-15 * (1.0 + std::fabs(a)); ++i) {
    if (f1 < f2) {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + r * (b - a);
      f2 = f(x2);
    } else {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - r * (b - a);
      f1 = f(x1);
    }
  }
  const double x = 0.5 * (a + b);
  return {x, f(x)};
}

// Maximum of f on [lo, hi]: evaluate `points` equally spaced grid points (ends included), take the
// grid's local maxima, refine the best `candidates` of them by golden section inside their two
// neighbouring cells, and return the best (argument, value). The ends themselves stay candidates.
template <class F>
std::pair<double, double> grid_maximize(F&& f, double lo, double hi, std::size_t points, std::size_t candidates = 8) {
  points = std::max<std::size_t>(points, 3);
  const double h = (hi - lo) / static_cast<double>(points - 1);
  std::vector<double> v(points);
  for (std::size_t i = 0; i < points; ++i) v[i] = f(i + 1 == points ? hi : lo + h * static_cast<double>(i));
  std::vector<std::size_t> peaks;
  for (std::size_t i = 0; i < points; ++i) {
    const bool left_ok = i == 0 || v[i] >= v[i - 1];
    const bool right_ok = i + 1 == points || v[i] >= v[i + 1];
    if (left_ok && right_ok) peaks.push_back(i);
  }
  std::sort(peaks.begin(), peaks.end(), [&](std::size_t x, std::size_t y) { return v[x] > v[y]; });
  if (peaks.size() > candidates) peaks.resize(candidates);
  std::pair<double, double> best{lo, v[0]};
  for (std::size_t i = 0; i < points; ++i)
    if (v[i] > best.second) best = {i + 1 == points ? hi : lo + h * static_cast<double>(i), v[i]};
  for (std::size_t i : peaks) {
    const double a = i == 0 ? lo : lo + h * static_cast<double>(i - 1);
    const double b = i + 1 >= points ? hi : std::min(hi, lo + h * static_cast<double>(i + 1));
    const auto cand = golden_maximize(f, a, b);
    if (cand.second > best.second) best = cand;
  }
  return best;
}

// The hull of the superlevel set {x in [lo, hi] : f(x) >= level}, which contains x_best: found on
// `points` equally spaced grid points (a multimodal likelihood can have several components, and
// all of them belong in a likelihood-ratio interval), each end then refined by bisection between
// the last grid point inside and the first outside.
template <class F>
std::pair<double, double> superlevel_hull(F&& f, double x_best, double level, double lo, double hi,
                                          std::size_t points) {
  points = std::max<std::size_t>(points, 3);
  const double h = (hi - lo) / static_cast<double>(points - 1);
  auto at = [&](std::size_t i) { return i + 1 == points ? hi : lo + h * static_cast<double>(i); };
  // Innermost known points of the set: x_best and the outermost grid points inside.
  double in_lo = x_best, in_hi = x_best;
  for (std::size_t i = 0; i < points; ++i) {
    if (f(at(i)) < level) continue;
    in_lo = std::min(in_lo, at(i));
    in_hi = std::max(in_hi, at(i));
  }
  // Every grid point beyond in_lo / in_hi is outside; bisect towards the nearest one.
  auto bisect = [&](double in, double out) {
    for (int i = 0; i < 200 && std::fabs(out - in) > 1e-16; ++i) {
      const double mid = 0.5 * (in + out);
      if (f(mid) >= level)
        in = mid;
      else
        out = mid;
    }
    return out;  // the outer end: the hull errs on the wide side, by one bisection step at most
  };
  double first = lo, last = hi;
  if (in_lo > lo) {
    const double k = std::ceil((in_lo - lo) / h - 1e-9) - 1.0;  // the grid point strictly below
    first = bisect(in_lo, std::max(lo, lo + h * std::max(0.0, k)));
  }
  if (in_hi < hi) {
    const double k = std::floor((in_hi - lo) / h + 1e-9) + 1.0;  // the grid point strictly above
    last = bisect(in_hi, std::min(hi, lo + h * k));
  }
  return {first, last};
}

}  // namespace qrm::detail
