// qrm/estimation/monte_carlo.hpp: classical Monte Carlo on the same oracle, the baseline: N shots
// of A alone (k = 0); estimate hits / N, standard error sqrt(p (1 - p) / N), and the Wilson score
// interval (unlike the normal interval it keeps a sensible width at 0 or N hits).
#pragma once

#include <cmath>
#include <cstdint>

#include "../support/random.hpp"
#include "detail/stats.hpp"
#include "oracle.hpp"
#include "result.hpp"

namespace qrm {

struct monte_carlo_options {
  std::uint64_t shots = 1000;
  double alpha = 0.05;
  bool exact_probabilities = false;
};

// monte_carlo_estimation(oracle, options, g): the classical estimate of a.
template <amplitude_oracle O>
estimation_result monte_carlo_estimation(O& oracle, const monte_carlo_options& opt, rng& g) {
  detail::check_alpha(opt.alpha, "monte_carlo_estimation");
  detail::check_shots(opt.shots, "monte_carlo_estimation");
  const detail::stopwatch sw;
  estimation_result r;
  r.estimator = "mc";
  r.exact_probabilities = opt.exact_probabilities;
  detail::shot_sampler s(g, opt.exact_probabilities, r);
  const double n = static_cast<double>(opt.shots);
  const double h = s.draw(oracle, 0, opt.shots);
  const double p = h / n;
  r.estimate = r.raw_estimate = p;
  r.standard_error = std::sqrt(std::max(0.0, p * (1.0 - p)) / n);
  const auto [lo, hi] = detail::wilson(h, n, opt.alpha);
  r.confidence_interval = {lo, hi};
  r.confidence = 1.0 - opt.alpha;
  detail::finish(r, sw);
  return r;
}

}  // namespace qrm
