// qrm/render/voxelize.hpp: surface voxelization of analytic geometry (rectangles, boxes,
// spheres) into an N^3 qrm::scene, and the paper's 3D scenes: the Cornell box and two spheres
// in a box.
//
// Coordinates are voxel units: voxel (i, j, k) is the cube [i, i+1) x [j, j+1) x [k, k+1) of
// the grid [0, N]^3. +y is up; the scenes' cameras look along +z.
//
// Surface, not solid: a voxel belongs to a primitive when the primitive's surface meets the
// closed voxel cube (exact tests: separating axes for a rectangle against the cube; nearest and
// farthest point of the cube for a sphere). Where several primitives meet one voxel, the voxel
// takes the material of the one whose surface passes closest to the voxel centre (ties: the one
// added first), and as normal the normalised sum of the normals of every surface of that
// primitive's group meeting the voxel. A group is one box (its faces) or one sphere, so box
// edges and corners get the average of their faces' normals and a sphere voxel gets the radial
// direction at its centre; a box resting on a floor does not bend the floor's normals, since
// floor and box are different groups.
//
// Closing the grid: the walk wraps positions modulo N, so a walker leaving the grid on one side
// would come back on the other. build() makes the outermost voxel layer `boundary` voxels with
// zero reflectance and emission (the absorbing shell): a walker reaching it adds nothing more
// to its path, i.e. light leaving the scene is lost, and nothing wraps around. Camera rays pass
// through the shell (render/dda.hpp), so cameras may sit outside the grid.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "detail/vec3.hpp"
#include "../walk/scene.hpp"
#include "camera.hpp"

namespace qrm::render {

// What a surface voxel gets: its kind (lambertian, specular, glossy), reflectance, emission and,
// for glossy surfaces, the lobe parameter (walk/coins.hpp, glossy_coin). A specular or glossy
// voxel's coin mirrors about the voxel's normal (below: a sphere's radial direction, a box
// edge's mean of its faces' normals).
struct surface_material {
  material kind = material::lambertian;
  rgb reflectance{0.75, 0.75, 0.75};
  rgb emission{0, 0, 0};
  double lobe = 0;
};

// A rectangle: centre, orthonormal in-plane axes u and v with half extents, and the unit normal
// of its visible side (orthogonal to u and v).
struct rectangle {
  vec3 centre{0, 0, 0}, u{1, 0, 0}, v{0, 0, 1};
  double half_u = 0, half_v = 0;
  vec3 normal{0, 1, 0};
};

// A box: centre, three orthonormal axes and the half extents along them.
struct oriented_box {
  vec3 centre{0, 0, 0};
  std::array<vec3, 3> axes{vec3{1, 0, 0}, vec3{0, 1, 0}, vec3{0, 0, 1}};
  vec3 half{0, 0, 0};
};

struct sphere {
  vec3 centre{0, 0, 0};
  double radius = 0;
};

// Box faces in order (and mask bit 1 << face): -axis0, +axis0, -axis1, +axis1, -axis2, +axis2.
constexpr unsigned box_face_bit(int axis, bool positive) {
  return 1u << (2 * axis + (positive ? 1 : 0));
}
inline constexpr unsigned all_box_faces = 63;

}  // namespace qrm::render

