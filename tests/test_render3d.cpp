// 3D rendering on the walk's discretization: voxelized scenes checked against their published
// geometry, the DDA against a brute-force traversal, camera rays, exact images against a naive
// per-pixel path enumeration, Monte Carlo convergence at the rate its own statistics predict,
// the emulator's path enumeration and sampling, and bit-identical results across thread counts
// and tiles.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <qrm/walk/classical.hpp>
#include <qrm/render/camera.hpp>
#include <qrm/render/dda.hpp>
#include <qrm/render/tiles.hpp>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <vector>

namespace {

namespace r = qrm::render;
using qrm::vec3;

vec3 centre_of(const std::array<unsigned, 3>& v) {
  return {v[0] + 0.5, v[1] + 0.5, v[2] + 0.5};
}
vec3 sub(const vec3& a, const vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
bool near_vec(const vec3& a, const vec3& b, double tol) {
  return qrm::norm(sub(a, b)) <= tol;
}
bool same_bits(const r::image& a, const r::image& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(qrm::io::rgb)) == 0;
}

// Cornell millimetres to voxel coordinates, as documented for cornell_box(N) / two_spheres(N):
// the room's inside [0, 550] mm spans [1.5, N - 1.5].
double mm(unsigned n, double x) {
  return 1.5 + (n - 3.0) / 550.0 * x;
}

// Signed distance (voxel units) from p to a block: a prism over the published top-face quad
// (corners in millimetres, convex) from the floor plane up to `height` mm.
double block_sdf(unsigned n, const std::array<std::array<double, 2>, 4>& quad_mm, double height_mm, const vec3& p) {
  std::array<std::array<double, 2>, 4> q{};
  for (int i = 0; i < 4; ++i) q[i] = {mm(n, quad_mm[i][0]), mm(n, quad_mm[i][1])};
  // 2D signed distance to a convex quad: outside = distance to the polygon, inside = -min edge distance.
  double inside_margin = std::numeric_limits<double>::infinity(), outside = std::numeric_limits<double>::infinity();
  bool inside = true;
  // Orientation of the quad.
  const double area = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]);
  for (int i = 0; i < 4; ++i) {
    const auto& a = q[i];
    const auto& b = q[(i + 1) % 4];
    const double ex = b[0] - a[0], ez = b[1] - a[1], len = std::hypot(ex, ez);
    const double px = p[0] - a[0], pz = p[2] - a[1];
    const double side = (ex * pz - ez * px) / len * (area > 0 ? 1 : -1);  // > 0 inside
    if (side < 0) inside = false;
    inside_margin = std::min(inside_margin, side);
    const double t = std::clamp((px * ex + pz * ez) / (len * len), 0.0, 1.0);
    outside = std::min(outside, std::hypot(px - t * ex, pz - t * ez));
  }
  const double d2 = inside ? -inside_margin : outside;
  const double y0 = mm(n, 0), y1 = mm(n, height_mm);
  const double dy = std::abs(p[1] - (y0 + y1) / 2) - (y1 - y0) / 2;
  return std::min(std::max(d2, dy), 0.0) + std::hypot(std::max(d2, 0.0), std::max(dy, 0.0));
}

const std::array<std::array<double, 2>, 4> short_block_mm{{{130, 65}, {82, 225}, {240, 272}, {290, 114}}};
const std::array<std::array<double, 2>, 4> tall_block_mm{{{423, 247}, {265, 296}, {314, 456}, {472, 406}}};

// ------------------------------------------------------------------------------------------
// Brute-force traversal: for every voxel, the ray parameters t >= 0 at which floor(o + t d) is
// that voxel (an interval per axis, intersected); the first hit is the stopping voxel with a
// positive-length interval that starts first.
struct brute_hit {
  bool hit = false;
  std::array<unsigned, 3> voxel{0, 0, 0};
  double t = 0;
};
brute_hit brute_first_hit(const qrm::scene& s, const vec3& o, const vec3& d, bool stop_boundary) {
  brute_hit best;
  best.t = std::numeric_limits<double>::infinity();
  const unsigned n = s.size();
  for (unsigned z = 0; z < n; ++z)
    for (unsigned y = 0; y < n; ++y)
      for (unsigned x = 0; x < n; ++x) {
        const qrm::material k = s.at(x, y, z).kind;
        if (k == qrm::material::air || (k == qrm::material::boundary && !stop_boundary)) continue;
        const unsigned v[3] = {x, y, z};
        double lo = 0, hi = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
          if (d[a] == 0) {
            if (!(o[a] >= v[a] && o[a] < v[a] + 1.0)) hi = -1;
            continue;
          }
          const double enter = ((d[a] > 0 ? v[a] : v[a] + 1.0) - o[a]) / d[a];
          const double leave = ((d[a] > 0 ? v[a] + 1.0 : v[a]) - o[a]) / d[a];
          lo = std::max(lo, enter);
          hi = std::min(hi, leave);
        }
        if (hi > lo && lo < best.t) {
          best.hit = true;
          best.voxel = {x, y, z};
          best.t = lo;
        }
      }
  return best;
}

