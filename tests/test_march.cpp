// The surface (bounce-driven) march: the model's moves against an independent marcher, the
// circuit's March gate as a permutation of every basis state, the history variant against the
// classical path sum, and the radiance table against per-start path sums.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include <qrm/backends/compact.hpp>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/scene_format.hpp>

#include "support/history_check.hpp"

namespace {

// An N x N room: boundary ring, Lambertian inner walls facing in, a light in the top wall and
// one Lambertian block in the middle.
qrm::scene room_2d(unsigned n) {
  qrm::scene s("room", 2, n);
  for (unsigned y = 0; y < n; ++y)
    for (unsigned x = 0; x < n; ++x) {
      qrm::voxel& v = s.at(x, y);
      const bool edge = x == 0 || y == 0 || x == n - 1 || y == n - 1;
      if (!edge) continue;
      v.kind = qrm::material::lambertian;
      v.reflectance = {0.7, 0.5, 0.3};
      v.normal_index = y == 0 ? 4 : y == n - 1 ? 0 : x == 0 ? 2 : 6;
      if ((x == 0 || x == n - 1) && (y == 0 || y == n - 1)) {
        v.kind = qrm::material::boundary;
        v.reflectance = {0, 0, 0};
        v.normal_index = 0;
      }
    }
  s.at(n / 2, 0).emission = {4, 3, 2};
  s.at(n / 2, n / 2).kind = qrm::material::lambertian;
  s.at(n / 2, n / 2).normal_index = 0;
  s.at(n / 2, n / 2).reflectance = {0.9, 0.8, 0.7};
  return s;
}

// The march written out independently: from the centre of voxel v, add round(2^F u) (u the
// direction's unit vector) until a non-air voxel (at most `limit` times), wrapping per axis;
// land at that voxel's centre.
struct landing {
  std::size_t voxel;
  std::uint64_t k;
};
landing march_by_hand(const qrm::scene& s, const qrm::direction_set& dirs, std::size_t v, std::uint32_t d,
                      std::uint64_t limit) {
  const unsigned f = dirs.fractional_bits;
  const auto c = s.coords(v);
  const std::int64_t unit = std::int64_t{1} << f, wrap = static_cast<std::int64_t>(s.size()) * unit;
  std::int64_t p[3], step[3];
  for (unsigned a = 0; a < 3; ++a) {
    p[a] = static_cast<std::int64_t>(c[a]) * unit + unit / 2;
    step[a] = a < s.dims() ? std::llround(dirs.vectors[d][a] * static_cast<double>(unit)) : 0;
  }
  for (std::uint64_t k = 1;; ++k) {
    for (unsigned a = 0; a < s.dims(); ++a) p[a] = ((p[a] + step[a]) % wrap + wrap) % wrap;
    const std::size_t w = s.index(static_cast<unsigned>(p[0] / unit), static_cast<unsigned>(p[1] / unit),
                                  s.dims() == 3 ? static_cast<unsigned>(p[2] / unit) : 0u);
    if (s[w].kind != qrm::material::air || k == limit) return {w, k};
  }
}

}  // namespace

