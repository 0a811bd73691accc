// qrm/walk/classical.hpp: classical references for the walk: the exact branching path sum and a
// Monte Carlo random walk, with the transition probabilities |U[r][d]|^2 of the same coins.
//
// A path x = (state_1, ..., state_s) has probability prod |coin amplitude|^2 (times 1/D for a
// start in air) and contribution f(x) = sum_i Le(p_i) prod_{k<i} rho(p_k), p_i the voxel after
// step i (Eq. 14). The path sum is E[f] = sum_x P(x) f(x), computed here by a forward pass
// over walker states (exact: it regroups the same sum), and also by explicit enumeration of
// every path (exponential in s; a cross-check for small s).
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <vector>

#include "../support/random.hpp"
#include "model.hpp"

namespace qrm {

// path_sum(model, start, steps, channel): E[f], exactly.
template <int = 0>
double path_sum(const walk_model& m, const walk_start& start, unsigned steps, int channel) {
  std::map<walk_state, double> weight;  // probability times prod of rho sampled so far
  for (const auto& [w, a] : m.initial_states(start)) weight[w] += std::norm(a);
  double expected = 0;
  for (unsigned i = 0; i < steps; ++i) {
    std::map<walk_state, double> next;
    for (const auto& [w, p] : weight) {
      const std::size_t v = m.voxel_of(w.pos);
      for (const auto& [d, amp] : m.scatter(v, w.dir)) next[{m.moved(w.pos, d), d}] += p * std::norm(amp);
    }
    for (auto& [w, p] : next) {
      const std::size_t v = m.voxel_of(w.pos);
      expected += p * m.emission(v, channel);
      p *= m.reflectance(v, channel);
    }
    weight = std::move(next);
  }
  return expected;
}

// path_sum_enumerated(...): the same sum, one path at a time (D * branching^s paths).
template <int = 0>
double path_sum_enumerated(const walk_model& m, const walk_start& start, unsigned steps, int channel) {
  double total = 0;
  auto walk = [&](auto&& self, const walk_state& w, unsigned i, double prob, double prefix, double f) -> void {
    if (i == steps) {
      total += prob * f;
      return;
    }
    for (const auto& [d, amp] : m.scatter(m.voxel_of(w.pos), w.dir)) {
      const walk_state n{m.moved(w.pos, d), d};
      const std::size_t v = m.voxel_of(n.pos);
      self(self, n, i + 1, prob * std::norm(amp), prefix * m.reflectance(v, channel), f + prefix * m.emission(v, channel));
    }
  };
  for (const auto& [w, a] : m.initial_states(start)) walk(walk, w, 0, std::norm(a), 1.0, 0.0);
  return total;
}

struct monte_carlo_estimate {
  double mean = 0;
  double standard_error = 0;
  std::uint64_t paths = 0;
};

// monte_carlo(model, start, steps, channel, paths, g): the random walk with the same
// transition probabilities; mean of f over `paths` samples and its standard error.
template <int = 0>
monte_carlo_estimate monte_carlo(const walk_model& m, const walk_start& start, unsigned steps, int channel,
                                        std::uint64_t paths, rng& g) {
  if (paths == 0) throw std::invalid_argument("monte_carlo: paths must be positive");
  const auto init = m.initial_states(start);
  auto pick = [&g](const auto& options) {
    double u = g.uniform(), acc = 0;
    for (std::size_t k = 0; k < options.size(); ++k) {
      acc += std::norm(options[k].second);
      if (u < acc) return k;
    }
    return options.size() - 1;  // rounding: the sum of |amp|^2 is 1 to ~1e-16
  };
  double sum = 0, sum2 = 0;
  for (std::uint64_t n = 0; n < paths; ++n) {
    walk_state w = init[pick(init)].first;
    double prefix = 1, f = 0;
    for (unsigned i = 0; i < steps; ++i) {
      const auto options = m.scatter(m.voxel_of(w.pos), w.dir);
      const std::uint32_t d = options[pick(options)].first;
      w = {m.moved(w.pos, d), d};
      const std::size_t v = m.voxel_of(w.pos);
      f += prefix * m.emission(v, channel);
      prefix *= m.reflectance(v, channel);
    }
    sum += f;
    sum2 += f * f;
  }
  monte_carlo_estimate r;
  r.paths = paths;
  r.mean = sum / static_cast<double>(paths);
  const double var = paths > 1 ? std::max(0.0, (sum2 - sum * r.mean) / static_cast<double>(paths - 1)) : 0.0;
  r.standard_error = std::sqrt(var / static_cast<double>(paths));
  return r;
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_CLASSICAL_INSTANCES(PREFIX)                                                                          \
  PREFIX double path_sum<0>(const walk_model&, const walk_start&, unsigned, int);                                       \
  PREFIX double path_sum_enumerated<0>(const walk_model&, const walk_start&, unsigned, int);                            \
  PREFIX monte_carlo_estimate monte_carlo<0>(const walk_model&, const walk_start&, unsigned, int, std::uint64_t, rng&);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_CLASSICAL_INSTANCES(extern template)
}  // namespace qrm
#endif