// ------------------------------------------------------------------------------------------
// Naive path enumeration from the definition (Eq. 14), through walk_model::scatter: every path
// with its probability and f, per channel.
struct naive_path {
  double p;
  std::array<double, 3> f;
};
std::vector<naive_path> naive_paths(const qrm::walk_model& m, const qrm::walk_start& start, unsigned steps) {
  std::vector<naive_path> out;
  auto rec = [&](auto&& self, const qrm::walk_state& w, unsigned i, double p, std::array<double, 3> prefix,
                 std::array<double, 3> f) -> void {
    if (i == steps) {
      out.push_back({p, f});
      return;
    }
    for (const auto& [d, amp] : m.scatter(m.voxel_of(w.pos), w.dir)) {
      const qrm::walk_state nw{m.shifted(w.pos, d), d};
      const std::size_t v = m.voxel_of(nw.pos);
      auto nf = f, np = prefix;
      for (int c = 0; c < 3; ++c) {
        nf[c] += prefix[c] * m.emission(v, c);
        np[c] *= m.reflectance(v, c);
      }
      self(self, nw, i + 1, p * std::norm(amp), np, nf);
    }
  };
  for (const auto& [w, a] : m.initial_states(start)) rec(rec, w, 0, std::norm(a), {1, 1, 1}, {0, 0, 0});
  return out;
}

struct f_moments {
  std::array<double, 3> mean{}, var{}, m4{};  // E f, central 2nd and 4th moments
};
f_moments moments_of(const std::vector<naive_path>& paths) {
  f_moments r;
  for (const auto& q : paths)
    for (int c = 0; c < 3; ++c) r.mean[c] += q.p * q.f[c];
  for (const auto& q : paths)
    for (int c = 0; c < 3; ++c) {
      const double e = q.f[c] - r.mean[c];
      r.var[c] += q.p * e * e;
      r.m4[c] += q.p * e * e * e * e;
    }
  return r;
}

// Radiance of a pixel from the definition: Le + rho * E[f] at the ray's first hit.
std::array<double, 3> reference_pixel(const qrm::walk_model& m, const r::camera& cam, unsigned px, unsigned py,
                                      unsigned steps, f_moments* mom = nullptr, double* rho = nullptr) {
  const auto ray = cam.ray(px, py);
  const auto h = r::first_hit(m.scene_data(), ray.origin, ray.direction);
  if (!h) return {0, 0, 0};
  const auto start = r::hit_walk_start(m, h, ray.direction);
  const f_moments mo = moments_of(naive_paths(m, start, steps));
  if (mom) *mom = mo;
  const qrm::voxel& v = m.scene_data()[h.index];
  if (rho)
    for (int c = 0; c < 3; ++c) rho[c] = v.reflectance[c];
  return {v.emission[0] + v.reflectance[0] * mo.mean[0], v.emission[1] + v.reflectance[1] * mo.mean[1],
          v.emission[2] + v.reflectance[2] * mo.mean[2]};
}

qrm::walk_model small_cornell_model() {
  return qrm::walk_model(r::cornell_box(8), qrm::golden_spiral(15, 3));
}

}  // namespace

