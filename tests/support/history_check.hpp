// tests/support/history_check.hpp: the history variant's P(out = 1) against the classical path
// sum (the walk's exactness check, shared by the march, materials and media tests).
#pragma once

#include <doctest/doctest.h>

#include <cstddef>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/walk/lightmap.hpp>

namespace qrm_test {

// For every start and colour channel: the history circuit's P(out = 1) on the compact backend
// equals path_sum / (steps * emission scale) to 1e-12 (relative, or absolute near 0); with
// `enumerated`, the path sum by dynamic programming also equals the one by enumeration. At least
// one start must see light, so an all-black scene cannot pass.
inline void check_history_equals_path_sum(const qrm::walk_model& m, const std::vector<qrm::walk_start>& starts,
                                          unsigned steps, bool enumerated = false) {
  std::size_t nonzero = 0;
  for (const auto& st : starts)
    for (int c = 0; c < 3; ++c) {
      qrm::walk_options o;
      o.steps = steps;
      o.channel = c;
      o.variant = qrm::walk_variant::history;
      const qrm::walk_program w = qrm::make_walk_program(m, st, o);
      const double p = qrm::walk_probability<qrm::compact_backend>(w);
      const double classical = qrm::path_sum(m, st, steps, c) / (steps * w.tables.emission_scale);
      REQUIRE(p == doctest::Approx(classical).epsilon(1e-12).scale(1.0));
      if (enumerated)
        CHECK(qrm::path_sum_enumerated(m, st, steps, c) == doctest::Approx(qrm::path_sum(m, st, steps, c)).epsilon(1e-12));
      nonzero += p > 0;
    }
  CHECK(nonzero > 0);
}

}  // namespace qrm_test
