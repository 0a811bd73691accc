// The ray-marching circuit: against the classical path sum, across pruning levels, the typed
// circuit against the run-time builder, scaling of emission, and the interference the paper's
// scenes show (faithful vs classical).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <type_traits>

#include <qrm/walk/classical.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/paper_scenes.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/circuit/qasm.hpp>

namespace {

double run_dense(const qrm::walk_program& w) { return qrm::walk_probability<qrm::dense_backend>(w); }
double run_compact(const qrm::walk_program& w) { return qrm::walk_probability<qrm::compact_backend>(w); }

}  // namespace

TEST_CASE("path sum by forward pass equals explicit path enumeration") {
  for (const auto& sc : {qrm::paper_4x4(), qrm::paper_8x8()}) {
    const qrm::walk_model m(sc, qrm::king_2d());
    for (unsigned cell = 0; cell < sc.voxel_count(); cell += 3)
      for (unsigned s : {1u, 2u, 4u}) {
        const auto start = m.light_map_start(sc.coords(cell));
        // Both sum the same products in different orders: agreement to rounding (~1e-16).
        CHECK(qrm::path_sum(m, start, s, 0) == doctest::Approx(qrm::path_sum_enumerated(m, start, s, 0)).epsilon(1e-12));
      }
  }
}

TEST_CASE("history circuit equals the classical path sum; dense and compact agree; pruning never changes P(out=1)") {
  for (const auto& sc : {qrm::paper_4x4(), qrm::paper_8x8()}) {
    const qrm::walk_model m(sc, qrm::king_2d());
    double max_rel_interference = 0, worst_history = 0, worst_backends = 0;
    for (unsigned cell = 0; cell < sc.voxel_count(); ++cell)
      for (int c = 0; c < 3; ++c) {
        const auto start = m.light_map_start(sc.coords(cell));
        qrm::walk_options o;
        o.channel = c;
        const double classical = qrm::path_sum(m, start, 3, c) / 3.0;
        o.variant = qrm::walk_variant::history;
        const auto hist = qrm::make_walk_program(m, start, o);
        const double history = run_compact(hist);
        worst_history = std::max(worst_history, std::abs(history - classical));
        o.variant = qrm::walk_variant::faithful;
        const auto faithful_program = qrm::make_walk_program(m, start, o);
        const double faithful = run_dense(faithful_program);
        worst_backends = std::max(worst_backends, std::abs(run_compact(faithful_program) - faithful));
        for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::scene}) {
          o.prune = p;
          CHECK(std::abs(run_compact(qrm::make_walk_program(m, start, o)) - faithful) < 1e-12);
        }
        if (classical > 0) max_rel_interference = std::max(max_rel_interference, std::abs(faithful - classical) / classical);
      }
    // Sums of at most a few hundred products of O(1) numbers, in different orders: 1e-12 is the
    // issue's bar (measured: ~2e-16).
    MESSAGE(sc.name() << ": max |history - classical| = " << worst_history << ", max |dense - compact| = " << worst_backends);
    CHECK(worst_history < 1e-12);
    CHECK(worst_backends < 1e-12);
    // The faithful circuit differs from classical transport by up to about 11% of a cell's value
    // on the 4x4 scene and 5% on the 8x8 scene (11.5% and 5.5% in an independent sparse
    // simulator written from the scenes' conventions alone).
    MESSAGE(sc.name() << ": largest |faithful - classical| / classical = " << max_rel_interference);
    if (sc.size() == 4) CHECK((max_rel_interference > 0.09 && max_rel_interference < 0.13));
    if (sc.size() == 8) CHECK((max_rel_interference > 0.04 && max_rel_interference < 0.07));
  }
}

namespace {
// Everything a program says, op by op: QASM text (angles round-trip exactly) plus the layer labels.
std::string describe(const qrm::program& p) {
  std::string r = qrm::to_qasm(p);
  for (std::size_t i = 0; i < p.size(); ++i) r += std::string(p.layer_of(i) ? p.layer_of(i) : "-") + ";";
  return r;
}

// The static-width walk (constant offsets) and the dynamic-width walk (offsets from the model)
// lower to the same program, op for op, for one start.
template <class Static>
void check_static_equals_dynamic(const qrm::walk_model& m, const qrm::walk_start& start, unsigned steps,
                                 qrm::walk_variant v) {
  for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::reachable}) {
    const Static typed(m, start, 0, p);
    qrm::walk_options o;
    o.steps = steps;
    o.variant = v;
    o.prune = p;
    const auto dynamic = qrm::with_dynamic_walk(m.dims(), [&]<class C>(std::type_identity<C>) {
      return qrm::record(C(m, start, o));
    });
    const qrm::program from_type = qrm::record(typed);
    CHECK(from_type.width() == Static::width);
    CHECK(dynamic.width() == Static::width);
    CHECK(describe(from_type) == describe(dynamic));
    CHECK(from_type.registers().size() == dynamic.registers().size());
    // The builder's program is the same with idle qubits removed (plus a qubit for `out` where
    // no term can fire and `out` was idle).
    const qrm::walk_program built = qrm::make_walk_program(m, start, o);
    // Naming the dimension builds the same program; naming another is refused.
    const qrm::walk_program known = qrm::make_walk_program<Static::dims>(m, start, o);
    CHECK(describe(known.circuit) == describe(built.circuit));
    CHECK(known.out == built.out);
    CHECK_THROWS_WITH(qrm::make_walk_program<5 - Static::dims>(m, start, o), doctest::Contains("the scene has"));
    if (p == qrm::pruning::none) CHECK(describe(from_type) == describe(built.circuit));
    CHECK(qrm::remove_idle_qubits(from_type).size() == built.circuit.size());
    // The logical depth stays within the compile-time O(s(p^dims + d)) bound.
    CHECK(qrm::circuit_metrics_of(from_type).logical_depth <= Static::depth_bound);
  }
}
}  // namespace