// ============================================================================================
TEST_CASE("Cornell box: walls, shell, light and blocks are where the published data puts them") {
  for (unsigned n : {16u, 32u}) {
    CAPTURE(n);
    const qrm::scene sc = r::cornell_box(n);
    CHECK(sc.dims() == 3);
    CHECK(sc.size() == n);
    // Shell: the outermost layer absorbs.
    for (unsigned a = 0; a < n; ++a)
      for (unsigned b = 0; b < n; ++b)
        for (const auto& xyz : std::array<std::array<unsigned, 3>, 6>{
                 {{0, a, b}, {n - 1, a, b}, {a, 0, b}, {a, n - 1, b}, {a, b, 0}, {a, b, n - 1}}}) {
          const qrm::voxel& v = sc.at(xyz[0], xyz[1], xyz[2]);
          REQUIRE(v.kind == qrm::material::boundary);
          CHECK(v.reflectance == qrm::rgb{0, 0, 0});
          CHECK(v.emission == qrm::rgb{0, 0, 0});
        }
    // Walls (away from their edges): right (green) at x = 1, left (red) at x = N - 2, floor
    // y = 1, ceiling y = N - 2, back z = N - 2; normals facing into the room.
    for (unsigned a = 2; a + 2 < n; ++a)
      for (unsigned b = 2; b + 2 < n; ++b) {
        const qrm::voxel& green = sc.at(1, a, b);
        const qrm::voxel& red = sc.at(n - 2, a, b);
        const qrm::voxel& floor = sc.at(a, 1, b);
        const qrm::voxel& ceiling = sc.at(a, n - 2, b);
        const qrm::voxel& back = sc.at(a, b, n - 2);
        for (const qrm::voxel* v : {&green, &red, &floor, &ceiling, &back})
          REQUIRE(v->kind == qrm::material::lambertian);
        CHECK(green.normal == vec3{1, 0, 0});
        CHECK(green.reflectance == r::cornell_green);
        CHECK(red.normal == vec3{-1, 0, 0});
        CHECK(red.reflectance == r::cornell_red);
        CHECK(floor.normal == vec3{0, 1, 0});
        CHECK(floor.reflectance == r::cornell_white);
        CHECK(ceiling.normal == vec3{0, -1, 0});
        CHECK(ceiling.reflectance == r::cornell_white);
        CHECK(back.normal == vec3{0, 0, -1});
        CHECK(back.reflectance == r::cornell_white);
      }
    // An edge voxel averages its two walls' normals; the open front has no wall.
    const qrm::voxel& edge = sc.at(1, 1, n / 2);
    CHECK(near_vec(edge.normal, qrm::normalized({1, 1, 0}), 1e-12));
    CHECK(edge.reflectance == r::cornell_green);  // coloured walls were added first
    CHECK(sc.at(n / 2, n - 4, 1).kind == qrm::material::air);
    // The light: ceiling voxels only, emission (17, 12, 4), centred on the published light
    // (130 x 105 mm around (278, 279.5) mm), as many voxels as its area allows.
    std::size_t lights = 0;
    double cx = 0, cz = 0;
    for (std::size_t i = 0; i < sc.voxel_count(); ++i) {
      const qrm::voxel& v = sc[i];
      if (v.emission == qrm::rgb{0, 0, 0}) continue;
      const auto xyz = sc.coords(i);
      CHECK(xyz[1] == n - 2);
      CHECK(v.normal == vec3{0, -1, 0});
      CHECK(v.emission == qrm::rgb{17, 12, 4});
      ++lights;
      cx += xyz[0] + 0.5;
      cz += xyz[2] + 0.5;
    }
    REQUIRE(lights > 0);
    // A centred a x b rectangle covers between (a - 1)(b - 1) and (a + 1)(b + 1) voxel centres,
    // and their mean lies within half a voxel of its centre.
    const double a = mm(n, 343) - mm(n, 213), b = mm(n, 332) - mm(n, 227);
    CHECK(static_cast<double>(lights) >= (a - 1) * (b - 1));
    CHECK(static_cast<double>(lights) <= (a + 1) * (b + 1));
    CHECK(std::abs(cx / lights - mm(n, 278)) <= 0.5);
    CHECK(std::abs(cz / lights - mm(n, 279.5)) <= 0.5);
    // Blocks: every voxel inside the room that is not air lies on a block's surface (its centre
    // within half a voxel diagonal, plus 0.15 voxel for the fitted box's deviation from the
    // published corners), its normal points away from the block's axis, and every voxel whose
    // centre is within 0.35 voxel of a block surface (so the surface meets it) is not air.
    std::size_t block_voxels = 0;
    for (unsigned z = 2; z + 2 < n; ++z)
      for (unsigned y = 2; y + 2 < n; ++y)
        for (unsigned x = 2; x + 2 < n; ++x) {
          const vec3 c = centre_of({x, y, z});
          const double ds = block_sdf(n, short_block_mm, 165, c), dt = block_sdf(n, tall_block_mm, 330, c);
          const qrm::voxel& v = sc.at(x, y, z);
          if (std::min(std::abs(ds), std::abs(dt)) < 0.35) CHECK(v.kind != qrm::material::air);
          if (v.kind == qrm::material::air) continue;
          ++block_voxels;
          CHECK(std::min(std::abs(ds), std::abs(dt)) <= std::sqrt(3.0) / 2 + 0.15);
          const bool is_short = std::abs(ds) < std::abs(dt);
          const auto& quad = is_short ? short_block_mm : tall_block_mm;
          const double ax = mm(n, (quad[0][0] + quad[1][0] + quad[2][0] + quad[3][0]) / 4);
          const double az = mm(n, (quad[0][1] + quad[1][1] + quad[2][1] + quad[3][1]) / 4);
          const double h = mm(n, is_short ? 165 : 330);
          // Outward: horizontally away from the axis, or up at the top.
          CHECK(v.normal[0] * (c[0] - ax) + v.normal[2] * (c[2] - az) + v.normal[1] * (c[1] > h - 1 ? 1 : 0) > 0);
          CHECK(v.reflectance == r::cornell_white);
        }
    CHECK(block_voxels > 20);
    // The blocks keep their published rotation: some side voxels have exactly the normals of
    // the published faces (the short block's edge from (130, 65) to (82, 225) has outward
    // normal (-160, 0, -48) / |.|).
    const vec3 published = qrm::normalized({-160, 0, -48});
    bool found = false;
    for (const qrm::voxel& v : sc.voxels()) found = found || near_vec(v.normal, published, 0.02);
    CHECK(found);
  }
}

TEST_CASE("two spheres: sphere voxels hug the spheres, with outward normals") {
  for (unsigned n : {16u, 32u}) {
    CAPTURE(n);
    const qrm::scene sc = r::two_spheres(n);
    const double k = (n - 3.0) / 550.0;
    struct ball {
      vec3 c;
      double r;
      qrm::rgb colour;
    };
    const ball balls[2] = {{{mm(n, 385), mm(n, 110), mm(n, 330)}, 110 * k, {0.2, 0.35, 0.75}},
                           {{mm(n, 160), mm(n, 70), mm(n, 200)}, 70 * k, {0.8, 0.45, 0.15}}};
    for (const ball& b : balls) {
      std::size_t count = 0;
      for (std::size_t i = 0; i < sc.voxel_count(); ++i) {
        const auto xyz = sc.coords(i);
        const vec3 c = centre_of(xyz);
        const double dist = qrm::norm(sub(c, b.c)) - b.r;
        const qrm::voxel& v = sc[i];
        if (xyz[1] >= 2 && std::abs(dist) < 0.5) CHECK(v.kind != qrm::material::air);  // surface inside the cube
        if (!(v.reflectance == b.colour)) continue;
        ++count;
        CHECK(std::abs(dist) <= std::sqrt(3.0) / 2 + 1e-12);  // the surface meets the cube
        CHECK(qrm::dot(v.normal, sub(c, b.c)) > 0);
        CHECK(near_vec(v.normal, qrm::normalized(sub(c, b.c)), 1e-12));
      }
      // Surface voxels of a sphere: about its area (4 pi r^2) and at least a third of it.
      CHECK(static_cast<double>(count) > 4 * std::numbers::pi * b.r * b.r / 3);
    }
    // Light: on the ceiling, emission 10.
    std::size_t lights = 0;
    for (std::size_t i = 0; i < sc.voxel_count(); ++i)
      if (sc[i].emission.r > 0) {
        ++lights;
        CHECK(sc.coords(i)[1] == n - 2);
        CHECK(sc[i].emission == qrm::rgb{10, 10, 10});
      }
    CHECK(lights > 0);
  }
}