namespace qrm::detail {

template <int = 0>
inline void check_unit_vector(const vec3& v, const char* what) {
  if (!vec_finite(v) || std::abs(norm(v) - 1.0) > 1e-9)
    throw std::invalid_argument(std::string("voxelizer: ") + what + " must be a unit vector");
}

// The rectangle meets the closed unit cube centred at c (separating axis test).
template <int = 0>
inline bool rectangle_meets_cube(const render::rectangle& r, const vec3& c) {
  const vec3 d = vec_sub(r.centre, c);
  auto separated = [&](const vec3& l) {
    const double rr = r.half_u * std::abs(dot(r.u, l)) + r.half_v * std::abs(dot(r.v, l));
    const double rc = 0.5 * (std::abs(l[0]) + std::abs(l[1]) + std::abs(l[2]));
    return std::abs(dot(d, l)) > rr + rc;
  };
  for (int a = 0; a < 3; ++a) {
    vec3 e{0, 0, 0};
    e[static_cast<std::size_t>(a)] = 1;
    if (separated(e)) return false;
  }
  if (separated(r.normal)) return false;
  for (int a = 0; a < 3; ++a) {
    vec3 e{0, 0, 0};
    e[static_cast<std::size_t>(a)] = 1;
    for (const vec3* w : {&r.u, &r.v}) {
      const vec3 l = vec_cross(e, *w);
      if (norm(l) > 1e-12 && separated(l)) return false;
    }
  }
  return true;
}

template <int = 0>
inline double rectangle_distance(const render::rectangle& r, const vec3& p) {
  const vec3 d = vec_sub(p, r.centre);
  const double a = dot(d, r.u), b = dot(d, r.v), w = dot(d, r.normal);
  const double da = a - std::clamp(a, -r.half_u, r.half_u), db = b - std::clamp(b, -r.half_v, r.half_v);
  return std::sqrt(da * da + db * db + w * w);
}

// The sphere's surface meets the closed unit cube centred at c.
template <int = 0>
inline bool sphere_meets_cube(const render::sphere& s, const vec3& c) {
  double near2 = 0, far2 = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    const double lo = c[a] - 0.5, hi = c[a] + 0.5, x = s.centre[a];
    const double n = x < lo ? lo - x : (x > hi ? x - hi : 0.0);
    const double f = std::max(std::abs(x - lo), std::abs(x - hi));
    near2 += n * n;
    far2 += f * f;
  }
  const double r2 = s.radius * s.radius;
  return near2 <= r2 && r2 <= far2;
}

}  // namespace qrm::detail

namespace qrm::render {

class voxelizer {
 public:
  // voxelizer(size): an empty size^3 grid (size a power of two >= 4).
  template <int = 0>
  explicit voxelizer(unsigned size) : size_(size) {
    if (size < 4 || (size & (size - 1)) != 0 || size > 1024)
      throw std::invalid_argument("voxelizer: size must be a power of two in [4, 1024], got " + std::to_string(size));
  }
  unsigned size() const { return size_; }

  // add_rectangle(r, m): a one-sided rectangle, a group of its own. Returns the group id.
  template <int = 0>
  int add_rectangle(const rectangle& r, const surface_material& m) {
    check_rectangle(r);
    element e;
    e.rect = r;
    e.mat = m;
    e.group = next_group_++;
    elements_.push_back(e);
    return e.group;
  }

  // add_box(b, faces, mask, inward): the faces of box b selected by `mask` (box_face_bit), face
  // f with material faces[f]; normals point out of the box, or into it when `inward` (a room
  // seen from inside). One group. Returns the group id.
  template <int = 0>
  int add_box(const oriented_box& b, const std::array<surface_material, 6>& faces, unsigned mask = all_box_faces,
              bool inward = false) {
    for (int a = 0; a < 3; ++a) {
      qrm::detail::check_unit_vector(b.axes[static_cast<std::size_t>(a)], "a box axis");
      if (!(b.half[static_cast<std::size_t>(a)] > 0) || !std::isfinite(b.half[static_cast<std::size_t>(a)]))
        throw std::invalid_argument("voxelizer: box half extent " +
                                    std::to_string(b.half[static_cast<std::size_t>(a)]) +
                                    " must be positive and finite");
    }
    for (int a = 0; a < 3; ++a)
      for (int c = a + 1; c < 3; ++c)
        if (std::abs(dot(b.axes[static_cast<std::size_t>(a)], b.axes[static_cast<std::size_t>(c)])) > 1e-9)
          throw std::invalid_argument("voxelizer: box axes must be orthogonal");
    if (!qrm::detail::vec_finite(b.centre)) throw std::invalid_argument("voxelizer: box centre must be finite");
    if ((mask & all_box_faces) == 0 || (mask & ~all_box_faces) != 0)
      throw std::invalid_argument("voxelizer: box face mask " + std::to_string(mask) +
                                  " must select some of the 6 faces");
    const int group = next_group_++;
    for (int f = 0; f < 6; ++f) {
      if (!(mask & (1u << f))) continue;
      const auto a = static_cast<std::size_t>(f / 2), a1 = (a + 1) % 3, a2 = (a + 2) % 3;
      const double sign = f % 2 ? 1.0 : -1.0;
      element e;
      e.rect.centre = qrm::detail::vec_add_scaled(b.centre, b.axes[a], sign * b.half[a]);
      e.rect.u = b.axes[a1];
      e.rect.v = b.axes[a2];
      e.rect.half_u = b.half[a1];
      e.rect.half_v = b.half[a2];
      e.rect.normal = qrm::detail::vec_scale(b.axes[a], inward ? -sign : sign);
      e.mat = faces[static_cast<std::size_t>(f)];
      e.group = group;
      elements_.push_back(e);
    }
    return group;
  }
  template <int = 0>
  int add_box(const oriented_box& b, const surface_material& m, unsigned mask = all_box_faces, bool inward = false) {
    return add_box(b, {m, m, m, m, m, m}, mask, inward);
  }

