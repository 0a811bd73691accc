// examples/qrm/studies.hpp (used by `qrm figures` and test_quantum_render): the paper's convergence study (Fig. 1 centre) and what accuracy
// costs in time, on the same cells for every method.
//
// Error is measured against what each method estimates: the quantum estimators estimate the
// faithful circuit's P(out = 1) (read exactly from the simulated state), Monte Carlo estimates
// the classical transport E[f] (the exact path sum). Both are reported in radiance units
// (times S and the emission scale), as the root mean square over cells and repetitions.
// The cost axis is the number of estimates: paths traced for Monte Carlo, runs of the
// ray-marching circuit (applications of A, counting 2k+1 per shot of Q^k A) for the quantum
// estimators, as the paper chose. Circuits run on a backend family (the compact backend unless
// told otherwise).
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <qrm/backends/backend.hpp>
#include <qrm/backends/compact.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/support/parallel.hpp>
#include <qrm/estimation/estimator.hpp>
#include <qrm/estimation/oracle.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/render/quantum.hpp>

namespace qrm::render {

// A cell and channel to measure on, with its exact values.
struct study_cell {
  walk_start start;
  int channel = 0;
  double exact = 0;           // faithful P(out = 1)
  double classical_mean = 0;  // E[f] (radiance units)
  double radiance_scale = 1;  // S * emission scale
  walk_program program;       // for the simulated oracle
};

// study_cells<F>(model, steps, max_cells): the cells of a 2D light map with light reaching them
// (exact P(out = 1) > 0, run on backend family F), every channel, up to max_cells of them spread
// evenly.
template <backend_family F = compact_backend>
std::vector<study_cell> study_cells(const walk_model& m, unsigned steps, std::size_t max_cells) {
  const scene& sc = m.scene_data();
  std::vector<study_cell> all;
  for (std::size_t cell = 0; cell < sc.voxel_count(); ++cell)
    for (int c = 0; c < 3; ++c) {
      study_cell s;
      s.start = m.light_map_start(sc.coords(cell));
      s.channel = c;
      walk_options o;
      o.steps = steps;
      o.channel = c;
      s.program = make_walk_program(m, s.start, o);
      s.exact = walk_probability<F>(s.program);
      s.radiance_scale = static_cast<double>(steps) * s.program.tables.emission_scale;
      s.classical_mean = path_sum(m, s.start, steps, c);
      if (s.exact > 0) all.push_back(std::move(s));
    }
  if (all.size() <= max_cells || max_cells == 0) return all;
  std::vector<study_cell> picked;
  for (std::size_t i = 0; i < max_cells; ++i) picked.push_back(all[i * all.size() / max_cells]);
  return picked;
}

// One point of an error curve: a method at one budget setting.
struct error_point {
  std::string method;   // "mc" or an estimator name
  std::string setting;  // e.g. "maxiter=5", "paths=1024"
  double estimates = 0; // mean cost per cell: paths (mc) or A applications (quantum)
  double rmse = 0;      // radiance units
  double seconds = 0;   // mean wall time per cell
};

struct study_options {
  unsigned repetitions = 8;  // seeds per cell and setting
  std::uint64_t seed = 1;
  unsigned threads = 0;
  grover_mode grover = grover_mode::analytic;  // analytic: same statistics as simulated (tested), faster
};

namespace detail {
template <class Run>
error_point measure_point(std::string method, std::string setting, const std::vector<study_cell>& cells,
                          const study_options& so, Run run) {
  const std::size_t jobs = cells.size() * so.repetitions;
  std::vector<double> sq(jobs), cost(jobs), secs(jobs);
  qrm::detail::parallel_jobs(jobs, so.threads, [&](std::size_t j) {
    rng g = rng::stream(so.seed, j);
    const auto t0 = std::chrono::steady_clock::now();
    const auto [err, c] = run(cells[j / so.repetitions], g);
    secs[j] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sq[j] = err * err;
    cost[j] = c;
  });
  error_point p{std::move(method), std::move(setting), 0, 0, 0};
  double s = 0;
  for (std::size_t j = 0; j < jobs; ++j) {  // summed in a fixed order: deterministic
    s += sq[j];
    p.estimates += cost[j];
    p.seconds += secs[j];
  }
  p.rmse = std::sqrt(s / static_cast<double>(jobs));
  p.estimates /= static_cast<double>(jobs);
  p.seconds /= static_cast<double>(jobs);
  return p;
}
}  // namespace detail

// monte_carlo_curve(model, cells, steps, paths, options): classical random walks.
template <int = 0>
std::vector<error_point> monte_carlo_curve(const walk_model& m, const std::vector<study_cell>& cells, unsigned steps,
                                           const std::vector<std::uint64_t>& paths, const study_options& so) {
  std::vector<error_point> out;
  for (std::uint64_t n : paths)
    out.push_back(detail::measure_point("mc", "paths=" + std::to_string(n), cells, so, [&](const study_cell& c, rng& g) {
      const auto est = monte_carlo(m, c.start, steps, c.channel, n, g);
      return std::pair<double, double>{est.mean - c.classical_mean, static_cast<double>(n)};
    }));
  return out;
}

// estimator_curve<F>(cells, settings, options): one quantum estimator at several settings; a
// simulated Grover runs on backend family F.
template <backend_family F = compact_backend>
std::vector<error_point> estimator_curve(const std::vector<study_cell>& cells,
                                         const std::vector<std::pair<std::string, estimator_settings>>& settings,
                                         const study_options& so) {
  std::vector<error_point> out;
  for (const auto& [label, s] : settings)
    out.push_back(detail::measure_point(std::string(estimator_name(s.kind)), label, cells, so,
                                        [&, &s = s](const study_cell& c, rng& g) {
                                          estimation_result r;
                                          // any_oracle: the estimators compiled once, not per oracle type
                                          if (so.grover == grover_mode::analytic) {
                                            any_oracle o(analytic_oracle(c.exact));
                                            r = estimate_amplitude(o, s, g);
                                          } else {
                                            r = with_simulated_oracle<F>(
                                                estimation_problem{c.program.circuit, {control{c.program.out, true}}},
                                                [&](auto& o) {
                                                  any_oracle held(std::move(o));
                                                  return estimate_amplitude(held, s, g);
                                                });
                                          }
                                          return std::pair<double, double>{
                                              (r.estimate - c.exact) * c.radiance_scale,
                                              static_cast<double>(r.a_calls + r.check_a_calls)};
                                        }));
  return out;
}

// The budget sweeps the figures use, per estimator (cheap to expensive).
inline std::vector<std::pair<std::string, estimator_settings>> budget_sweep(estimator_kind k, int levels) {
  std::vector<std::pair<std::string, estimator_settings>> out;
  for (int i = 0; i < levels; ++i) {
    estimator_settings s;
    s.kind = k;
    std::string label;
    switch (k) {
      case estimator_kind::fae:
        s.fae.maxiter = static_cast<unsigned>(1 + i);
        s.fae.delta = 0.05;
        label = "maxiter=" + std::to_string(s.fae.maxiter);
        break;
      case estimator_kind::iqae:
        s.iqae.epsilon = 0.05 * std::pow(0.5, i);
        // A failed interval (probability alpha per run) leaves an error that does not shrink
        // with epsilon and dominates an RMS over many runs; 0.01 keeps the curve readable.
        s.iqae.alpha = 0.01;
        label = "epsilon=" + std::to_string(s.iqae.epsilon);
        break;
      case estimator_kind::mlae:
        s.mlae.m = static_cast<unsigned>(1 + i);
        label = "m=" + std::to_string(s.mlae.m);
        break;
      case estimator_kind::canonical:
        s.canonical.evaluation_qubits = static_cast<unsigned>(std::min(12, 3 + i));
        label = "qubits=" + std::to_string(s.canonical.evaluation_qubits);
        break;
      case estimator_kind::qcoin:
        s.qcoin.steps = static_cast<unsigned>(2 + i);
        label = "steps=" + std::to_string(s.qcoin.steps);
        break;
      case estimator_kind::mc:
        s.mc.shots = std::uint64_t{100} << (2 * i);
        label = "shots=" + std::to_string(s.mc.shots);
        break;
      case estimator_kind::chebae:
        s.chebae.epsilon = 0.05 * std::pow(0.5, i);
        s.chebae.alpha = 0.01;  // as IQAE: a failed interval would dominate the RMS error
        label = "epsilon=" + std::to_string(s.chebae.epsilon);
        break;
    }
    out.push_back({label, s});
  }
  return out;
}

}  // namespace qrm::render