TEST_CASE("surface march: moves by hand in 2D, and against an independent marcher in 3D") {
  const qrm::scene room = room_2d(8);
  const qrm::walk_model m(room, qrm::king_2d(), qrm::march_mode::surface);
  CHECK(m.march() == qrm::march_mode::surface);
  CHECK(m.march_limit() == 8);    // 8 cells to cross the room along an axis
  CHECK(m.distance_bits() == 4);  // k in 0..8
  // From (1, 4): east (2) reaches the block at (4, 4) after 3 cells; north (0) the top wall at
  // (1, 0) after 4; north-east (1) the top wall at (5, 0) after 4.
  auto land = [&](unsigned x, unsigned y, std::uint32_t d) {
    const auto mv = m.moved_by(m.centre_of({x, y, 0}), d);
    return std::make_tuple(mv.pos[0], mv.pos[1], mv.distance);
  };
  CHECK(land(1, 4, 2) == std::make_tuple(4u, 4u, 3u));
  CHECK(land(1, 4, 0) == std::make_tuple(1u, 0u, 4u));
  CHECK(land(1, 4, 1) == std::make_tuple(5u, 0u, 4u));
  CHECK(land(4, 4, 4) == std::make_tuple(4u, 7u, 3u));
  // The voxel march moves one cell.
  const qrm::walk_model v(room, qrm::king_2d(), qrm::march_mode::voxel);
  CHECK(v.moved_by(v.centre_of({1, 4, 0}), 2).pos[0] == 2);
  CHECK(v.distance_bits() == 0);
  // A scene's own march is the default; an explicit one wins.
  qrm::scene marked = room;
  marked.set_march(qrm::march_mode::surface);
  CHECK(qrm::walk_model(marked, qrm::king_2d()).march() == qrm::march_mode::surface);
  CHECK(qrm::walk_model(marked, qrm::king_2d(), qrm::march_mode::voxel).march() == qrm::march_mode::voxel);
  CHECK(qrm::walk_model(room, qrm::king_2d()).march() == qrm::march_mode::voxel);

  // 3D, golden spiral with sub-voxel bits: every non-air voxel and direction of the 8^3 box.
  const qrm::scene box = qrm::render::cornell_box(8);
  const qrm::direction_set dirs = qrm::golden_spiral(32, 4);
  const qrm::walk_model m3(box, dirs, qrm::march_mode::surface);
  std::size_t checked = 0, longer = 0;
  for (std::size_t vx = 0; vx < box.voxel_count(); ++vx) {
    if (box[vx].kind == qrm::material::air) continue;
    for (std::uint32_t d = 0; d < dirs.size(); ++d) {
      const landing want = march_by_hand(box, dirs, vx, d, m3.march_limit());
      const auto got = m3.moved_by(m3.centre_of(box.coords(vx)), d);
      REQUIRE(m3.voxel_of(got.pos) == want.voxel);
      REQUIRE(got.distance == want.k);
      REQUIRE(got.pos == m3.centre_of(box.coords(want.voxel)));
      ++checked;
      longer += want.k > 1;
    }
  }
  CHECK(checked > 10000);
  CHECK(longer > 500);  // the room's inside is crossed, not just neighbours
}