  // add_sphere(s, m): a sphere (normals point outward), a group of its own.
  template <int = 0>
  int add_sphere(const sphere& s, const surface_material& m) {
    if (!qrm::detail::vec_finite(s.centre) || !(s.radius > 0) || !std::isfinite(s.radius))
      throw std::invalid_argument("voxelizer: sphere radius " + std::to_string(s.radius) +
                                  " must be positive and finite, and its centre finite");
    element e;
    e.is_sphere = true;
    e.ball = s;
    e.mat = m;
    e.group = next_group_++;
    elements_.push_back(e);
    return e.group;
  }

  // build(name, absorbing_shell): the scene. With the shell (see the file comment), no surface
  // may reach the outermost voxel layer.
  template <int = 0>
  scene build(const std::string& name, bool absorbing_shell = true) const;

 private:
  struct element {
    bool is_sphere = false;
    rectangle rect;
    sphere ball;
    surface_material mat;
    int group = 0;
  };

  template <int = 0>
  static vec3 centre_of(const std::array<unsigned, 3>& v) {
    return {static_cast<double>(v[0]) + 0.5, static_cast<double>(v[1]) + 0.5, static_cast<double>(v[2]) + 0.5};
  }
  template <int = 0>
  static void check_rectangle(const rectangle& r) {
    qrm::detail::check_unit_vector(r.u, "a rectangle's u axis");
    qrm::detail::check_unit_vector(r.v, "a rectangle's v axis");
    qrm::detail::check_unit_vector(r.normal, "a rectangle's normal");
    if (std::abs(dot(r.u, r.v)) > 1e-9 || std::abs(dot(r.u, r.normal)) > 1e-9 || std::abs(dot(r.v, r.normal)) > 1e-9)
      throw std::invalid_argument("voxelizer: a rectangle's u, v and normal must be orthogonal");
    if (!(r.half_u > 0 && r.half_v > 0) || !std::isfinite(r.half_u) || !std::isfinite(r.half_v) ||
        !qrm::detail::vec_finite(r.centre))
      throw std::invalid_argument("voxelizer: rectangle half extents " + std::to_string(r.half_u) + ", " +
                                  std::to_string(r.half_v) + " must be positive and finite, and its centre finite");
  }
  template <int = 0>
  static double distance(const element& e, const vec3& p) {
    if (e.is_sphere) return std::abs(norm(qrm::detail::vec_sub(p, e.ball.centre)) - e.ball.radius);
    return qrm::detail::rectangle_distance(e.rect, p);
  }
  // The outward normal of the element's surface seen from point p.
  template <int = 0>
  static vec3 normal_at(const element& e, const vec3& p) {
    if (!e.is_sphere) return e.rect.normal;
    const vec3 r = qrm::detail::vec_sub(p, e.ball.centre);
    return norm(r) > 0 ? normalized(r) : vec3{0, 1, 0};  // the centre itself: any direction; up
  }
  // Calls fn(index, voxel centre) for every voxel whose closed cube the element's surface meets.
  template <class F>
  void for_each_met_voxel(const element& e, F&& fn) const {
    vec3 lo{}, hi{};
    for (std::size_t a = 0; a < 3; ++a) {
      const double c = e.is_sphere ? e.ball.centre[a] : e.rect.centre[a];
      const double ext =
          e.is_sphere ? e.ball.radius : e.rect.half_u * std::abs(e.rect.u[a]) + e.rect.half_v * std::abs(e.rect.v[a]);
      lo[a] = c - ext;
      hi[a] = c + ext;
    }
    const double top = static_cast<double>(size_) - 1;
    auto first = [&](double x) { return static_cast<unsigned>(std::clamp(std::floor(x) - 1, 0.0, top)); };
    auto last = [&](double x) { return static_cast<unsigned>(std::clamp(std::floor(x) + 1, 0.0, top)); };
    const std::size_t n = size_;
    for (unsigned z = first(lo[2]); z <= last(hi[2]); ++z)
      for (unsigned y = first(lo[1]); y <= last(hi[1]); ++y)
        for (unsigned x = first(lo[0]); x <= last(hi[0]); ++x) {
          const vec3 c = centre_of({x, y, z});
          const bool meets =
              e.is_sphere ? qrm::detail::sphere_meets_cube(e.ball, c) : qrm::detail::rectangle_meets_cube(e.rect, c);
          if (meets) fn(x + n * (y + n * static_cast<std::size_t>(z)), c);
        }
  }

