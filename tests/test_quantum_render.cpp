// Rendering with the quantum circuit: simulated and analytic Grover agree on the paper's
// circuit, FAE intervals hold the exact values, the exact maps are the walk's numbers, the 3D
// quantum image is the walk circuits' P(out=1), and the convergence slopes of the paper's study.
#include <doctest/doctest.h>

#include <cmath>

#include <qrm/backends/dense.hpp>
#include <qrm/io/svg_plot.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/paper_scenes.hpp>
#include "studies.hpp"  // examples/qrm: the convergence and cost studies
#include <qrm/render/quantum.hpp>
#include <qrm/render/voxelize.hpp>

namespace {
const qrm::walk_model& paper_model() {
  static const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  return m;
}
}  // namespace

TEST_CASE("simulated and analytic Grover give the same outcomes on the paper 8x8 circuit") {
  const auto& m = paper_model();
  // Cells with light (air, wall, centre block), every estimator, one seed each: the counts of
  // every round must be identical, so the estimates are bit-identical.
  for (unsigned cell : {9u, 19u, 27u, 42u}) {
    qrm::walk_options o;
    o.channel = static_cast<int>(cell % 3);
    const auto w = qrm::make_walk_program(m, m.light_map_start(qrm::paper_8x8().coords(cell)), o);
    const qrm::estimation_problem problem{w.circuit, {qrm::control{w.out, true}}};
    const double a = qrm::walk_probability<qrm::compact_backend>(w);
    for (qrm::estimator_kind k : {qrm::estimator_kind::fae, qrm::estimator_kind::iqae, qrm::estimator_kind::mlae,
                                  qrm::estimator_kind::qcoin}) {
      qrm::estimator_settings s;
      s.kind = k;
      qrm::rng g1(100 + cell), g2(100 + cell);
      qrm::simulated_oracle<qrm::compact_state<double>> simulated(problem);
      qrm::analytic_oracle analytic(a);
      const auto r1 = qrm::estimate_amplitude(simulated, s, g1);
      const auto r2 = qrm::estimate_amplitude(analytic, s, g2);
      INFO("cell " << cell << " estimator " << qrm::estimator_name(k));
      REQUIRE(r1.rounds.size() == r2.rounds.size());
      for (std::size_t i = 0; i < r1.rounds.size(); ++i) {
        CHECK(r1.rounds[i].power == r2.rounds[i].power);
        CHECK(r1.rounds[i].hits == r2.rounds[i].hits);
      }
      CHECK(r1.estimate == r2.estimate);
      CHECK(r1.a_calls == r2.a_calls);
      CHECK(simulated.probability(0) == doctest::Approx(a).epsilon(1e-12));
    }
  }
}

TEST_CASE("the estimated light map: exact values are the walk's, FAE intervals hold them") {
  const auto& m = paper_model();
  qrm::render::quantum_options o;  // FAE maxiter 5, rescaling, every Grover iteration simulated
  o.seed = 7;
  const auto cells = qrm::render::estimate_lightmap(m, o);
  qrm::lightmap_options lo;
  lo.history = false;
  const auto exact = qrm::exact_lightmap<qrm::compact_backend>(m, lo);
  REQUIRE(cells.size() == exact.size());
  std::size_t inside = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    CHECK(cells[i].exact == exact[i].faithful);  // the same circuit on the same backend
    CHECK(cells[i].classical == doctest::Approx(exact[i].classical).epsilon(1e-12));
    inside += cells[i].exact >= cells[i].interval[0] && cells[i].exact <= cells[i].interval[1];
  }
  // Each FAE interval holds with probability >= 1 - 2 * maxiter * delta = 0.9 by its union
  // bound (in practice far more: ~0.999). The bar is 95% of the 192 cell-channels; with a
  // per-cell failure rate of 0.01 (10x what we measure), P(more than 9 failures) < 1e-3.
  MESSAGE("exact value inside the FAE interval in " << inside << " of " << cells.size() << " cell-channels");
  CHECK(static_cast<double>(inside) >= 0.95 * static_cast<double>(cells.size()));
}

