// Determinism: the same inputs and seed give bit-identical results for any thread count, on
// either backend where they compute the same sums, and for tiles merged; where two results are
// not expected to be bit-identical the test says why and checks their agreement instead.
//  - exact light maps, threads 1, 2, 3, on the dense and the compact backend;
//  - dense vs compact: identical amplitudes, P(out=1) equal up to the order of the final sum;
//  - the dense backend's parallel kernels (threads forced on every op) vs one thread;
//  - every estimator with simulated oracles: dense (1 or 2 threads) and compact, same seed;
//  - classical images (extending test_render3d): another scene, ragged tiles rendered with
//    different thread counts, repeated runs, and the seed actually mattering.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/paper_scenes.hpp>
#include <qrm/render/camera.hpp>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <qrm/walk/circuit.hpp>

#include "support/estimation.hpp"

namespace {

namespace r = qrm::render;

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same_maps(const std::vector<qrm::lightmap_cell>& a, const std::vector<qrm::lightmap_cell>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].channel != b[i].channel || !same_bits(a[i].faithful, b[i].faithful) ||
        !same_bits(a[i].history, b[i].history) || !same_bits(a[i].classical, b[i].classical))
      return false;
  return true;
}

bool same_image(const r::image& a, const r::image& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(qrm::io::rgb)) == 0;
}

bool same_result(const qrm::estimation_result& a, const qrm::estimation_result& b) {
  if (!same_bits(a.estimate, b.estimate) || !same_bits(a.raw_estimate, b.raw_estimate) ||
      !same_bits(a.confidence_interval[0], b.confidence_interval[0]) ||
      !same_bits(a.confidence_interval[1], b.confidence_interval[1]) || a.a_calls != b.a_calls ||
      a.grover_calls != b.grover_calls || a.shots != b.shots || a.rounds.size() != b.rounds.size() ||
      a.phase_counts != b.phase_counts || a.warning != b.warning)
    return false;
  for (std::size_t i = 0; i < a.rounds.size(); ++i)
    if (a.rounds[i].power != b.rounds[i].power || a.rounds[i].shots != b.rounds[i].shots ||
        !same_bits(a.rounds[i].hits, b.rounds[i].hits) || !same_bits(a.rounds[i].reference, b.rounds[i].reference))
      return false;
  return true;
}

qrm::dense_options one_thread() {
  qrm::dense_options o;
  o.threads = 1;
  return o;
}

// Threads on every kernel, however small the state: the parallel code paths run.
qrm::dense_options forced_threads(unsigned t) {
  qrm::dense_options o;
  o.threads = t;
  o.min_parallel = 1;
  return o;
}

}  // namespace

TEST_CASE("exact light maps are bit-identical for 1, 2 and 3 threads, on each backend") {
  // Both 2D paper scenes, s = 3. On the 8x8 scene the dense backend runs the faithful circuits
  // only (its history circuits reach 23 qubits, 64 MiB per cell: slow here, and no other code).
  for (const qrm::scene& sc : {qrm::paper_4x4(), qrm::paper_8x8()}) {
    const qrm::walk_model m(sc, qrm::king_2d());
    for (const bool dense : {true, false}) {
      const auto run = [&](const qrm::lightmap_options& lo) {
        return dense ? qrm::exact_lightmap<qrm::dense_backend>(m, lo)
                     : qrm::exact_lightmap<qrm::compact_backend>(m, lo);
      };
      qrm::lightmap_options o;
      o.history = !(dense && sc.size() == 8);
      INFO(sc.name() << (dense ? " dense" : " compact"));
      o.threads = 1;
      const auto one = run(o);
      o.threads = 2;
      const auto two = run(o);
      o.threads = 3;
      const auto three = run(o);
      CHECK(same_maps(one, two));
      CHECK(same_maps(one, three));
      CHECK(same_maps(one, run(o)));  // and run to run
    }
  }
}