  unsigned size_;
  std::vector<element> elements_;
  int next_group_ = 0;
};

template <int Deferred>
scene voxelizer::build(const std::string& name, bool absorbing_shell) const {
  const unsigned n = size_;
  scene sc(name, 3, n);
  const std::size_t count = sc.voxel_count();
  std::vector<double> best(count, std::numeric_limits<double>::infinity());
  std::vector<int> winner(count, -1);
  for (std::size_t k = 0; k < elements_.size(); ++k)
    for_each_met_voxel(elements_[k], [&](std::size_t i, const vec3& c) {
      const double d = distance(elements_[k], c);
      if (d < best[i]) {
        best[i] = d;
        winner[i] = static_cast<int>(k);
      }
    });
  std::vector<vec3> normal_sum(count, vec3{0, 0, 0});
  for (const element& e : elements_)
    for_each_met_voxel(e, [&](std::size_t i, const vec3& c) {
      if (winner[i] >= 0 && elements_[static_cast<std::size_t>(winner[i])].group == e.group)
        normal_sum[i] = qrm::detail::vec_add(normal_sum[i], normal_at(e, c));
    });
  for (std::size_t i = 0; i < count; ++i) {
    if (winner[i] < 0) continue;
    const element& w = elements_[static_cast<std::size_t>(winner[i])];
    voxel& v = sc[i];
    v.kind = w.mat.kind;
    v.reflectance = w.mat.reflectance;
    v.emission = w.mat.emission;
    v.lobe = w.mat.lobe;
    const auto xyz = sc.coords(i);
    v.normal = norm(normal_sum[i]) > 1e-9 ? normalized(normal_sum[i]) : normal_at(w, centre_of(xyz));
  }
  if (absorbing_shell) {
    for (std::size_t i = 0; i < count; ++i) {
      const auto xyz = sc.coords(i);
      int axis = -1;
      double inward = 0;
      for (int a = 0; a < 3 && axis < 0; ++a) {
        const unsigned c = xyz[static_cast<std::size_t>(a)];
        if (c == 0 || c == n - 1) {
          axis = a;
          inward = c == 0 ? 1.0 : -1.0;
        }
      }
      if (axis < 0) continue;
      if (winner[i] >= 0)
        throw std::invalid_argument("voxelizer '" + name + "': a surface reaches voxel (" + std::to_string(xyz[0]) +
                                    ", " + std::to_string(xyz[1]) + ", " + std::to_string(xyz[2]) +
                                    ") of the outermost layer, which is the absorbing shell");
      voxel& v = sc[i];
      v.kind = material::boundary;
      v.reflectance = {0, 0, 0};
      v.emission = {0, 0, 0};
      v.normal = {0, 0, 0};
      v.normal[static_cast<std::size_t>(axis)] = inward;
    }
  }
  sc.validate();
  return sc;
}

// ---------------------------------------------------------------------------------------------
// The paper's scenes. Both are a room in the grid: one shell layer, then one-voxel walls whose
// planes pass through the centres of the second layer, so the room's inside spans voxel
// coordinates [1.5, N - 1.5] on every axis and 550 mm (the Cornell box's size) maps to N - 3
// voxels. The front side (-z) of the room is open, as in the Cornell box: light leaving through
// it reaches the shell and is lost. Both cameras are the Cornell box's published camera.

}  // namespace qrm::render