TEST_CASE("voxelizer: rejects bad input, closes the grid, averages box edges") {
  CHECK_THROWS_AS(r::voxelizer(12), std::invalid_argument);
  CHECK_THROWS_AS(r::voxelizer(2), std::invalid_argument);
  CHECK_THROWS_AS(r::cornell_box(4), std::invalid_argument);
  r::voxelizer vx(8);
  r::rectangle bad;
  bad.u = {2, 0, 0};
  bad.half_u = bad.half_v = 1;
  CHECK_THROWS_AS(vx.add_rectangle(bad, {}), std::invalid_argument);
  CHECK_THROWS_AS(vx.add_sphere({{4, 4, 4}, 0.0}, {}), std::invalid_argument);
  // A box exactly on voxel centres: its faces are single voxel layers; edges get averaged normals.
  r::oriented_box b;
  b.centre = {4, 4, 4};
  b.half = {1.5, 1.5, 1.5};  // faces at 2.5 and 5.5: through the centres of layers 2 and 5
  vx.add_box(b, r::surface_material{});
  const qrm::scene sc = vx.build("box");
  CHECK(sc.at(2, 3, 4).normal == vec3{-1, 0, 0});
  CHECK(sc.at(5, 4, 3).normal == vec3{1, 0, 0});
  CHECK(near_vec(sc.at(5, 5, 4).normal, qrm::normalized({1, 1, 0}), 1e-12));
  CHECK(near_vec(sc.at(2, 2, 2).normal, qrm::normalized({-1, -1, -1}), 1e-12));
  CHECK(sc.at(3, 3, 3).kind == qrm::material::air);  // hollow
  CHECK(sc.at(1, 4, 4).kind == qrm::material::air);
  CHECK(sc.at(0, 4, 4).kind == qrm::material::boundary);
  // A surface reaching the outer layer is refused when the shell is asked for.
  r::voxelizer big(8);
  big.add_sphere({{4, 4, 4}, 3.4}, {});
  CHECK_THROWS_AS(big.build("too big"), std::invalid_argument);
  CHECK_NOTHROW(big.build("open", false));
}

// ============================================================================================
TEST_CASE("DDA first hit equals brute-force traversal, including axis rays and edge/corner crossings") {
  qrm::rng g(20240611);
  for (int trial = 0; trial < 6; ++trial) {
    qrm::scene sc("random", 3, 8);
    for (std::size_t i = 0; i < sc.voxel_count(); ++i) {
      const double u = g.uniform();
      if (u < 0.04) {
        sc[i].kind = qrm::material::lambertian;
        sc[i].normal = {0, 1, 0};
      } else if (u < 0.06) {
        sc[i].kind = qrm::material::boundary;
        sc[i].normal = {0, 1, 0};
      }
    }
    std::vector<std::pair<vec3, vec3>> rays;
    for (int k = 0; k < 400; ++k) {
      const vec3 o{g.uniform() * 16 - 4, g.uniform() * 16 - 4, g.uniform() * 16 - 4};
      vec3 d{g.uniform() * 2 - 1, g.uniform() * 2 - 1, g.uniform() * 2 - 1};
      rays.push_back({o, d});
    }
    // Along axes, on voxel faces, through edges and corners (exact dyadic coordinates).
    for (int k = 0; k < 150; ++k) {
      const vec3 o{static_cast<double>(g.below(17)) / 2 - 0.5, static_cast<double>(g.below(17)) / 2 - 0.5,
                   static_cast<double>(g.below(17)) / 2 - 0.5};
      vec3 d{static_cast<double>(g.below(3)) - 1, static_cast<double>(g.below(3)) - 1,
             static_cast<double>(g.below(3)) - 1};
      if (d == vec3{0, 0, 0}) d = {0, 0, 1};
      rays.push_back({o, d});
    }
    rays.push_back({{-1, 3, 3}, {1, 0, 0}});    // along x on a voxel edge
    rays.push_back({{-1, -1, -1}, {1, 1, 1}});  // the grid's diagonal, corner to corner
    rays.push_back({{0, 0, 4.5}, {1, 1, 0}});   // through edges from a grid edge
    for (bool stop_boundary : {false, true}) {
      r::dda_options opt;
      opt.stop_at_boundary = stop_boundary;
      for (const auto& ray : rays) {
        const vec3 o = ray.first, d = ray.second;
        CAPTURE(o);
        CAPTURE(d);
        const auto h = r::first_hit(sc, o, d, opt);
        const auto b = brute_first_hit(sc, o, d, stop_boundary);
        REQUIRE(h.hit == b.hit);
        if (!b.hit) continue;
        CHECK(h.voxel == b.voxel);
        CHECK(h.t == b.t);  // the same expressions, so the same doubles
        CHECK(h.index == sc.index(b.voxel[0], b.voxel[1], b.voxel[2]));
        if (h.axis >= 0) {
          // The entry point lies on the crossed face of the voxel.
          const double face = h.voxel[h.axis] + (h.side > 0 ? 1.0 : 0.0);
          CHECK(std::abs(h.point[h.axis] - face) < 1e-9);
          CHECK(h.side == (d[h.axis] > 0 ? -1 : 1));
        } else {
          CHECK(h.t == 0);
        }
      }
    }
  }
  qrm::scene sc("s", 3, 4);
  CHECK_THROWS_AS(r::first_hit(sc, {0, 0, 0}, {0, 0, 0}), std::invalid_argument);
  CHECK_FALSE(r::first_hit(sc, {0.5, 0.5, 0.5}, {1, 0, 0}).hit);  // all air
}