TEST_CASE("dense vs compact: identical amplitudes; P(out=1) equal up to the order of the final sum") {
  // Both backends compute each amplitude as the same products summed in the same order (the
  // compact backend's documented contract), so the states agree exactly. P(out = 1) is a sum
  // over the out = 1 half: the compact backend adds the stored amplitudes in label order, the
  // dense one adds chunks of 2^13 indices and then the chunk totals (so that the sum does not
  // depend on the thread count). Up to 2^13 terms the two orders coincide and P is identical;
  // beyond, they differ by at most the rounding of the sums, N u P for N terms.
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  std::size_t identical = 0, compared = 0;
  for (std::size_t cell = 0; cell < sc.voxel_count(); ++cell) {
    qrm::walk_options o;
    o.channel = static_cast<int>(cell % 3);
    const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start(sc.coords(cell)), o);
    qrm::state_vector<double> d(w.circuit.width(), one_thread());
    qrm::compact_state<double> c(w.circuit.width());
    const double pd = qrm::probability_out(d, w), pc = qrm::probability_out(c, w);
    const std::vector<double> cd = c.to_dense();
    INFO("cell " << cell << " width " << w.circuit.width());
    // Equal values; only the sign of a zero may differ (-1/2 * 0 is -0 in the dense vector, the
    // compact backend stores no zeros and reads back +0).
    CHECK(std::equal(cd.begin(), cd.end(), d.amplitudes().begin()));
    const double terms = std::ldexp(1.0, static_cast<int>(w.circuit.width()) - 1);
    if (terms <= 8192) {
      CHECK(same_bits(pd, pc));
    } else {
      CHECK(std::abs(pd - pc) <= terms * std::numeric_limits<double>::epsilon() / 2 * pd);
      ++compared;
      identical += same_bits(pd, pc) ? 1 : 0;
    }
  }
  MESSAGE(compared << " cells sum more than 2^13 terms; P is bit-identical in " << identical << " of them");
}

TEST_CASE("the dense backend's parallel kernels give the single-threaded state bit for bit") {
  // Every op with threads (min_parallel = 1) against one thread: kernels split work by index
  // ranges and reductions by fixed chunks, so nothing may depend on the thread count. The paper's
  // 8x8 walks (17 qubits, multiplexed coins and rotations, adds), and 200 Grover iterations.
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  for (std::size_t cell : {0u, 11u, 27u, 36u, 50u}) {
    qrm::walk_options o;
    o.variant = cell % 2 ? qrm::walk_variant::history : qrm::walk_variant::faithful;
    const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start(sc.coords(cell)), o);
    qrm::state_vector<double> one(w.circuit.width(), one_thread());
    const double p1 = qrm::probability_out(one, w);
    for (unsigned t : {2u, 4u}) {
      qrm::state_vector<double> many(w.circuit.width(), forced_threads(t));
      const double pt = qrm::probability_out(many, w);
      INFO("cell " << cell << " threads " << t);
      CHECK(std::memcmp(one.amplitudes().data(), many.amplitudes().data(), one.size() * sizeof(double)) == 0);
      CHECK(same_bits(p1, pt));
      CHECK(same_bits(one.norm_squared(), many.norm_squared()));
    }
  }
  qrm::walk_options o;
  o.steps = 2;
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({2, 3, 0}), o);
  const qrm::estimation_problem e{w.circuit, {qrm::control{w.out, true}}};
  const qrm::program q = qrm::grover_operator(e);
  qrm::state_vector<double> one(w.circuit.width(), one_thread()), two(w.circuit.width(), forced_threads(2));
  qrm::run(one, e.a);
  qrm::run(two, e.a);
  for (int k = 0; k < 200; ++k) {
    qrm::run(one, q);
    qrm::run(two, q);
  }
  CHECK(std::memcmp(one.amplitudes().data(), two.amplitudes().data(), one.size() * sizeof(double)) == 0);
}