namespace qrm::detail {
// Cornell box millimetres to voxel coordinates for an N^3 grid.
struct cornell_frame {
  double k;  // voxels per millimetre
  explicit cornell_frame(unsigned n) : k((static_cast<double>(n) - 3.0) / 550.0) {}
  double at(double mm) const { return 1.5 + k * mm; }
  vec3 at(const vec3& mm) const { return {at(mm[0]), at(mm[1]), at(mm[2])}; }
};

template <int = 0>
inline void check_box_scene_size(const char* what, unsigned n) {
  if (n < 8 || (n & (n - 1)) != 0 || n > 1024)
    throw std::invalid_argument(std::string(what) +
                                ": size must be a power of two in [8, 1024] (the shell and the walls take two voxel "
                                "layers on each side), got " +
                                std::to_string(n));
}

// The room: walls at the faces of [1.5, N-1.5]^3 facing in, the -z face open.
template <int = 0>
inline render::oriented_box room_box(unsigned n) {
  const double c = static_cast<double>(n) / 2.0, h = (static_cast<double>(n) - 3.0) / 2.0;
  return {{c, c, c}, {vec3{1, 0, 0}, vec3{0, 1, 0}, vec3{0, 0, 1}}, {h, h, h}};
}
inline constexpr unsigned room_faces = render::all_box_faces & ~render::box_face_bit(2, false);

// A block resting on the floor, from its published top face (corners in order, millimetres) and
// height: centre = mean of the corners, axes from the edges (orthonormalised), extents = mean of
// opposite edge lengths. The published blocks are squares and rectangles to within 2 mm.
template <int = 0>
inline render::oriented_box published_block(const cornell_frame& fr, const std::array<std::array<double, 2>, 4>& xz,
                                            double height_mm) {
  auto edge = [&](int i, int j) {
    return vec3{xz[static_cast<std::size_t>(j)][0] - xz[static_cast<std::size_t>(i)][0], 0,
                xz[static_cast<std::size_t>(j)][1] - xz[static_cast<std::size_t>(i)][1]};
  };
  const vec3 e01 = edge(0, 1), e12 = edge(1, 2), e32 = edge(3, 2), e03 = edge(0, 3);
  const vec3 u = normalized(e01);
  const vec3 w = normalized(vec_add_scaled(e12, u, -dot(e12, u)));
  const double len_u = (norm(e01) + norm(e32)) / 2.0, len_w = (norm(e12) + norm(e03)) / 2.0;
  const double cx = (xz[0][0] + xz[1][0] + xz[2][0] + xz[3][0]) / 4.0;
  const double cz = (xz[0][1] + xz[1][1] + xz[2][1] + xz[3][1]) / 4.0;
  render::oriented_box b;
  b.centre = fr.at(vec3{cx, height_mm / 2.0, cz});
  b.axes = {u, vec3{0, 1, 0}, w};
  b.half = {fr.k * len_u / 2.0, fr.k * height_mm / 2.0, fr.k * len_w / 2.0};
  return b;
}

// Marks the ceiling voxels (layer N - 2) whose centres lie in the rectangle [x0, x1] x [z0, z1]
// (voxel coordinates) as emitters; if that is none (a light smaller than a voxel), the voxel
// holding the rectangle's centre.
template <int = 0>
inline void paint_ceiling_light(scene& sc, double x0, double x1, double z0, double z1, const rgb& emission) {
  const unsigned y = sc.size() - 2;
  bool any = false;
  for (unsigned z = 0; z < sc.size(); ++z)
    for (unsigned x = 0; x < sc.size(); ++x) {
      const double cx = x + 0.5, cz = z + 0.5;
      if (cx >= x0 && cx <= x1 && cz >= z0 && cz <= z1 && sc.at(x, y, z).kind == material::lambertian) {
        sc.at(x, y, z).emission = emission;
        any = true;
      }
    }
  if (!any)
    sc.at(static_cast<unsigned>((x0 + x1) / 2.0), y, static_cast<unsigned>((z0 + z1) / 2.0)).emission = emission;
}
}  // namespace qrm::detail