namespace {
// The March gate of step 0 (pruning none: every voxel and direction) as a program.
struct march_program {
  qrm::program ops;
  std::map<std::string, qrm::register_info> regs;
};
march_program march_ops(const qrm::walk_model& m) {
  qrm::walk_options o;
  o.steps = 1;
  o.prune = qrm::pruning::none;
  const qrm::walk_program w = qrm::make_walk_program(m, {{1, 1, m.dims() == 3 ? 1u : 0u}, 0}, o);
  march_program r{qrm::program(w.circuit.width()), {}};
  for (const auto& ri : w.circuit.registers()) r.regs[std::string(ri.name)] = ri;
  for (std::size_t i = 0; i < w.circuit.ops().size(); ++i)
    if (w.circuit.layer_of(i) && std::string(w.circuit.layer_of(i)) == "shift") r.ops.push(w.circuit.ops()[i]);
  return r;
}

// Under AddressSanitizer a basis state costs about 17x its optimized time (this test: 123 s
// against 7 s), so there every fresh voxel-centre state runs and one in 7 of the others: memory
// errors, not coverage, are what that build is for, and the optimized build runs every state.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::uint64_t sanitizer_stride = 7;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr std::uint64_t sanitizer_stride = 7;
#else
constexpr std::uint64_t sanitizer_stride = 1;
#endif
#else
constexpr std::uint64_t sanitizer_stride = 1;
#endif

// Runs the March gate on every basis state of (position, direction, distance) (sampled under
// AddressSanitizer, above) and checks it is a permutation of them that maps (voxel centre, d, 0)
// to (the marcher's landing, d, k).
void check_march_bijection(const qrm::walk_model& m) {
  const march_program mp = march_ops(m);
  REQUIRE(!mp.ops.ops().empty());
  std::vector<qrm::qubit_index> qubits;  // the March's register bits, in label order
  for (const char* name : {"x", "y", "z", "dir", "dist"}) {
    const auto it = mp.regs.find(name);
    if (it == mp.regs.end()) continue;
    for (std::size_t b = 0; b < it->second.width; ++b) qubits.push_back(it->second.offset + static_cast<qrm::qubit_index>(b));
  }
  // Every other op qubit must be outside: the March touches only these registers.
  for (const auto& o : mp.ops.ops())
    for (qrm::qubit_index q : qrm::op_qubits(o)) REQUIRE(std::find(qubits.begin(), qubits.end(), q) != qubits.end());
  const std::uint64_t states = std::uint64_t{1} << qubits.size();
  REQUIRE(states <= (std::uint64_t{1} << 20));
  std::set<std::uint64_t> images;
  const unsigned axis = m.axis_bits(), f = m.fractional_bits();
  const std::size_t dist_offset = m.dims() * axis + m.direction_bits();
  std::size_t centre_checks = 0, runs = 0;
  for (std::uint64_t in = 0; in < states; ++in) {
    // A voxel centre with a fresh distance register: the landing and k are checked too.
    std::array<std::uint64_t, 3> pos{};
    bool centre = true;
    for (unsigned a = 0; a < m.dims(); ++a) {
      pos[a] = (in >> (a * axis)) & ((std::uint64_t{1} << axis) - 1);
      centre = centre && (f == 0 || (pos[a] & ((std::uint64_t{1} << f) - 1)) == (std::uint64_t{1} << (f - 1)));
    }
    const std::uint64_t d = (in >> (m.dims() * axis)) & ((std::uint64_t{1} << m.direction_bits()) - 1);
    const std::uint64_t dist = in >> dist_offset;
    const bool fresh_centre = centre && dist == 0 && d < m.direction_count();
    if (!fresh_centre && in % sanitizer_stride != 0) continue;
    ++runs;
    std::uint64_t label = 0;
    for (std::size_t b = 0; b < qubits.size(); ++b)
      if ((in >> b) & 1u) label |= std::uint64_t{1} << qubits[b];
    qrm::compact_state<double> st(mp.ops.width());
    st.set_basis_state(label);
    qrm::run(st, mp.ops);
    REQUIRE(st.nonzeros() == 1);
    REQUIRE(std::abs(std::abs(st.entries()[0].amp) - 1.0) < 1e-12);
    const std::uint64_t outl = st.entries()[0].label;
    std::uint64_t out = 0;
    for (std::size_t b = 0; b < qubits.size(); ++b)
      if ((outl >> qubits[b]) & 1u) out |= std::uint64_t{1} << b;
    REQUIRE(images.insert(out).second);
    if (!fresh_centre) continue;
    const landing want = march_by_hand(m.scene_data(), m.directions(), m.voxel_of(pos), static_cast<std::uint32_t>(d),
                                       m.march_limit());
    const auto wc = m.centre_of(m.scene_data().coords(want.voxel));
    std::uint64_t expect = d << (m.dims() * axis) | want.k << dist_offset;
    for (unsigned a = 0; a < m.dims(); ++a) expect |= wc[a] << (a * axis);
    REQUIRE(out == expect);
    ++centre_checks;
  }
  CHECK(images.size() == runs);
  CHECK((sanitizer_stride > 1 || runs == states));
  CHECK(centre_checks == m.scene_data().voxel_count() * m.direction_count());
}
}  // namespace

TEST_CASE("surface march: the March gate is a bijection on every basis state of small grids") {
  SUBCASE("2D, 4x4, king moves") { check_march_bijection(qrm::walk_model(room_2d(4), qrm::king_2d(), qrm::march_mode::surface)); }
  SUBCASE("2D, 8x8, king moves") { check_march_bijection(qrm::walk_model(room_2d(8), qrm::king_2d(), qrm::march_mode::surface)); }
  SUBCASE("3D, 4^3, 6 directions, 1 sub-voxel bit (the reset of sub-voxel bits)") {
    qrm::scene s("cube", 3, 4);
    for (unsigned z = 0; z < 4; ++z)
      for (unsigned y = 0; y < 4; ++y)
        for (unsigned x = 0; x < 4; ++x)
          if (x == 0 || y == 0 || z == 0 || x == 3 || y == 3 || z == 3) {
            s.at(x, y, z).kind = qrm::material::boundary;
            s.at(x, y, z).normal = {0, 1, 0};
            s.at(x, y, z).reflectance = {0, 0, 0};
          }
    check_march_bijection(qrm::walk_model(s, qrm::cube_directions(6, 1), qrm::march_mode::surface));
  }
  SUBCASE("3D, 4^3, golden spiral of 6, 2 sub-voxel bits") {
    qrm::scene s("open", 3, 4);
    s.at(2, 2, 2).kind = qrm::material::lambertian;
    s.at(2, 2, 2).normal = {0, 1, 0};
    check_march_bijection(qrm::walk_model(s, qrm::golden_spiral(6, 2), qrm::march_mode::surface));
  }
}