TEST_CASE("the static-width walk has the paper's width and lowers exactly as the dynamic-width one") {
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  using A = qrm::ray_marching_circuit<2, 3, 3, 3>;
  using H = qrm::ray_marching_circuit<2, 3, 3, 3, qrm::walk_variant::history>;
  // Width = 2 log2 p + log2 d + s (Le) + (s-1) (rho) + ceil(log2 s) (steps) + 1 (out).
  static_assert(A::width == 3 + 3 + 3 + 3 + 2 + 2 + 1);
  static_assert(H::width == A::width + 2 * 3);  // (s - 1) * log2 d history qubits
  static_assert(A::is_real);
  static_assert(A::layout_type::offset<qrm::walk_registers::direction<3>> == 1 + 2 + 3 + 2);  // out, steps, Le, rho below
  const auto start = m.light_map_start({3, 4, 0});
  check_static_equals_dynamic<A>(m, start, 3, qrm::walk_variant::faithful);
  check_static_equals_dynamic<H>(m, start, 3, qrm::walk_variant::history);
  // One step: the static layout has no rho (nor hist) register, the dynamic one an empty one.
  check_static_equals_dynamic<qrm::ray_marching_circuit<2, 3, 3, 1>>(m, start, 1, qrm::walk_variant::faithful);
  check_static_equals_dynamic<qrm::ray_marching_circuit<2, 3, 3, 1, qrm::walk_variant::history>>(
      m, start, 1, qrm::walk_variant::history);
  // 3D with fixed-point positions.
  qrm::scene box("box", 3, 4);
  for (unsigned z = 0; z < 4; ++z)
    for (unsigned x = 0; x < 4; ++x) {
      qrm::voxel& v = box.at(x, 0, z);
      v.kind = qrm::material::lambertian;
      v.normal = {0, 1, 0};
      v.reflectance = {0.5, 0.5, 0.5};
      v.emission = {1, 1, 1};
    }
  const qrm::walk_model m3(box, qrm::golden_spiral(15, 2));
  check_static_equals_dynamic<qrm::ray_marching_circuit<3, 2, 4, 2, qrm::walk_variant::history, 2>>(
      m3, m3.light_map_start({1, 1, 1}), 2, qrm::walk_variant::history);

  // A scene that does not fit the circuit type: the error names the register.
  const qrm::walk_model m4(qrm::paper_4x4(), qrm::king_2d());
  CHECK_THROWS_WITH_AS(A(m4, m4.light_map_start({1, 1, 0})), "register 'x' has 3 qubits in the layout type, but 2 are needed",
                       std::invalid_argument);
}

TEST_CASE("pruning removes gates, depth and qubits") {
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  const auto start = m.light_map_start({3, 4, 0});
  qrm::walk_options o;
  o.prune = qrm::pruning::none;
  const auto full = qrm::circuit_metrics_of(qrm::make_walk_program(m, start, o).circuit);
  o.prune = qrm::pruning::scene;
  const auto scene_pruned = qrm::circuit_metrics_of(qrm::make_walk_program(m, start, o).circuit);
  o.prune = qrm::pruning::reachable;
  const auto reach = qrm::circuit_metrics_of(qrm::make_walk_program(m, start, o).circuit);
  MESSAGE("unpruned: width " << full.width << " depth " << full.logical_depth << " gates " << full.gate_count);
  MESSAGE("scene:    width " << scene_pruned.width << " depth " << scene_pruned.logical_depth << " gates " << scene_pruned.gate_count);
  MESSAGE("reach:    width " << reach.width << " depth " << reach.logical_depth << " gates " << reach.gate_count);
  CHECK(full.width == 17);
  // Unpruned: every step has a 64-entry coin and two 64-entry sample layers (the last step one).
  CHECK(full.by_kind.at("mux_unitary") == 3 * 64);
  // Le (3 layers), rho (2 layers), and the steps preparation's lower qubit (one entry).
  CHECK(full.by_kind.at("mux_ry") == 3 * 64 + 2 * 64 + 1);
  CHECK(scene_pruned.gate_count < full.gate_count);
  CHECK(reach.gate_count < scene_pruned.gate_count);
  CHECK(reach.logical_depth < scene_pruned.logical_depth);
  CHECK(scene_pruned.by_kind.at("mux_unitary") == 3 * 37);  // 37 non-air cells
}