namespace qrm::render {

// The Cornell box's reflectances (common RGB values of the published spectra).
inline constexpr rgb cornell_white{0.725, 0.71, 0.68};
inline constexpr rgb cornell_red{0.63, 0.065, 0.05};
inline constexpr rgb cornell_green{0.14, 0.45, 0.091};

// Blocks rest on the floor: no bottom face.
inline constexpr unsigned cornell_block_faces = all_box_faces & ~box_face_bit(1, false);

// The Cornell box's two blocks, at their published corners (mm) and heights.
template <int = 0>
inline oriented_box cornell_short_block(const qrm::detail::cornell_frame& fr) {
  return qrm::detail::published_block(fr, {{{130, 65}, {82, 225}, {240, 272}, {290, 114}}}, 165);
}
template <int = 0>
inline oriented_box cornell_tall_block(const qrm::detail::cornell_frame& fr) {
  return qrm::detail::published_block(fr, {{{423, 247}, {265, 296}, {314, 456}, {472, 406}}}, 330);
}

// The Cornell box's room (green wall at small x, red at large x, the rest white, front open) and
// its short block; what stands beside the short block is the caller's.
template <int = 0>
inline void add_cornell_room(voxelizer& vx, const qrm::detail::cornell_frame& fr, unsigned size) {
  const surface_material white{material::lambertian, cornell_white, {}, 0};
  const surface_material red{material::lambertian, cornell_red, {}, 0};
  const surface_material green{material::lambertian, cornell_green, {}, 0};
  // Faces -x, +x, -y, +y, -z (open), +z: the coloured walls come first, so they win the edges.
  vx.add_box(qrm::detail::room_box(size), {green, red, white, white, white, white}, qrm::detail::room_faces, true);
  vx.add_box(cornell_short_block(fr), white, cornell_block_faces);
}

// cornell_box(N, light_emission): the Cornell box (Cornell University's published data) in an
// N^3 grid (N >= 8). The paper's "modified Cornell box"; what differs from the published box:
//   - the room is a 550 mm cube (published: 549.6-556 mm wide, 548.8 mm high, 559.2 mm deep;
//     the largest difference, 9.2 mm, is one voxel at N = 64), walls one voxel thick, front
//     open, inside the absorbing shell;
//   - the blocks are the oriented boxes closest to their published top faces (rotations kept),
//     standing on the floor plane, without bottom faces;
//   - the light (130 x 105 mm at the ceiling's centre) is the set of ceiling voxels whose
//     centres lie in it (at least one voxel), flush with the ceiling and keeping the ceiling's
//     white reflectance; emission defaults to the common RGB radiance (17, 12, 4).
// Red wall at large x (seen on the left by box_scene_camera), green wall at x small.
template <int = 0>
scene cornell_box(unsigned size, const rgb& light_emission = {17, 12, 4}) {
  qrm::detail::check_box_scene_size("cornell_box", size);
  const qrm::detail::cornell_frame fr(size);
  voxelizer vx(size);
  add_cornell_room(vx, fr, size);
  vx.add_box(cornell_tall_block(fr), surface_material{material::lambertian, cornell_white, {}, 0}, cornell_block_faces);
  scene sc = vx.build("cornell_box_" + std::to_string(size));
  qrm::detail::paint_ceiling_light(sc, fr.at(213), fr.at(343), fr.at(227), fr.at(332), light_emission);
  sc.validate();
  return sc;
}

// two_spheres(N, light_emission): the paper's Fig. 5 setting: a grey room (reflectance 0.75),
// a square light of 165 x 165 mm (0.3 of the room) in the middle of the ceiling, and two
// spheres resting on the floor: a large blue one (radius 110 mm, at x = 385, z = 330 mm, seen
// on the left) and a small orange one (radius 70 mm, at x = 160, z = 200 mm, on the right).
// Same room, shell and units as cornell_box.
template <int = 0>
scene two_spheres(unsigned size, const rgb& light_emission = {10, 10, 10}) {
  qrm::detail::check_box_scene_size("two_spheres", size);
  const qrm::detail::cornell_frame fr(size);
  const surface_material grey{material::lambertian, {0.75, 0.75, 0.75}, {}, 0};
  voxelizer vx(size);
  vx.add_box(qrm::detail::room_box(size), grey, qrm::detail::room_faces, true);
  vx.add_sphere({fr.at(vec3{385, 110, 330}), fr.k * 110}, {material::lambertian, {0.2, 0.35, 0.75}, {}, 0});
  vx.add_sphere({fr.at(vec3{160, 70, 200}), fr.k * 70}, {material::lambertian, {0.8, 0.45, 0.15}, {}, 0});
  scene sc = vx.build("two_spheres_" + std::to_string(size));
  qrm::detail::paint_ceiling_light(sc, fr.at(192.5), fr.at(357.5), fr.at(192.5), fr.at(357.5), light_emission);
  sc.validate();
  return sc;
}

// cornell_mirror(N, reflectance, light_emission): the Cornell box (cornell_box above: room,
// light, short block) with the tall block replaced by a mirror sphere (specular, reflectance
// 0.9 grey, radius 110 mm resting on the floor at x = 385, z = 330 mm: where two_spheres puts
// its large sphere, between the short block and the red wall). Seen through box_scene_camera,
// its left limb reflects the red wall beside it, its top the ceiling and light, its right side
// the room and the green wall, its centre the open front (black).
// cornell_glossy(N, lobe): the same room with a glossy sphere (glossy_coin with that lobe).
template <int = 0>
inline scene cornell_sphere(unsigned size, const surface_material& ball, const std::string& name,
                            const rgb& light_emission = {17, 12, 4}) {
  qrm::detail::check_box_scene_size(name.c_str(), size);
  const qrm::detail::cornell_frame fr(size);
  voxelizer vx(size);
  add_cornell_room(vx, fr, size);
  vx.add_sphere({fr.at(vec3{385, 110, 330}), fr.k * 110}, ball);
  scene sc = vx.build(name + "_" + std::to_string(size));
  qrm::detail::paint_ceiling_light(sc, fr.at(213), fr.at(343), fr.at(227), fr.at(332), light_emission);
  sc.validate();
  return sc;
}
template <int = 0>
scene cornell_mirror(unsigned size, const rgb& reflectance = {0.9, 0.9, 0.9}) {
  return cornell_sphere(size, {material::specular, reflectance, {}, 0}, "cornell_mirror");
}
template <int = 0>
scene cornell_glossy(unsigned size, double lobe = 1.0, const rgb& reflectance = {0.9, 0.9, 0.9}) {
  if (!(lobe >= 0.0 && lobe <= glossy_lobe_max))
    throw std::invalid_argument("cornell_glossy: lobe " + std::to_string(lobe) + " outside [0, 4]");
  return cornell_sphere(size, {material::glossy, reflectance, {}, lobe}, "cornell_glossy");
}

// Participating media in the box scenes: a fog's per-voxel parameters at N^3 from those at the
// CLI's default 8^3, keeping the same optical depth. The room is 550 mm = N - 3 voxel lengths,
// so light crossing it passes N - 3 fog voxels; with density p_N per voxel the chance of
// crossing unscattered is (1 - p_N)^(N - 3), the same at every N when
//     p_N = 1 - (1 - p_8)^(5 / (N - 3)),   and likewise rho_N = rho_8^(5 / (N - 3)) per channel
// (the fraction kept per voxel crossed). (Thin fog: p_N ~ 5 p_8 / (N - 3), density per voxel
// falls as 1/N.) The walk stops in every fog voxel (walk/model.hpp), so a step crosses one
// voxel of fog: to cross the room light needs about N - 3 steps, and at large N the default 6
// steps see little beyond the fog near each start.
template <int = 0>
inline double fog_density_at(unsigned size, double density_at_8) {
  return 1.0 - std::pow(1.0 - density_at_8, 5.0 / (static_cast<double>(size) - 3.0));
}
template <int = 0>
inline rgb fog_reflectance_at(unsigned size, const rgb& rho_at_8) {
  const double e = 5.0 / (static_cast<double>(size) - 3.0);
  return {std::pow(rho_at_8.r, e), std::pow(rho_at_8.g, e), std::pow(rho_at_8.b, e)};
}

// cornell_fog(N, density_at_8, rho_at_8): the Cornell box (cornell_box above) with thin fog in
// every air voxel inside the room (voxel coordinates 2..N-3 on each axis, outside both blocks):
// material::medium with density fog_density_at(N, density_at_8) and reflectance
// fog_reflectance_at(N, rho_at_8). Defaults: at 8^3 a fog voxel scatters 10% of the light
// crossing it (the room's 5 voxels let 0.9^5 = 59% through unscattered) and absorbs 2%.
template <int = 0>
scene cornell_fog(unsigned size, double density_at_8 = 0.1, const rgb& rho_at_8 = {0.98, 0.98, 0.98}) {
  if (!(density_at_8 >= 0.0 && density_at_8 <= 1.0))
    throw std::invalid_argument("cornell_fog: density " + std::to_string(density_at_8) + " outside [0, 1]");
  for (int c = 0; c < 3; ++c)
    if (!(rho_at_8[c] >= 0.0 && rho_at_8[c] <= 1.0))
      throw std::invalid_argument("cornell_fog: rho " + std::to_string(rho_at_8[c]) + " outside [0, 1]");
  scene sc = cornell_box(size);
  sc.set_name("cornell_fog_" + std::to_string(size));
  const qrm::detail::cornell_frame fr(size);
  const std::array<oriented_box, 2> blocks{cornell_short_block(fr), cornell_tall_block(fr)};
  auto inside = [](const oriented_box& b, const vec3& p) {
    const vec3 r = qrm::detail::vec_sub(p, b.centre);
    for (std::size_t a = 0; a < 3; ++a)
      if (std::abs(dot(r, b.axes[a])) > b.half[a]) return false;
    return true;
  };
  voxel fog;
  fog.kind = material::medium;
  fog.density = fog_density_at(size, density_at_8);
  fog.reflectance = fog_reflectance_at(size, rho_at_8);
  for (unsigned z = 2; z + 3 <= size; ++z)
    for (unsigned y = 2; y + 3 <= size; ++y)
      for (unsigned x = 2; x + 3 <= size; ++x) {
        const vec3 c{x + 0.5, y + 0.5, z + 0.5};
        if (sc.at(x, y, z).kind == material::air && !inside(blocks[0], c) && !inside(blocks[1], c)) sc.at(x, y, z) = fog;
      }
  sc.validate();
  return sc;
}

// box_scene_camera(N, width, height): the Cornell box's published camera (at (278, 273, -800)
// mm looking along +z, up +y, 35 mm lens on 25 mm film: vertical field of view 2 atan(12.5/35)
// = 39.3 degrees) in the voxel coordinates of cornell_box(N) and two_spheres(N). It sits
// outside the grid and sees the room through its open front.
template <int = 0>
inline camera box_scene_camera(unsigned size, unsigned width, unsigned height) {
  qrm::detail::check_box_scene_size("box_scene_camera", size);
  const qrm::detail::cornell_frame fr(size);
  const vec3 eye = fr.at(vec3{278, 273, -800});
  const double fov = 2.0 * std::atan(12.5 / 35.0) * 180.0 / std::numbers::pi;
  return camera(eye, qrm::detail::vec_add(eye, vec3{0, 0, 1}), {0, 1, 0}, fov, width, height);
}

}  // namespace qrm::render

// This header's part of <qrm/render/compiled_render.hpp> (QRM_COMPILED_RENDER).
#define QRM_DETAIL_VOXELIZE_INSTANCES(PREFIX)                       \
  PREFIX scene voxelizer::build<0>(const std::string&, bool) const; \
  PREFIX scene cornell_box<0>(unsigned, const rgb&);                \
  PREFIX scene two_spheres<0>(unsigned, const rgb&);                \
  PREFIX scene cornell_mirror<0>(unsigned, const rgb&);             \
  PREFIX scene cornell_glossy<0>(unsigned, double, const rgb&);     \
  PREFIX scene cornell_fog<0>(unsigned, double, const rgb&);
#ifdef QRM_COMPILED_RENDER
namespace qrm::render {
QRM_DETAIL_VOXELIZE_INSTANCES(extern template)
}  // namespace qrm::render
#endif