TEST_CASE("surface march: the history variant's P(out = 1) is the classical path sum") {
  auto check = [](const qrm::walk_model& m, const std::vector<qrm::walk_start>& starts, unsigned steps) {
    qrm_test::check_history_equals_path_sum(m, starts, steps, true);
  };
  SUBCASE("2D room, every cell, 3 steps") {
    const qrm::walk_model m(room_2d(8), qrm::king_2d(), qrm::march_mode::surface);
    std::vector<qrm::walk_start> starts;
    for (unsigned y = 0; y < 8; ++y)
      for (unsigned x = 0; x < 8; ++x) starts.push_back(m.light_map_start({x, y, 0}));
    check(m, starts, 3);
  }
  SUBCASE("3D Cornell box 16^3, 14 directions, every start of a 16x16 image, 4 bounces") {
    const qrm::walk_model m(qrm::render::cornell_box(16), qrm::cube_directions(14, 2), qrm::march_mode::surface);
    const auto px = qrm::render::pixel_starts(m, qrm::render::box_scene_camera(16, 16, 16));
    std::set<std::pair<std::size_t, int>> seen;
    std::vector<qrm::walk_start> starts;
    for (const auto& p : px)
      if (p.hit && seen.insert({p.voxel, p.start.direction}).second) starts.push_back(p.start);
    CHECK(starts.size() > 50);
    check(m, starts, 4);
  }
  SUBCASE("3D Cornell box 16^3, 14 directions, 4 bounces, starts drawn from every voxel and direction") {
    // Beyond what a camera sees: any non-air voxel with any incoming direction (facing away from
    // the camera, inside the blocks' walls, into a surface), 400 drawn uniformly from them all.
    const qrm::scene sc = qrm::render::cornell_box(16);
    const qrm::walk_model m(sc, qrm::cube_directions(14, 2), qrm::march_mode::surface);
    std::vector<std::pair<std::size_t, int>> all;
    for (std::size_t i = 0; i < sc.voxel_count(); ++i)
      if (sc[i].kind != qrm::material::air)
        for (int d = 0; d < 14; ++d) all.push_back({i, d});
    CHECK(all.size() > 10000);
    qrm::rng g(7);
    std::vector<qrm::walk_start> starts;
    for (int k = 0; k < 400; ++k) starts.push_back(qrm::detail::render_start_of(sc, all[g.below(all.size())]));
    check(m, starts, 4);
  }
  // Mirrors and glossy surfaces: the coins flow through the model into both the circuit and the
  // path sum (which uses |U_ed|^2 of the same matrices).
  SUBCASE("2D room with a mirror block and a glossy wall cell, every cell, 3 steps") {
    qrm::scene s = room_2d(8);
    s.at(4, 4).kind = qrm::material::specular;
    s.at(4, 4).normal_index = 7;  // NW: a diagonal mirror
    s.at(4, 4).normal = qrm::normalized({-1, -1, 0});
    s.at(7, 3).kind = qrm::material::glossy;  // the right wall, normal W
    s.at(7, 3).lobe = 1.5;
    const qrm::walk_model m(s, qrm::king_2d(), qrm::march_mode::surface);
    CHECK_FALSE(m.coins_are_real());  // the glossy coin is complex
    std::vector<qrm::walk_start> starts;
    for (unsigned y = 0; y < 8; ++y)
      for (unsigned x = 0; x < 8; ++x) starts.push_back(m.light_map_start({x, y, 0}));
    check(m, starts, 3);
  }
  SUBCASE("3D: the mirror and the glossy sphere at 16^3, 14 directions, starts of a 12x12 image") {
    for (const qrm::scene& sc : {qrm::render::cornell_mirror(16), qrm::render::cornell_glossy(16, 1.5)}) {
      CAPTURE(sc.name());
      const qrm::walk_model m(sc, qrm::cube_directions(14, 2), qrm::march_mode::surface);
      const auto px = qrm::render::pixel_starts(m, qrm::render::box_scene_camera(16, 12, 12));
      std::set<std::pair<std::size_t, int>> seen;
      std::vector<qrm::walk_start> starts;
      std::size_t on_sphere = 0;
      for (const auto& p : px)
        if (p.hit && seen.insert({p.voxel, p.start.direction}).second) {
          starts.push_back(p.start);
          on_sphere += sc[p.voxel].kind != qrm::material::lambertian;
        }
      CHECK(on_sphere > 3);
      check(m, starts, 3);
    }
  }
}