TEST_CASE("the 3D quantum image is each pixel's walk circuit, independent of threads and tiles") {
  const qrm::scene sc = qrm::render::cornell_box(8);
  const qrm::walk_model m(sc, qrm::sphere_directions(15, 3));
  const auto cam = qrm::render::box_scene_camera(8, 12, 12);
  qrm::render::quantum_options o;
  o.steps = 3;
  o.grover = qrm::render::grover_mode::analytic;
  o.threads = 2;
  const auto q = qrm::render::render_quantum(m, cam, o);
  CHECK(q.distinct_starts > 0);
  // Walk circuits of the pixels' starts: compact (what render_quantum uses) against dense.
  const auto px = qrm::render::pixel_starts(m, cam);
  std::size_t compared = 0;
  for (const auto& p : px) {
    if (!p.hit || compared >= 5) continue;
    qrm::walk_options wo;
    wo.steps = 3;
    const auto w = qrm::make_walk_program(m, p.start, wo);
    if (w.circuit.width() > 24) continue;
    const double dense = qrm::walk_probability<qrm::dense_backend>(w);
    CHECK(qrm::walk_probability<qrm::compact_backend>(w) == doctest::Approx(dense).epsilon(1e-12));
    ++compared;
  }
  o.threads = 1;
  const auto q1 = qrm::render::render_quantum(m, cam, o);
  CHECK(q1.estimated == q.estimated);
  CHECK(q1.exact == q.exact);
  std::vector<qrm::io::image> parts;
  for (unsigned i = 0; i < 3; ++i) {
    o.part = {i, 3};
    parts.push_back(qrm::render::render_quantum(m, cam, o).estimated);
  }
  CHECK(qrm::render::merge_tiles(parts) == q.estimated);
}

TEST_CASE("convergence: Monte Carlo slope near -1/2, quantum estimators below -0.85 over two decades") {
  const auto& m = paper_model();
  const auto cells = qrm::render::study_cells(m, 3, 12);
  qrm::render::study_options so;
  so.repetitions = 6;
  so.seed = 3;
  std::vector<std::uint64_t> paths;
  for (int k = 2; k <= 14; k += 2) paths.push_back(std::uint64_t{1} << k);
  auto slope = [](const std::vector<qrm::render::error_point>& pts) {
    std::vector<double> x, y;
    for (const auto& p : pts) {
      x.push_back(p.estimates);
      y.push_back(p.rmse);
    }
    return std::pair{qrm::io::fit_log_log(x, y).slope, x.back() / x.front()};
  };
  // RMS over 12 x 6 = 72 runs per point: the error of each point's RMSE is ~1/sqrt(2 * 72) = 8%,
  // which moves a slope fitted over 3.6 decades by a few hundredths; the bars have 0.1 of room.
  const auto [mc, mc_span] = slope(qrm::render::monte_carlo_curve(m, cells, 3, paths, so));
  MESSAGE("Monte Carlo slope " << mc);
  CHECK((mc > -0.6 && mc < -0.4));
  CHECK(mc_span >= 100);
  // The best quantum estimator (MLAE or FAE here) must fall at least as fast as N^-0.85.
  const auto [fae, fae_span] =
      slope(qrm::render::estimator_curve(cells, qrm::render::budget_sweep(qrm::estimator_kind::fae, 8), so));
  const auto [mlae, mlae_span] =
      slope(qrm::render::estimator_curve(cells, qrm::render::budget_sweep(qrm::estimator_kind::mlae, 8), so));
  MESSAGE("FAE slope " << fae << " over " << fae_span << "x, MLAE slope " << mlae << " over " << mlae_span << "x");
  CHECK(std::min(fae, mlae) <= -0.85);
  CHECK(fae_span >= 100);
  CHECK(mlae_span >= 100);
}

TEST_CASE("the emulator's amplitude-estimation hook estimates the mean of the sampled paths") {
  qrm::estimator_settings s;
  s.exact_probabilities = true;  // deterministic: the algorithm's own error only
  const auto hook = qrm::render::amplitude_path_estimator(s);
  qrm::rng g(1);
  const std::vector<double> f = {0.0, 1.2, 0.6, 0.3};  // mean 0.525, S = 3, scale 2: a = 0.0875
  const double v = hook(f, 3, 2.0, g);
  // FAE (maxiter 5) in exact mode resolves theta to ~1e-3: a to ~1e-3, times S * scale = 6.
  CHECK(v == doctest::Approx(0.525).epsilon(0.02));
}
