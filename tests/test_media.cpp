// Participating media: the medium coin's unitarity and transition probabilities on every direction
// set, the march through fog, the history walk against the classical path sum, the radiance
// table, scene files with medium voxels, and cornell_fog's density scaling.
#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/walk/coins.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/scene_format.hpp>

#include "support/history_check.hpp"

namespace {

// Coin entries are one square root and one product each, so unitarity and |U|^2 hold to ~1e-15
// (measured: at most 2e-15 for D = 64); 1e-12 is the issue's bar.
constexpr double tol = 1e-12;

struct named_set {
  std::string name;
  qrm::direction_set set;
};
std::vector<named_set> all_sets() {
  return {{"cube-6", qrm::cube_directions(6, 2)},        {"cube-14", qrm::cube_directions(14, 2)},
          {"cube-26", qrm::cube_directions(26, 2)},      {"golden-15", qrm::golden_spiral(15, 3)},
          {"golden-32", qrm::golden_spiral(32, 4)},      {"golden-64", qrm::golden_spiral(64, 4)},
          {"antipodal-32", qrm::antipodal_spiral(32, 4)}, {"antipodal-64", qrm::antipodal_spiral(64, 4)},
          {"king-8", qrm::king_2d()}};
}

std::string error_of(auto&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

// An N x N 2D room (boundary corners, Lambertian walls facing in, a light in the top wall) with a
// medium region of the given density in its lower half.
qrm::scene fog_room_2d(unsigned n, double density) {
  qrm::scene s("fog_room", 2, n);
  for (unsigned y = 0; y < n; ++y)
    for (unsigned x = 0; x < n; ++x) {
      qrm::voxel& v = s.at(x, y);
      const bool edge = x == 0 || y == 0 || x == n - 1 || y == n - 1;
      if (!edge) {
        if (y >= n / 2) {
          v.kind = qrm::material::medium;
          v.density = density;
          v.reflectance = {0.95, 0.9, 0.85};
        }
        continue;
      }
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
  return s;
}

}  // namespace

TEST_CASE("medium coin: unitary, straight on with 1 - density, isotropic elsewhere, on every direction set") {
  std::size_t coins = 0;
  for (const named_set& ns : all_sets()) {
    const qrm::direction_set& s = ns.set;
    const std::size_t D = s.size();
    for (double p : {0.0, 0.1, 0.5, 1.0}) {
      INFO(ns.name << " density " << p);
      if (p > qrm::medium_isotropic_limit(D)) {
        // Odd D (golden-15): no conference matrix; the I + beta J coin stops at 4 (D - 1) / D^2.
        CHECK(D % 2 == 1);
        CHECK_THROWS_WITH(qrm::medium_coin(s, p), doctest::Contains("the most this isotropic coin reaches on 15 directions"));
        continue;
      }
      const qrm::dense_matrix u = qrm::medium_coin(s, p);
      REQUIRE(qrm::unitarity_error(u) < tol);
      for (std::size_t d = 0; d < u.dim; ++d)
        for (std::size_t e = 0; e < u.dim; ++e) {
          const double want = d >= D || e >= D ? (e == d ? 1.0 : 0.0) : e == d ? 1.0 - p : p / static_cast<double>(D - 1);
          REQUIRE(std::abs(std::norm(u(e, d)) - want) < tol);
        }
      if (p == 0.0) CHECK(u.data == qrm::dense_matrix::identity(u.dim).data);  // air, exactly
      // Real (so real backends run fog) where the conference matrix is antisymmetric.
      if (D == 8 || D == 32 || D == 64) CHECK(u.is_real());
      ++coins;
    }
    // At its limit the odd-D coin is still exact.
    const double limit = qrm::medium_isotropic_limit(D);
    if (limit < 1.0) {
      const qrm::dense_matrix u = qrm::medium_coin(s, limit);
      CHECK(qrm::unitarity_error(u) < tol);
      CHECK(std::abs(std::norm(u(0, 0)) - (1.0 - limit)) < tol);
      CHECK(std::abs(std::norm(u(1, 0)) - limit / static_cast<double>(D - 1)) < tol);
    }
  }
  MESSAGE(coins << " medium coins checked");
  CHECK(qrm::medium_isotropic_limit(15) == doctest::Approx(4.0 * 14 / 225));
  for (std::size_t D : {6u, 8u, 14u, 26u, 32u, 64u}) CHECK(qrm::medium_isotropic_limit(D) == 1.0);
  CHECK_THROWS_WITH(qrm::medium_coin(qrm::cube_directions(14, 2), 1.5), doctest::Contains("got 1.5"));
  CHECK_THROWS_WITH(qrm::medium_coin(qrm::cube_directions(14, 2), std::nan("")), doctest::Contains("got nan"));
}

TEST_CASE("conference matrices: C C^T = (n - 1) I with zero diagonal, for the orders the coin uses") {
  // Independent of make_conference_matrix's own check: recomputed here.
  for (std::size_t n : {6u, 8u, 14u, 26u, 32u, 64u, 10u, 12u, 16u, 18u}) {
    CAPTURE(n);
    const auto c = qrm::detail::make_conference_matrix(n);
    REQUIRE(c.n == n);
    CHECK(c.symmetric == (n % 4 == 2));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        long s = 0;
        for (std::size_t k = 0; k < n; ++k) s += long{c.c[i * n + k]} * c.c[j * n + k];
        REQUIRE(s == (i == j ? static_cast<long>(n - 1) : 0L));
        REQUIRE(std::abs(c.c[i * n + j]) == (i == j ? 0 : 1));
      }
  }
  CHECK(qrm::detail::make_conference_matrix(15).n == 0);
}

TEST_CASE("surface march through fog: one voxel per step, straight on with probability 1 - density") {
  // A 3D corridor of fog along +x: from each fog voxel's centre the walker moving along +x
  // lands in the next voxel (distance 1), so crossing k fog voxels takes k steps.
  qrm::scene s("corridor", 3, 8);
  for (unsigned x = 1; x < 7; ++x) {
    s.at(x, 3, 3).kind = qrm::material::medium;
    s.at(x, 3, 3).density = 0.25;
    s.at(x, 3, 3).reflectance = {0.5, 0.5, 0.5};
  }
  // Black at the corridor's -x end: a walker scattered back would otherwise wrap around the grid
  // onto the light's back. (Sideways it marches through air around the grid back to its voxel.)
  s.at(0, 3, 3).kind = qrm::material::boundary;
  s.at(0, 3, 3).normal = {1, 0, 0};
  s.at(0, 3, 3).reflectance = {0, 0, 0};
  s.at(7, 3, 3).kind = qrm::material::lambertian;
  s.at(7, 3, 3).normal = {-1, 0, 0};
  s.at(7, 3, 3).emission = {1, 1, 1};
  s.at(7, 3, 3).reflectance = {0, 0, 0};
  const qrm::walk_model m(s, qrm::cube_directions(6, 2), qrm::march_mode::surface);
  const std::uint32_t east = m.nearest_direction({1, 0, 0});
  for (unsigned x = 1; x < 7; ++x) {
    const auto mv = m.moved_by(m.centre_of({x, 3, 3}), east);
    CHECK(mv.distance == 1);
    CHECK(m.voxel_of(mv.pos) == s.index(x + 1, 3, 3));
  }
  // Transmittance: from voxel 1 in +x, the light (k = 6 voxels on) arrives at exactly step 6
  // only along the straight path, (1 - p)^6 of the walkers, each keeping rho^5 (five fog voxels
  // after the start). Beer-Lambert on the discrete medium.
  const qrm::walk_start st{{1, 3, 3}, static_cast<int>(east)};
  const double want = std::pow(0.75, 6) * std::pow(0.5, 5);
  CHECK(qrm::path_sum(m, st, 6, 0) == doctest::Approx(want).epsilon(1e-14));
  CHECK(qrm::path_sum(m, st, 5, 0) == 0.0);  // five steps never reach it
}

TEST_CASE("media: the history variant's P(out = 1) is the classical path sum") {
  auto check = [](const qrm::walk_model& m, const std::vector<qrm::walk_start>& starts, unsigned steps) {
    qrm_test::check_history_equals_path_sum(m, starts, steps);
  };
  SUBCASE("2D room with a fog region (lower half), every cell, 3 steps") {
    for (double p : {0.3, 1.0}) {
      CAPTURE(p);
      const qrm::walk_model m(fog_room_2d(8, p), qrm::king_2d(), qrm::march_mode::surface);
      std::vector<qrm::walk_start> starts;
      for (unsigned y = 0; y < 8; ++y)
        for (unsigned x = 0; x < 8; ++x) starts.push_back(m.light_map_start({x, y, 0}));
      check(m, starts, 3);
      // The path sum by explicit enumeration agrees (a different summation).
      for (int c = 0; c < 3; ++c)
        CHECK(qrm::path_sum_enumerated(m, starts[45], 3, c) ==
              doctest::Approx(qrm::path_sum(m, starts[45], 3, c)).epsilon(1e-12));
    }
  }
  SUBCASE("3D cornell_fog 8^3, 14 directions (complex coin), every start of an 8x8 image, 3 steps") {
    const qrm::walk_model m(qrm::render::cornell_fog(8, 0.3), qrm::cube_directions(14, 2), qrm::march_mode::surface);
    CHECK_FALSE(m.coins_are_real());
    const auto px = qrm::render::pixel_starts(m, qrm::render::box_scene_camera(8, 8, 8));
    std::set<std::pair<std::size_t, int>> seen;
    std::vector<qrm::walk_start> starts;
    std::size_t in_fog = 0;
    for (const auto& p : px)
      if (p.hit && seen.insert({p.voxel, p.start.direction}).second) {
        starts.push_back(p.start);
        in_fog += m.scene_data()[p.voxel].kind == qrm::material::medium;
      }
    CHECK(in_fog > 3);
    check(m, starts, 3);
  }
}

TEST_CASE("radiance table and Monte Carlo on cornell_fog: the same transitions as the path sum") {
  const qrm::walk_model m(qrm::render::cornell_fog(16), qrm::golden_spiral(32, 4), qrm::march_mode::surface);
  const qrm::detail::transition_table t(m);
  const qrm::render::radiance_table table(t, 4, 2);
  const auto px = qrm::render::pixel_starts(m, qrm::render::box_scene_camera(16, 10, 10));
  std::size_t checked = 0;
  for (const auto& p : px) {
    if (!p.hit) continue;
    const auto want = qrm::render::path_sum_rgb(t, p.start, 4);
    const auto& got = table.value(p.voxel, static_cast<std::uint32_t>(p.start.direction));
    for (int c = 0; c < 3; ++c) REQUIRE(got[c] == doctest::Approx(want[c]).epsilon(1e-12).scale(1e-300));
    ++checked;
  }
  CHECK(checked > 80);
  // Monte Carlo from a fog start: within 5 standard errors of the exact mean (a 5-sigma band
  // fails by chance with probability 6e-7).
  const qrm::walk_start st = m.light_map_start({8, 12, 8});  // above both blocks
  REQUIRE(m.scene_data().at(8, 12, 8).kind == qrm::material::medium);
  qrm::rng g(18);
  const auto mc = qrm::monte_carlo(m, st, 4, 0, 50000, g);
  const double exact = qrm::path_sum(m, st, 4, 0);
  CHECK(exact > 0);
  CHECK(std::abs(mc.mean - exact) < 5 * mc.standard_error);
}

TEST_CASE("cornell_fog: fog in the room's air, density scaled to keep the optical depth") {
  const qrm::scene s8 = qrm::render::cornell_fog(8), box8 = qrm::render::cornell_box(8);
  std::size_t fog = 0;
  for (std::size_t i = 0; i < s8.voxel_count(); ++i) {
    if (s8[i].kind == qrm::material::medium) {
      ++fog;
      CHECK(box8[i].kind == qrm::material::air);  // only air becomes fog
      const auto c = s8.coords(i);
      for (unsigned a : c) CHECK((a >= 2 && a <= 5));
      CHECK(s8[i].density == doctest::Approx(0.1));
    } else {
      CHECK(s8[i] == box8[i]);  // everything else is the Cornell box
    }
  }
  CHECK(fog > 30);
  // Crossing the room (N - 3 voxel lengths) unscattered: 0.9^5 at every size.
  for (unsigned n : {8u, 16u, 32u, 64u}) {
    CAPTURE(n);
    const double p = qrm::render::fog_density_at(n, 0.1);
    CHECK(std::pow(1.0 - p, n - 3.0) == doctest::Approx(std::pow(0.9, 5)).epsilon(1e-12));
    const qrm::rgb r = qrm::render::fog_reflectance_at(n, {0.98, 0.5, 1.0});
    CHECK(std::pow(r.g, n - 3.0) == doctest::Approx(std::pow(0.5, 5)).epsilon(1e-12));
    CHECK(r.b == 1.0);
  }
  CHECK(qrm::render::cornell_fog(32).at(16, 24, 16).density == doctest::Approx(qrm::render::fog_density_at(32, 0.1)));
}

TEST_CASE("medium voxels in scene files: kind M with 'density P', written back exactly, bad values refused") {
  const qrm::scene s = qrm::parse_scene(
      "qrm-scene 1\ndims 3\nsize 4\nfill 1 1 1 2 2 2 M density 0.125 rho 0.9 0.8 0.7\nvoxel 3 3 3 medium density 1 rho 1 1 1 "
      "le 0.5 0.5 0.5\nvoxel 0 0 0 L 0 1 0 rho 0.5 0.5 0.5\n",
      "m.txt");
  CHECK(s.at(1, 2, 1).kind == qrm::material::medium);
  CHECK(s.at(1, 2, 1).density == 0.125);
  CHECK(s.at(1, 2, 1).reflectance == qrm::rgb{0.9, 0.8, 0.7});
  CHECK(s.at(3, 3, 3).emission == qrm::rgb{0.5, 0.5, 0.5});
  CHECK(s.at(0, 0, 0).density == 0.0);
  const std::string text = qrm::format_scene(s);
  CHECK(text.find("voxel 1 1 1 M density 0.125 rho 0.90000000000000002") != std::string::npos);
  CHECK(qrm::parse_scene(text, "again").voxels() == s.voxels());
  const std::string header2d = "qrm-scene 1\ndims 2\nsize 4\ncolor w 1 1 1\n";
  const qrm::scene s2 = qrm::parse_scene(header2d + "fill 1 1 2 2 M density 0.5 rho w\n", "m2.txt");
  CHECK(s2.at(2, 2).density == 0.5);
  CHECK(qrm::parse_scene(qrm::format_scene(s2), "again").voxels() == s2.voxels());
  // A medium start in a 2D light map: every direction (no normal).
  CHECK(qrm::walk_model(s2, qrm::king_2d()).light_map_start({1, 1, 0}).direction == -1);
  auto err = [](const std::string& t) { return error_of([&] { qrm::parse_scene(t, "s.txt"); }); };
  const std::string head3 = "qrm-scene 1\ndims 3\nsize 4\n";
  CHECK(err(head3 + "voxel 1 1 1 M density 1.5 rho 1 1 1\n") ==
        "s.txt:4: density 1.5 outside [0, 1] (the probability of scattering per voxel crossed)");
  CHECK(err(head3 + "voxel 1 1 1 M density -0.1 rho 1 1 1\n") ==
        "s.txt:4: density -0.1 outside [0, 1] (the probability of scattering per voxel crossed)");
  CHECK(err(head3 + "voxel 1 1 1 M density nan rho 1 1 1\n") == "s.txt:4: density: nan is not finite");
  CHECK(err(head3 + "voxel 1 1 1 M density\n") == "s.txt:4: 'density' needs a number in [0, 1]");
  CHECK(err(head3 + "voxel 1 1 1 M rho 1 1 1\n") ==
        "s.txt:4: a medium voxel needs 'density P' (P in [0, 1]: the probability of scattering per voxel crossed)");
  CHECK(err(head3 + "voxel 1 1 1 M density 0.5\n") == "s.txt:4: a medium voxel needs 'rho C'");
  CHECK(err(head3 + "voxel 1 1 1 M density 0.5 rho 1.2 1 1\n") == "s.txt:4: reflectance 1.200000 outside [0, 1] in channel R");
  CHECK(err(head3 + "voxel 1 1 1 L 0 1 0 density 0.5 rho 1 1 1\n") ==
        "s.txt:4: 'density' is a medium's scattering probability; a lambertian voxel has none");
  CHECK(err(header2d + "kinds\n. M . .\n") ==
        "s.txt:6: medium cell 'M' at x = 1: a grid cell has no room for the density; use a line 'voxel X Y M density P rho C'");
  // Scenes built in code are checked too (walk_model validates).
  qrm::scene bad("bad", 3, 4);
  bad.at(1, 1, 1).kind = qrm::material::medium;
  bad.at(1, 1, 1).density = 2;
  CHECK(error_of([&] { bad.validate(); }) ==
        "scene 'bad': voxel (1, 1, 1): density 2.000000 outside [0, 1] (the medium's scattering probability)");
  bad.at(1, 1, 1).kind = qrm::material::air;
  bad.at(1, 1, 1).density = 0.5;
  CHECK(error_of([&] { bad.validate(); }) ==
        "scene 'bad': voxel (1, 1, 1): density 0.500000 on a voxel of kind air (only medium voxels have a density)");
  // golden-15 and a density above its isotropic limit: refused when the walk is made.
  qrm::scene dense("dense", 3, 8);
  dense.at(3, 3, 3).kind = qrm::material::medium;
  dense.at(3, 3, 3).density = 0.5;
  CHECK(error_of([&] { qrm::walk_model(dense, qrm::golden_spiral(15, 3)); }).find("use an even set") != std::string::npos);
}