TEST_CASE("radiance table: equals the per-start path sum on every start of an image") {
  const std::pair<std::string, qrm::walk_model> cases[] = {
      {"surface, golden 32, F=4",
       qrm::walk_model(qrm::render::cornell_box(16), qrm::golden_spiral(32, 4), qrm::march_mode::surface)},
      {"surface, glossy sphere, golden 32, F=4",
       qrm::walk_model(qrm::render::cornell_glossy(16, 2.0), qrm::golden_spiral(32, 4), qrm::march_mode::surface)},
      {"voxel, cube 26, F=0", qrm::walk_model(qrm::render::two_spheres(16), qrm::cube_directions(26, 0), qrm::march_mode::voxel)}};
  for (const auto& c : cases) {
    const std::string& name = c.first;
    const qrm::walk_model& m = c.second;
    CAPTURE(name);
    REQUIRE(qrm::render::radiance_table::applies(m));
    const qrm::detail::transition_table t(m);
    const qrm::render::radiance_table table(t, 5, 2);
    const auto px = qrm::render::pixel_starts(m, qrm::render::box_scene_camera(16, 24, 24));
    // A start is its voxel and direction, and neighbouring pixels often share one: each distinct
    // start is checked once (the same checks as per pixel, without repeating a path sum).
    std::set<std::pair<std::size_t, int>> seen;
    std::size_t checked = 0;
    for (const auto& p : px) {
      if (!p.hit || !seen.insert({p.voxel, p.start.direction}).second) continue;
      const auto want = qrm::render::path_sum_rgb(t, p.start, 5);
      const auto& got = table.value(p.voxel, static_cast<std::uint32_t>(p.start.direction));
      for (int c = 0; c < 3; ++c) REQUIRE(got[c] == doctest::Approx(want[c]).epsilon(1e-12).scale(1e-300));
      ++checked;
    }
    CHECK(checked > 300);  // 345, 358 and 370 distinct starts
  }
  // Sub-voxel bits with the voxel march leave voxel centres: the table refuses.
  const qrm::walk_model drift(qrm::render::cornell_box(8), qrm::golden_spiral(15, 3), qrm::march_mode::voxel);
  CHECK_FALSE(qrm::render::radiance_table::applies(drift));
  CHECK_THROWS_WITH(qrm::render::radiance_table(qrm::detail::transition_table(drift), 3),
                    doctest::Contains("leaves voxel centres"));
}