TEST_CASE("estimators: the same seed gives bit-identical results on dense (1 or 2 threads) and compact oracles") {
  // Walk problems of at most 14 qubits: P(good) sums at most 2^13 terms, so (previous test) the
  // backends' p_k agree bit for bit; the estimators then draw the same shots from the same
  // generator and must return identical results. The premise is checked first.
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  using dense = qrm::state_vector<double>;
  using compact = qrm::compact_state<double>;
  for (std::size_t cell : {9u, 18u}) {
    qrm::walk_options o;
    o.steps = 2;
    const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start(sc.coords(cell)), o);
    REQUIRE(w.circuit.width() <= 14);
    const qrm::estimation_problem e{w.circuit, {qrm::control{w.out, true}}};
    {
      qrm::simulated_oracle<dense> d(e, [](std::size_t n) { return dense(n, one_thread()); });
      qrm::simulated_oracle<compact> c(e);
      for (std::uint64_t k = 0; k <= 64; ++k) REQUIRE(same_bits(d.probability(k), c.probability(k)));
    }
    for (const std::string& name : qrm_test::estimator_names()) {
      INFO("cell " << cell << " estimator " << name);
      qrm::simulated_oracle<dense> d1(e, [](std::size_t n) { return dense(n, one_thread()); });
      qrm::simulated_oracle<dense> d2(e, [](std::size_t n) { return dense(n, forced_threads(2)); });
      qrm::simulated_oracle<compact> c(e);
      qrm::rng g1(77), g2(77), g3(77);
      const auto r1 = qrm_test::run_named(name, d1, g1, false, 0.05);
      const auto r2 = qrm_test::run_named(name, d2, g2, false, 0.05);
      const auto r3 = qrm_test::run_named(name, c, g3, false, 0.05);
      CHECK(same_result(r1, r2));
      CHECK(same_result(r1, r3));
      // The generators were used alike.
      const std::uint64_t next = g1();
      CHECK(next == g2());
      CHECK(next == g3());
      // Run to run, with a fresh oracle (nothing cached): identical again.
      qrm::simulated_oracle<dense> again(e, [](std::size_t n) { return dense(n, one_thread()); });
      qrm::rng g4(77);
      CHECK(same_result(r1, qrm_test::run_named(name, again, g4, false, 0.05)));
      // And the seed matters (so the comparisons above can fail): another seed changes the shots.
      qrm::rng g5(78);
      const auto other = qrm_test::run_named(name, d1, g5, false, 0.05);
      CHECK_FALSE(same_result(r1, other));
    }
  }
}

TEST_CASE("classical images: another scene, ragged tiles with mixed thread counts, repeated runs, seeds") {
  // test_render3d checks the Cornell box at 1 vs 2 threads and 4 equal tiles. Here: the two
  // spheres (curved surfaces: many distinct normals and coins), 13 x 11 = 143 pixels so that
  // tiles are ragged, 3 and 5 tiles rendered with 1, 2 and 3 threads, the hardware's thread
  // count, and run-to-run repeats.
  const qrm::walk_model m(r::two_spheres(8), qrm::golden_spiral(15, 3));
  const r::camera cam = r::box_scene_camera(8, 13, 11);
  r::render_options one;
  one.threads = 1;
  r::emulation_options e;
  e.paths_per_pixel = 8;
  e.seed = 11;
  const r::image exact = r::render_exact(m, cam, one);
  const auto mc = r::render_monte_carlo(m, cam, 24, 5, one);
  const auto em = r::render_emulated(m, cam, e, one);
  for (unsigned threads : {0u, 3u}) {
    r::render_options t;
    t.threads = threads;
    INFO("threads " << threads);
    CHECK(same_image(exact, r::render_exact(m, cam, t)));
    const auto mct = r::render_monte_carlo(m, cam, 24, 5, t);
    CHECK(same_image(mc.mean, mct.mean));
    CHECK(same_image(mc.standard_error, mct.standard_error));
    const auto emt = r::render_emulated(m, cam, e, t);
    CHECK(same_image(em.sampled, emt.sampled));
    CHECK(same_image(em.exact, emt.exact));
  }
  for (unsigned count : {3u, 5u}) {
    std::vector<r::image> exact_parts, mc_parts, se_parts, em_parts;
    for (unsigned i = 0; i < count; ++i) {
      r::render_options t;
      t.threads = 1 + i % 3;
      t.part = {i, count};
      exact_parts.push_back(r::render_exact(m, cam, t));
      const auto part = r::render_monte_carlo(m, cam, 24, 5, t);
      mc_parts.push_back(part.mean);
      se_parts.push_back(part.standard_error);
      em_parts.push_back(r::render_emulated(m, cam, e, t).sampled);
    }
    INFO(count << " tiles");
    CHECK(same_image(r::merge_tiles(exact_parts), exact));
    CHECK(same_image(r::merge_tiles(mc_parts), mc.mean));
    CHECK(same_image(r::merge_tiles(se_parts), mc.standard_error));
    CHECK(same_image(r::merge_tiles(em_parts), em.sampled));
  }
  // The comparisons can fail: another seed gives other Monte Carlo and emulated images.
  CHECK_FALSE(same_image(mc.mean, r::render_monte_carlo(m, cam, 24, 6, one).mean));
  r::emulation_options e2 = e;
  e2.seed = 12;
  CHECK_FALSE(same_image(em.sampled, r::render_emulated(m, cam, e2, one).sampled));
}
