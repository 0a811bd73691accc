// qrm/estimation/estimator.hpp: choosing an estimator at run time (a name and its settings),
// for the renderer and the command-line tool.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "canonical.hpp"
#include "chebae.hpp"
#include "fae.hpp"
#include "iqae.hpp"
#include "mlae.hpp"
#include "monte_carlo.hpp"
#include "qcoin.hpp"

namespace qrm {

enum class estimator_kind : unsigned char { fae, iqae, mlae, canonical, qcoin, mc, chebae };

inline constexpr estimator_kind all_estimators[] = {estimator_kind::fae,       estimator_kind::iqae,
                                                    estimator_kind::mlae,      estimator_kind::canonical,
                                                    estimator_kind::qcoin,     estimator_kind::mc,
                                                    estimator_kind::chebae};

constexpr std::string_view estimator_name(estimator_kind k) {
  switch (k) {
    case estimator_kind::fae: return "fae";
    case estimator_kind::iqae: return "iqae";
    case estimator_kind::mlae: return "mlae";
    case estimator_kind::canonical: return "canonical";
    case estimator_kind::qcoin: return "qcoin";
    case estimator_kind::mc: return "mc";
    case estimator_kind::chebae: return "chebae";
  }
  return "?";
}

// estimator_from_name("fae"): the kind, or std::invalid_argument listing the names.
template <int = 0>
inline estimator_kind estimator_from_name(std::string_view name) {
  for (estimator_kind k : all_estimators)
    if (estimator_name(k) == name) return k;
  throw std::invalid_argument("unknown estimator '" + std::string(name) +
                              "' (fae, iqae, mlae, canonical, qcoin, mc or chebae)");
}

// estimator_settings: which estimator, each one's options, and exact-probability mode for all.
struct estimator_settings {
  estimator_kind kind = estimator_kind::fae;
  fae_options fae;  // defaults: the paper's maxiter 5 with rescaling
  iqae_options iqae;
  mlae_options mlae;
  canonical_options canonical;
  qcoin_options qcoin;
  monte_carlo_options mc;
  chebae_options chebae;
  bool exact_probabilities = false;
};

// estimate_amplitude(oracle, settings, g): run the chosen estimator.
template <amplitude_oracle O>
estimation_result estimate_amplitude(O& oracle, const estimator_settings& s, rng& g) {
  auto with_exact = [&](auto o) {
    o.exact_probabilities = o.exact_probabilities || s.exact_probabilities;
    return o;
  };
  switch (s.kind) {
    case estimator_kind::fae: return faster_amplitude_estimation(oracle, with_exact(s.fae), g);
    case estimator_kind::iqae: return iterative_amplitude_estimation(oracle, with_exact(s.iqae), g);
    case estimator_kind::mlae: return maximum_likelihood_amplitude_estimation(oracle, with_exact(s.mlae), g);
    case estimator_kind::canonical: return canonical_amplitude_estimation(oracle, with_exact(s.canonical), g);
    case estimator_kind::qcoin: return quantum_coin_estimation(oracle, with_exact(s.qcoin), g);
    case estimator_kind::mc: return monte_carlo_estimation(oracle, with_exact(s.mc), g);
    case estimator_kind::chebae: return chebyshev_amplitude_estimation(oracle, with_exact(s.chebae), g);
  }
  throw std::logic_error("estimate_amplitude: unknown estimator kind");
}

}  // namespace qrm

// This header's part of <qrm/estimation/compiled_estimation.hpp> (QRM_COMPILED_ESTIMATION): the
// estimators for the two oracles qrm's renderers and tool hand them (every oracle type reaches the
// renderers as an any_oracle; a known probability is an analytic_oracle).
#define QRM_DETAIL_ESTIMATOR_INSTANCES(PREFIX)                                                                    \
  PREFIX estimation_result estimate_amplitude<analytic_oracle>(analytic_oracle&, const estimator_settings&, rng&); \
  PREFIX estimation_result estimate_amplitude<any_oracle>(any_oracle&, const estimator_settings&, rng&);
#ifdef QRM_COMPILED_ESTIMATION
namespace qrm {
QRM_DETAIL_ESTIMATOR_INSTANCES(extern template)
}  // namespace qrm
#endif