TEST_CASE("black stays black: a start whose light arrives only through black surfaces keeps no path term") {
  // Column x = 3 cuts the room; it is black (reflectance 0), and so is the top wall cell (3, 0)
  // next to the light at (4, 0). From the left part the light is reachable in 4 bounces, but
  // only through a black cell, so the value is exactly 0.
  qrm::scene s = room_2d(8);
  for (unsigned y = 0; y < 8; ++y) {
    qrm::voxel& v = s.at(3, y);
    if (y > 0 && y < 7) {
      v.kind = qrm::material::lambertian;
      v.normal_index = 6;
    }
    v.reflectance = {0, 0, 0};
  }
  s.at(4, 4).kind = qrm::material::air;  // the block is not needed
  s.at(4, 0).emission = {4, 3, 2};
  const qrm::walk_model m(s, qrm::king_2d(), qrm::march_mode::surface);
  const qrm::walk_start dark = m.light_map_start({1, 3, 0});
  qrm::walk_options o;
  o.steps = 5;
  for (int c = 0; c < 3; ++c) {
    o.channel = c;
    CHECK(qrm::path_sum(m, dark, 5, c) == 0.0);
    const qrm::walk_program w = qrm::make_walk_program(m, dark, o);
    for (bool kept : w.tables.term_kept) CHECK_FALSE(kept);
    CHECK(qrm::walk_probability<qrm::compact_backend>(w) == 0.0);
    // Scene pruning (no support) keeps terms: the light is reachable, if only through black.
    o.prune = qrm::pruning::scene;
    const qrm::walk_program ws = qrm::make_walk_program(m, dark, o);
    CHECK(std::count(ws.tables.term_kept.begin(), ws.tables.term_kept.end(), true) > 0);
    CHECK(qrm::walk_probability<qrm::compact_backend>(ws) == 0.0);
    o.prune = qrm::pruning::reachable;
  }
  // With grey instead of black cells the same start sees the light: the paths exist, and only
  // the live-support rule (non-zero reflectance all along) drops their terms.
  qrm::scene grey = s;
  for (unsigned y = 0; y < 8; ++y) grey.at(3, y).reflectance = {0.5, 0.5, 0.5};
  CHECK(qrm::path_sum(qrm::walk_model(grey, qrm::king_2d(), qrm::march_mode::surface), dark, 5, 0) > 0.0);
  // A start that sees the light keeps its terms.
  const qrm::walk_program lit = qrm::make_walk_program(m, m.light_map_start({5, 3, 0}), o);
  CHECK(std::count(lit.tables.term_kept.begin(), lit.tables.term_kept.end(), true) > 0);
}

TEST_CASE("scene files: 'march' and 'lambertian' lines, written back by format_scene") {
  const qrm::scene s = qrm::parse_scene(
      "qrm-scene 1\nname m\ndims 2\nsize 4\nmarch surface\nlambertian symmetric\nvoxel 1 1 L 2 rho 0.5 0.5 0.5\n", "m.txt");
  REQUIRE(s.march().has_value());
  CHECK(*s.march() == qrm::march_mode::surface);
  CHECK(s.lambertian_coin() == qrm::lambertian_2d::symmetric);
  const qrm::scene back = qrm::parse_scene(qrm::format_scene(s), "back.txt");
  CHECK(back.march() == s.march());
  CHECK(back.lambertian_coin() == s.lambertian_coin());
  // The model takes both from the scene: the symmetric coin's straight-in column is the cosine lobe.
  const qrm::walk_model m(s, qrm::king_2d());
  CHECK(m.march() == qrm::march_mode::surface);
  const auto out = m.scatter(s.index(1, 1), 6);  // normal 2 (E): straight in is 6 (W)
  REQUIRE(out.size() == 3);
  for (const auto& [d, a] : out) CHECK(std::norm(a) == doctest::Approx(d == 2 ? std::sqrt(2.0) - 1 : 1 - 1 / std::sqrt(2.0)));
  const qrm::scene plain = qrm::parse_scene("qrm-scene 1\ndims 2\nsize 4\n", "p.txt");
  CHECK_FALSE(plain.march().has_value());
  CHECK(plain.lambertian_coin() == qrm::lambertian_2d::paper);
  CHECK(qrm::format_scene(plain).find("march") == std::string::npos);
  CHECK_THROWS_WITH(qrm::parse_scene("qrm-scene 1\ndims 2\nsize 4\nmarch voxel\nmarch surface\n", "twice.txt"),
                    doctest::Contains("twice.txt:5: 'march' given twice"));
  CHECK_THROWS_WITH(qrm::parse_scene("qrm-scene 1\ndims 2\nsize 4\nlambertian round\n", "bad.txt"),
                    doctest::Contains("bad.txt:4: expected 'lambertian paper' or 'lambertian symmetric'"));
}
