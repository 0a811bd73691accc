// qrm/backends/measure.hpp: reading a backend through a layout (probabilities, distributions, samples).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "../circuit/layout.hpp"
#include "backend.hpp"
#include "../support/detail/formatted_error.hpp"
#include "../support/detail/meta.hpp"
#include "../support/random.hpp"

namespace qrm {

// probability<L, C>(state): probability that control C (when<S, V>, on<S>, off<S>) holds.
template <static_layout L, control_spec C, state_reader B>
double probability(const B& state) {
  static constexpr auto cs = detail::resolve_controls<L, C>();
  return state.probability(std::span<const control>(cs));
}

// distribution<L, S>(state): probabilities of each value of the qubits S (2^|S| numbers).
template <static_layout L, selector S, state_reader B>
std::vector<double> distribution(const B& state) {
  static constexpr auto qs = resolve<L, S>();
  return state.distribution(std::span<const qubit_index>(qs));
}

// sample_counts(p, shots, g): multinomial counts for `shots` draws from probabilities p (which
// must sum to 1 within 1e-9), drawn as a chain of binomials so the cost is O(|p|) not O(shots).
template <int D = 0>
inline std::vector<std::uint64_t> sample_counts(std::span<const double> p, std::uint64_t shots, rng& g) {
  double total = 0;
  for (double x : p) {
    if (!(x >= 0.0)) detail::throw_formatted<std::invalid_argument>("sample_counts: probability %f is negative or NaN", x);
    total += x;
  }
  if (!(std::abs(total - 1.0) <= 1e-9))
    detail::throw_formatted<std::invalid_argument>("sample_counts: probabilities sum to %f, not 1", total);
  detail::deferred<std::vector<std::uint64_t>, D> counts(p.size(), 0);
  std::uint64_t left = shots;
  double mass = total;
  for (std::size_t v = 0; v < p.size() && left > 0; ++v) {
    if (v + 1 == p.size() || mass <= 0) {
      counts[v] = left;
      break;
    }
    const double q = std::min(1.0, std::max(0.0, p[v] / mass));
    counts[v] = binomial(left, q, g);
    left -= counts[v];
    mass -= p[v];
  }
  return counts;
}

// sample_counts<L, S>(state, shots, g): measurement counts of register S.
template <static_layout L, selector S, state_reader B>
std::vector<std::uint64_t> sample_counts(const B& state, std::uint64_t shots, rng& g) {
  const auto p = distribution<L, S>(state);
  std::vector<double> normalised(p);
  double total = 0;
  for (double x : p) total += x;
  for (double& x : normalised) x /= total;
  return sample_counts(normalised, shots, g);
}

}  // namespace qrm