TEST_CASE("camera: rays through pixel centres and inside pixels") {
  const r::camera cam({1, 2, 3}, {1, 2, 13}, {0, 1, 0}, 60, 9, 5);
  CHECK(near_vec(cam.forward(), {0, 0, 1}, 1e-15));
  CHECK(near_vec(cam.right(), {-1, 0, 0}, 1e-15));  // forward x up: +x appears on the left
  CHECK(near_vec(cam.up(), {0, 1, 0}, 1e-15));
  // The centre pixel of an odd image looks straight ahead.
  CHECK(near_vec(cam.ray(4, 2).direction, {0, 0, 1}, 1e-15));
  CHECK(cam.ray(4, 2).origin == vec3{1, 2, 3});
  // Film coordinates of a ray, in pixels.
  const double th = std::tan(std::numbers::pi / 6);  // half the vertical field of view
  auto film = [&](const vec3& d) {
    const double f = qrm::dot(d, cam.forward());
    const double sx = qrm::dot(d, cam.right()) / f, sy = qrm::dot(d, cam.up()) / f;
    return std::array<double, 2>{(sx / (th * 9.0 / 5.0) + 1) / 2 * 9, (1 - sy / th) / 2 * 5};
  };
  for (unsigned y = 0; y < 5; ++y)
    for (unsigned x = 0; x < 9; ++x) {
      const auto c = film(cam.ray(x, y).direction);
      CHECK(std::abs(c[0] - (x + 0.5)) < 1e-12);
      CHECK(std::abs(c[1] - (y + 0.5)) < 1e-12);
      CHECK(std::abs(qrm::norm(cam.ray(x, y).direction) - 1) < 1e-15);
    }
  // The top row's rays make the angle atan((1 - 1/H) tan(fov/2)) with the view direction.
  CHECK(std::acos(cam.ray(4, 0).direction[2]) == doctest::Approx(std::atan((1 - 1.0 / 5) * th)).epsilon(1e-12));
  qrm::rng g(5);
  for (int k = 0; k < 100; ++k) {
    const auto c = film(cam.ray(3, 1, g).direction);
    CHECK(c[0] >= 3 - 1e-12);
    CHECK(c[0] <= 4 + 1e-12);
    CHECK(c[1] >= 1 - 1e-12);
    CHECK(c[1] <= 2 + 1e-12);
  }
  CHECK_THROWS_AS(r::camera({0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 60, 4, 4), std::invalid_argument);
  CHECK_THROWS_AS(r::camera({0, 0, 0}, {0, 1, 0}, {0, 1, 0}, 60, 4, 4), std::invalid_argument);
  CHECK_THROWS_AS(r::camera({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 180, 4, 4), std::invalid_argument);
  CHECK_THROWS_AS(r::camera({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60, 0, 4), std::invalid_argument);
  CHECK_THROWS_AS(cam.ray(9, 0), std::out_of_range);
}

// ============================================================================================
TEST_CASE("renderers report progress: every job once, against the total they know, from any thread") {
  const qrm::walk_model m = small_cornell_model();
  const r::camera cam = r::box_scene_camera(8, 12, 10);
  const auto px = r::pixel_starts(m, cam);
  std::vector<std::pair<std::size_t, std::size_t>> distinct;  // the (voxel, direction) walk starts
  for (const auto& p : px)
    if (p.hit) distinct.emplace_back(p.voxel, p.start.direction);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  REQUIRE(distinct.size() > 10);
  for (unsigned threads : {1u, 2u}) {
    std::atomic<std::size_t> finished{0}, calls{0}, total{0};
    r::render_options o;
    o.steps = 2;
    o.threads = threads;
    o.progress = [&](std::size_t n, std::size_t t) {
      finished += n;
      ++calls;
      total = t;
    };
    (void)r::render_exact(m, cam, o);
    CHECK(total == distinct.size());  // one job per distinct walk start
    CHECK(finished == distinct.size());
    finished = 0;
    (void)r::render_monte_carlo(m, cam, 4, 1, o);
    CHECK(total == 120);  // one job per pixel
    CHECK(finished == 120);
    finished = 0;
    r::emulation_options e;
    e.paths_per_pixel = 4;
    (void)r::render_emulated(m, cam, e, o);
    CHECK(total == distinct.size());
    CHECK(finished == distinct.size());
  }
}

TEST_CASE("pixel starts: the walker enters the hit surface in the nearest incoming direction") {
  const qrm::walk_model m = small_cornell_model();
  const r::camera cam = r::box_scene_camera(8, 16, 16);
  const auto px = r::pixel_starts(m, cam);
  REQUIRE(px.size() == 256);
  std::size_t hits = 0;
  for (std::size_t p = 0; p < px.size(); ++p) {
    if (!px[p].hit) continue;
    ++hits;
    const auto ray = cam.ray(static_cast<unsigned>(p % 16), static_cast<unsigned>(p / 16));
    const qrm::voxel& v = m.scene_data()[px[p].voxel];
    REQUIRE(v.kind == qrm::material::lambertian);
    const auto split = qrm::split_hemisphere(m.directions(), v.normal);
    const auto d = static_cast<std::size_t>(px[p].start.direction);
    CHECK(std::find(split.incoming.begin(), split.incoming.end(), d) != split.incoming.end());
    for (std::size_t e : split.incoming)
      CHECK(qrm::dot(m.directions().vectors[e], ray.direction) <= qrm::dot(m.directions().vectors[d], ray.direction));
  }
  CHECK(hits == 256);  // the camera sees only the room
}

TEST_CASE("exact image equals a naive per-pixel path enumeration") {
  const qrm::walk_model m = small_cornell_model();
  const unsigned w = 16;  // fine enough that some pixels see the light's two voxels
  const r::camera cam = r::box_scene_camera(8, w, w);
  r::render_options o;
  o.steps = 3;
  const r::image img = r::render_exact(m, cam, o);
  std::size_t lit_by_bounce = 0, emitters = 0;
  for (unsigned y = 0; y < w; ++y)
    for (unsigned x = 0; x < w; ++x) {
      const auto want = reference_pixel(m, cam, x, y, 3);
      const auto ray = cam.ray(x, y);
      const bool emitter = m.scene_data()[r::first_hit(m.scene_data(), ray.origin, ray.direction).index].emission.r > 0;
      for (int c = 0; c < 3; ++c)
        // float storage: relative 2^-24; the two sums differ in order only (~1e-15).
        CHECK(std::abs(img.at(x, y).channel(c) - want[c]) <= 1e-6 * std::max(1.0, want[c]));
      emitters += emitter ? 1 : 0;
      if (!emitter && want[0] > 0) ++lit_by_bounce;
    }
  // The comparison covers visible emitters and light that arrives by walking.
  CHECK(emitters > 0);
  CHECK(lit_by_bounce > 5);
  // The forward pass is qrm::path_sum, bit for bit, per channel.
  const qrm::detail::transition_table tables(m);
  const auto starts = r::pixel_starts(m, cam);
  for (std::size_t k = 0; k < starts.size(); ++k)
    for (unsigned steps : {3u, 6u}) {
      if (steps == 6 && k % 16 != 0) continue;  // longer walks: many states meet (order matters)
      const auto rgb = r::path_sum_rgb(tables, starts[k].start, steps);
      for (int c = 0; c < 3; ++c) CHECK(rgb[c] == qrm::path_sum(m, starts[k].start, steps, c));
    }
}

TEST_CASE("Monte Carlo image converges to the exact image at the rate its variance predicts") {
  // Per pixel and channel, the MC mean of N paths has error e with E[e^2] = rho^2 sigma^2 / N and
  // Var[e^2] = rho^4 (2 sigma^4 / N^2 + (mu4 - 3 sigma^4) / N^3) (sigma^2, mu4: central moments
  // of f from the naive enumeration). The squared error summed over the pixels of R = 8
  // independent images (each pixel its own stream) must be within 6 standard deviations of its
  // expectation. One image alone is dominated by a few pixels (skewed sum); over 8 x 32 x 32
  // pixels the sum is close to normal: offline, 400 seeds gave z with mean 0.0 +- 0.06, sd
  // 0.96-1.03, skewness below 0.1 and max |z| 3.5. False failure ~2e-9 per check (normal
  // approximation); 9 checks of the error and 9 of the reported standard errors.
  const qrm::walk_model m = small_cornell_model();
  constexpr unsigned w = 32, pixels = w * w, replicas = 8;
  const r::camera cam = r::box_scene_camera(8, w, w);
  r::render_options o;
  o.steps = 3;
  std::vector<f_moments> mom(pixels);
  std::vector<std::array<double, 3>> exact(pixels), rho(pixels);
  r::image ex(w, w);
  for (unsigned p = 0; p < pixels; ++p) {
    exact[p] = reference_pixel(m, cam, p % w, p / w, 3, &mom[p], rho[p].data());
    for (int c = 0; c < 3; ++c) ex.at(p % w, p / w).channel(c) = static_cast<float>(exact[p][c]);
  }
  double rmse_prev = std::numeric_limits<double>::infinity();
  std::array<double, 3> pred_prev{}, sd_prev{}, obs_prev{};
  for (std::uint64_t paths : {16u, 64u, 256u}) {
    CAPTURE(paths);
    const double nn = static_cast<double>(paths);
    std::array<double, 3> obs{}, pred{}, var{}, se2_obs{}, se2_pred{}, se2_var{};
    double mse_images = 0;
    for (unsigned rep = 0; rep < replicas; ++rep) {
      const auto mc = r::render_monte_carlo(m, cam, paths, 1000 + 131 * paths + rep, o);
      const double e = qrm::io::rmse(mc.mean, ex);
      mse_images += e * e / replicas;
      for (unsigned p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c) {
          const double err = mc.mean.at(p % w, p / w).channel(c) - exact[p][c];
          const double r2 = rho[p][c] * rho[p][c], s2 = mom[p].var[c];
          obs[c] += err * err;
          pred[c] += r2 * s2 / nn;
          var[c] += r2 * r2 * (2 * s2 * s2 / (nn * nn) + (mom[p].m4[c] - 3 * s2 * s2) / (nn * nn * nn));
          // The reported standard error: SE^2 = s^2 / N, s^2 the unbiased sample variance:
          // E[s^2] = sigma^2, Var[s^2] = mu4 / N - sigma^4 (N - 3) / (N (N - 1)).
          const double se = mc.standard_error.at(p % w, p / w).channel(c);
          se2_obs[c] += se * se;
          se2_pred[c] += r2 * s2 / nn;
          se2_var[c] += r2 * r2 * (mom[p].m4[c] / nn - s2 * s2 * (nn - 3) / (nn * (nn - 1))) / (nn * nn);
        }
    }
    for (int c = 0; c < 3; ++c) {
      CAPTURE(c);
      REQUIRE(pred[c] > 0);
      const double sd = std::sqrt(var[c]);
      CHECK(std::abs(obs[c] - pred[c]) <= 6 * sd);
      CHECK(std::abs(se2_obs[c] - se2_pred[c]) <= 6 * std::sqrt(se2_var[c]));
      if (paths > 16) {
        // RMSE ratio for 4x the paths: 1/2 in expectation (pred[c] = pred_prev[c] / 4 exactly);
        // its bounds follow from the two 6-sigma intervals.
        const double ratio = std::sqrt(obs[c] / obs_prev[c]);
        CHECK(ratio >= std::sqrt((pred[c] - 6 * sd) / (pred_prev[c] + 6 * sd_prev[c])));
        CHECK(ratio <= std::sqrt((pred[c] + 6 * sd) / (pred_prev[c] - 6 * sd_prev[c])));
      }
      pred_prev[c] = pred[c];
      sd_prev[c] = sd;
      obs_prev[c] = obs[c];
    }
    const double rmse = std::sqrt(mse_images);
    CHECK(rmse < rmse_prev);
    rmse_prev = rmse;
  }
  // The RGB walk is qrm::monte_carlo, bit for bit, per channel.
  const qrm::detail::transition_table tables(m);
  for (const auto& p : r::pixel_starts(m, cam)) {
    qrm::rng g0 = qrm::rng::stream(3, p.voxel);
    const auto rgb = r::monte_carlo_rgb_walk(tables, p.start, 3, 50, g0);
    for (int c = 0; c < 3; ++c) {
      qrm::rng g = qrm::rng::stream(3, p.voxel);
      const auto one = qrm::monte_carlo(m, p.start, 3, c, 50, g);
      CHECK(rgb.mean[c] == one.mean);
      CHECK(rgb.standard_error[c] == one.standard_error);
    }
  }
}

// ============================================================================================
TEST_CASE("emulator: enumerated paths sum to the path sum; sampling draws by probability") {
  const qrm::walk_model m = small_cornell_model();
  const r::camera cam = r::box_scene_camera(8, 8, 8);
  std::size_t checked = 0;
  for (const auto& p : r::pixel_starts(m, cam)) {
    for (unsigned steps : {1u, 2u, 3u}) {
      const r::path_set ps = r::enumerate_paths(m, p.start, steps);
      const auto naive = naive_paths(m, p.start, steps);
      REQUIRE(ps.size() == naive.size());
      CHECK(ps.voxels.size() == ps.size() * steps);
      CHECK(ps.directions.size() == ps.size() * steps);
      double total = 0;
      for (double q : ps.probability) total += q;
      CHECK(total == doctest::Approx(1.0).epsilon(1e-12));  // rounding of a few thousand products
      const auto mean = ps.exact_mean();
      for (int c = 0; c < 3; ++c) CHECK(mean[c] == doctest::Approx(qrm::path_sum(m, p.start, steps, c)).epsilon(1e-12));
      // Each path's recorded voxels give back its f.
      for (std::size_t k = 0; k < ps.size(); ++k) {
        double f = 0, prefix = 1;
        for (unsigned i = 0; i < steps; ++i) {
          const std::size_t v = ps.voxels[k * steps + i];
          f += prefix * m.emission(v, 0);
          prefix *= m.reflectance(v, 0);
        }
        CHECK(f == ps.f[k][0]);
      }
      ++checked;
    }
  }
  CHECK(checked == 64 * 3);
  // Budget: refused above it, clearly.
  const auto start = r::pixel_starts(m, cam)[27].start;
  const std::size_t count = r::enumerate_paths(m, start, 3).size();
  REQUIRE(count > 1);
  CHECK_NOTHROW(r::enumerate_paths(m, start, 3, count));
  CHECK_THROWS_AS(r::enumerate_paths(m, start, 3, count - 1), std::length_error);
  // Sampling: the mean of K draws is within 6 standard errors of the exact mean (false failure
  // ~2e-9, normal approximation with K = 20000), per channel; a path's draw frequency is within
  // 6 binomial standard deviations of its probability.
  const r::path_set ps = r::enumerate_paths(m, start, 3);
  qrm::rng g(77);
  const std::size_t k = 20000;
  const auto idx = ps.sample_path_indices(k, g);
  const auto mean = ps.exact_mean();
  for (int c = 0; c < 3; ++c) {
    double s = 0, var = 0;
    for (std::size_t i : idx) s += ps.f[i][c];
    for (std::size_t j = 0; j < ps.size(); ++j)
      var += ps.probability[j] * (ps.f[j][c] - mean[c]) * (ps.f[j][c] - mean[c]);
    CHECK(std::abs(s / k - mean[c]) <= 6 * std::sqrt(var / k) + 1e-15);
  }
  const std::size_t top =
      static_cast<std::size_t>(std::max_element(ps.probability.begin(), ps.probability.end()) - ps.probability.begin());
  const double q = ps.probability[top];
  const auto hits = static_cast<double>(std::count(idx.begin(), idx.end(), top));
  CHECK(std::abs(hits - k * q) <= 6 * std::sqrt(k * q * (1 - q)));
  qrm::rng g1(9), g2(9);
  const auto f1 = ps.sample_paths(10, g1);
  const auto i2 = ps.sample_path_indices(10, g2);
  for (std::size_t j = 0; j < 10; ++j) CHECK(f1[j] == ps.f[i2[j]]);
}

TEST_CASE("emulated image: exact part equals the exact image; the estimator hook sees K paths") {
  const qrm::walk_model m = small_cornell_model();
  const r::camera cam = r::box_scene_camera(8, 10, 10);
  r::render_options o;
  o.steps = 3;
  r::emulation_options e;
  e.paths_per_pixel = 32;
  e.seed = 11;
  const auto em = r::render_emulated(m, cam, e, o);
  const r::image ex = r::render_exact(m, cam, o);
  for (std::size_t i = 0; i < ex.pixels().size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float a = em.exact.pixels()[i].channel(c), b = ex.pixels()[i].channel(c);
      CHECK(std::abs(a - b) <= 1e-6 * std::max(1.0f, b));
    }  // float of sums in two orders
  // A hook that returns the mean reproduces the default bit for bit; it is called per hit pixel
  // and channel whose exact path sum is non-zero (a zero one stays exactly zero, without an
  // estimator) with K contributions, the step count and the channel's emission scale.
  std::size_t nonzero = 0, hit_channels = 0;
  const qrm::detail::transition_table tt(m);
  for (const auto& p : r::pixel_starts(m, cam)) {
    if (!p.hit) continue;
    const auto v = r::path_sum_rgb(tt, p.start, 3);
    for (int c = 0; c < 3; ++c) nonzero += v[static_cast<std::size_t>(c)] > 0;
    hit_channels += 3;
  }
  CHECK(hit_channels == 300);
  CHECK(nonzero > 30);
  CHECK(nonzero < hit_channels);
  std::size_t calls = 0;
  bool shapes_ok = true;
  r::emulation_options hooked = e;
  hooked.estimate = [&](const std::vector<double>& f, unsigned steps, double scale, qrm::rng&) {
    ++calls;
    shapes_ok = shapes_ok && f.size() == 32 && steps == 3 && (scale == 17 || scale == 12 || scale == 4);
    double s = 0;
    for (double x : f) s += x;
    return s / static_cast<double>(f.size());
  };
  o.threads = 1;  // the hook above is not thread-safe
  const auto em2 = r::render_emulated(m, cam, hooked, o);
  CHECK(calls == nonzero);
  CHECK(shapes_ok);
  CHECK(same_bits(em.sampled, em2.sampled));
  // The sampled image is an unbiased estimate: it differs from the exact one, but not wildly.
  CHECK_FALSE(same_bits(em.sampled, em.exact));
}

TEST_CASE("images are bit-identical for any thread count and for tiles merged") {
  const qrm::walk_model m = small_cornell_model();
  const r::camera cam = r::box_scene_camera(8, 14, 9);  // 126 pixels: tiles of unequal size
  r::render_options one, two;
  one.threads = 1;
  two.threads = 2;
  r::emulation_options e;
  e.paths_per_pixel = 16;
  CHECK(same_bits(r::render_exact(m, cam, one), r::render_exact(m, cam, two)));
  const auto mc1 = r::render_monte_carlo(m, cam, 40, 5, one), mc2 = r::render_monte_carlo(m, cam, 40, 5, two);
  CHECK(same_bits(mc1.mean, mc2.mean));
  CHECK(same_bits(mc1.standard_error, mc2.standard_error));
  const auto em1 = r::render_emulated(m, cam, e, one), em2 = r::render_emulated(m, cam, e, two);
  CHECK(same_bits(em1.sampled, em2.sampled));
  CHECK(same_bits(em1.exact, em2.exact));

  std::vector<r::image> exact_parts, mc_parts, se_parts, em_parts;
  for (unsigned i = 0; i < 4; ++i) {
    r::render_options t = two;
    t.part = {i, 4};
    exact_parts.push_back(r::render_exact(m, cam, t));
    const auto mc = r::render_monte_carlo(m, cam, 40, 5, t);
    mc_parts.push_back(mc.mean);
    se_parts.push_back(mc.standard_error);
    em_parts.push_back(r::render_emulated(m, cam, e, t).sampled);
    // Pixels outside the tile stay black.
    const auto range = r::tile_pixels(126, t.part);
    for (std::size_t p = 0; p < 126; ++p)
      if (p < range.begin || p >= range.end)
        for (int c = 0; c < 3; ++c) CHECK(exact_parts.back().pixels()[p].channel(c) == 0.0f);
  }
  CHECK(same_bits(r::merge_tiles(exact_parts), r::render_exact(m, cam, one)));
  CHECK(same_bits(r::merge_tiles(mc_parts), mc1.mean));
  CHECK(same_bits(r::merge_tiles(se_parts), mc1.standard_error));
  CHECK(same_bits(r::merge_tiles(em_parts), em1.sampled));
  CHECK_THROWS_AS(r::tile_pixels(10, {3, 3}), std::invalid_argument);
  CHECK_THROWS_AS(r::merge_tiles({r::image(2, 2), r::image(3, 2)}), std::invalid_argument);
}