TEST_CASE("emission above 1 is scaled into the circuit and back") {
  qrm::scene sc = qrm::paper_4x4();
  for (std::size_t i = 0; i < sc.voxel_count(); ++i) sc[i].emission.r *= 4.0;
  const qrm::walk_model m(sc, qrm::king_2d());
  CHECK(sc.emission_scale(0) == 4.0);
  for (unsigned cell : {5u, 6u, 9u}) {
    const auto start = m.light_map_start(sc.coords(cell));
    qrm::walk_options o;
    o.variant = qrm::walk_variant::history;
    const auto w = qrm::make_walk_program(m, start, o);
    CHECK(w.tables.emission_scale == 4.0);
    const double radiance = run_dense(w) * 3.0 * w.tables.emission_scale;
    CHECK(radiance == doctest::Approx(qrm::path_sum(m, start, 3, 0)).epsilon(1e-12));
  }
}

TEST_CASE("Monte Carlo agrees with the path sum") {
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  qrm::rng g(2024);
  for (unsigned cell : {9u, 20u, 27u, 45u, 54u}) {
    const auto start = m.light_map_start(sc.coords(cell));
    const auto mc = qrm::monte_carlo(m, start, 3, 0, 20000, g);
    const double exact = qrm::path_sum(m, start, 3, 0);
    // |mean - exact| < 5 standard errors: a false failure has probability < 6e-7 per cell
    // (normal approximation; 20000 paths of a bounded f).
    INFO("cell " << cell << " mc " << mc.mean << " +- " << mc.standard_error << " exact " << exact);
    CHECK(std::abs(mc.mean - exact) <= 5 * mc.standard_error + 1e-12);
  }
}

TEST_CASE("a light map computes identical channels once, and its order is y, x, channel") {
  const qrm::scene sc = qrm::paper_4x4();
  const qrm::walk_model m(sc, qrm::king_2d());
  qrm::lightmap_options o;
  o.threads = 2;
  const auto cells = qrm::exact_lightmap(m, o);
  REQUIRE(cells.size() == 48);
  CHECK((cells[0].x == 0 && cells[0].y == 0 && cells[0].channel == 0));
  CHECK((cells[3].x == 1 && cells[3].y == 0 && cells[3].channel == 0));
  CHECK((cells[12].x == 0 && cells[12].y == 1));
  o.threads = 1;
  const auto again = qrm::exact_lightmap(m, o);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    CHECK(cells[i].faithful == again[i].faithful);  // bit-identical whatever the thread count
    CHECK(std::abs(cells[i].history - cells[i].classical) < 1e-12);
  }
  qrm::scene grey = qrm::paper_4x4();
  for (std::size_t i = 0; i < grey.voxel_count(); ++i) {
    grey[i].reflectance.g = grey[i].reflectance.b = grey[i].reflectance.r;
    grey[i].emission.g = grey[i].emission.b = grey[i].emission.r;
  }
  CHECK(grey.same_channels(0, 1));
  const auto g = qrm::exact_lightmap(qrm::walk_model(grey, qrm::king_2d()), o);
  for (std::size_t i = 0; i < g.size(); i += 3) {
    CHECK(g[i].faithful == g[i + 1].faithful);
    CHECK(g[i + 2].classical == g[i].classical);
    CHECK(g[i + 1].channel == 1);
  }
}

TEST_CASE("a 3D walk (golden spiral, fixed-point positions) matches its classical path sum") {
  // 4^3 voxels: an emissive floor, a grey Lambertian wall, boundary voxels around.
  qrm::scene sc("box", 3, 4);
  for (unsigned z = 0; z < 4; ++z)
    for (unsigned y = 0; y < 4; ++y)
      for (unsigned x = 0; x < 4; ++x) {
        qrm::voxel& v = sc.at(x, y, z);
        if (y == 0) {
          v.kind = qrm::material::lambertian;
          v.normal = {0, 1, 0};
          v.reflectance = {0.5, 0.5, 0.5};
          v.emission = {2.0, 1.0, 0.5};
        } else if (x == 3) {
          v.kind = qrm::material::lambertian;
          v.normal = {-1, 0, 0};
          v.reflectance = {0.8, 0.2, 0.1};
        }
      }
  for (unsigned frac : {1u, 2u}) {
    const qrm::walk_model m(sc, qrm::golden_spiral(15, frac));
    CHECK(m.direction_bits() == 4);
    for (auto cell : {std::array<unsigned, 3>{1, 1, 1}, std::array<unsigned, 3>{2, 2, 1}, std::array<unsigned, 3>{3, 1, 2}}) {
      const auto start = m.light_map_start(cell);
      for (int c = 0; c < 3; ++c) {
        qrm::walk_options o;
        o.steps = 2;
        o.channel = c;
        o.variant = qrm::walk_variant::history;
        const auto w = qrm::make_walk_program(m, start, o);
        const double classical = qrm::path_sum(m, start, 2, c) / (2.0 * sc.emission_scale(c));
        CHECK(std::abs(run_compact(w) - classical) < 1e-12);
      }
    }
  }
}
