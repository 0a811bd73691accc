// qrm/render/dda.hpp: the first voxel a ray hits, by voxel traversal (Amanatides and Woo's 3D
// DDA, 1987) through a scene's N^3 grid.
//
// Voxel (i, j, k) is the half-open cube [i, i+1) x [j, j+1) x [k, k+1) in voxel coordinates. A
// ray o + t d (t >= 0) passes through a voxel when it spends a positive length in it; a ray
// that only touches a voxel at an edge or a corner does not pass through it (where the ray
// crosses an edge or a corner, the traversal steps every tied axis at once), and a ray lying
// in a voxel face plane belongs to the voxel on the + side of that plane.
//
// What stops a ray: any voxel that is not air, except `boundary` voxels, which the renderer's
// scenes use as the absorbing shell that closes the grid (so a camera outside the grid looks in
// through the shell); dda_options::stop_at_boundary makes them stop rays too.
//
// The walk's start for a hit (direction nearest the ray) is `hit_walk_start` in
// render_classical.hpp, which needs the walk model.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "detail/vec3.hpp"
#include "../walk/scene.hpp"

namespace qrm::render {

struct dda_options {
  bool stop_at_boundary = false;
};

struct voxel_hit {
  bool hit = false;
  std::array<unsigned, 3> voxel{0, 0, 0};
  std::size_t index = 0;  // scene index of the voxel
  double t = 0;           // ray parameter where the ray enters the voxel (0 if it starts inside)
  vec3 point{0, 0, 0};    // origin + t * direction
  int axis = -1;          // axis of the face crossed into the voxel; -1 if the ray starts inside it
  int side = 0;           // the crossed face's outward normal is side * e_axis
  explicit operator bool() const { return hit; }
};

// stops_ray(scene, index, options): whether a voxel ends the traversal.
template <int = 0>
inline bool stops_ray(const scene& s, std::size_t index, const dda_options& o = {}) {
  const material k = s[index].kind;
  return k != material::air && (k != material::boundary || o.stop_at_boundary);
}

// first_hit(scene, origin, direction, options): the first voxel along the ray that stops it.
// `direction` need not be unit length (t is in units of it); origins outside the grid are fine.
template <int = 0>
voxel_hit first_hit(const scene& s, const vec3& origin, const vec3& direction, const dda_options& opt = {}) {
  if (s.dims() != 3) throw std::invalid_argument("first_hit: scene '" + s.name() + "' is not 3D");
  if (!qrm::detail::vec_finite(origin) || !qrm::detail::vec_finite(direction) || !(norm(direction) > 0))
    throw std::invalid_argument("first_hit: the ray's origin and direction must be finite and the direction non-zero");
  const double n = static_cast<double>(s.size());
  const double inf = std::numeric_limits<double>::infinity();
  // Clip to the grid: the ray is inside for t in [t_enter, t_exit).
  double t_enter = 0, t_exit = inf;
  int enter_axis = -1;
  for (int a = 0; a < 3; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    const double o = origin[ua], d = direction[ua];
    if (d == 0) {
      if (!(o >= 0 && o < n)) return {};
      continue;
    }
    double t0 = (0 - o) / d, t1 = (n - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_enter) {
      t_enter = t0;
      enter_axis = a;
    }
    t_exit = std::min(t_exit, t1);
  }
  if (!(t_enter < t_exit)) return {};

  const auto last = static_cast<long long>(s.size()) - 1;
  std::array<long long, 3> idx{};
  std::array<double, 3> t_max{};
  auto next_boundary_t = [&](int a) {
    const auto ua = static_cast<std::size_t>(a);
    const double d = direction[ua];
    if (d > 0) return (static_cast<double>(idx[ua] + 1) - origin[ua]) / d;
    if (d < 0) return (static_cast<double>(idx[ua]) - origin[ua]) / d;
    return inf;
  };
  for (int a = 0; a < 3; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    const double d = direction[ua];
    if (a == enter_axis) {
      idx[ua] = d > 0 ? 0 : last;
    } else {
      // The voxel the ray is in just after t_enter: on a boundary, the one it moves into.
      const double p = t_enter == 0 ? origin[ua] : origin[ua] + t_enter * d;
      const double fl = std::floor(p);
      long long i = static_cast<long long>(fl);
      if (d < 0 && p == fl) --i;
      idx[ua] = std::clamp(i, 0LL, last);
      if (d == 0) continue;
      // p may be rounded across a boundary: settle the index with the same expressions that
      // give the crossing times below, so that the traversal is consistent with itself.
      // Voxel j is entered at enter_t(j) and left at enter_t(j + step).
      const long long step = d > 0 ? 1 : -1;
      auto enter_t = [&](long long j) { return (static_cast<double>(d > 0 ? j : j + 1) - origin[ua]) / d; };
      auto in_grid = [&](long long j) { return j >= 0 && j <= last; };
      while (in_grid(idx[ua] + step) && enter_t(idx[ua] + step) <= t_enter) idx[ua] += step;
      while (in_grid(idx[ua] - step) && enter_t(idx[ua]) > t_enter) idx[ua] -= step;
    }
  }
  for (int a = 0; a < 3; ++a) t_max[static_cast<std::size_t>(a)] = next_boundary_t(a);

  voxel_hit h;
  h.t = t_enter;
  h.axis = enter_axis;
  h.side = enter_axis < 0 ? 0 : (direction[static_cast<std::size_t>(enter_axis)] > 0 ? -1 : 1);
  const auto size = static_cast<std::size_t>(s.size());
  for (;;) {
    const std::size_t i = static_cast<std::size_t>(idx[0]) +
                          size * (static_cast<std::size_t>(idx[1]) + size * static_cast<std::size_t>(idx[2]));
    if (stops_ray(s, i, opt)) {
      h.hit = true;
      h.index = i;
      h.voxel = {static_cast<unsigned>(idx[0]), static_cast<unsigned>(idx[1]), static_cast<unsigned>(idx[2])};
      h.point = qrm::detail::vec_add_scaled(origin, direction, h.t);
      return h;
    }
    const double t_next = std::min({t_max[0], t_max[1], t_max[2]});
    if (!(t_next < t_exit)) return {};
    h.axis = -1;
    for (int a = 0; a < 3; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      if (t_max[ua] != t_next) continue;  // every axis crossing at t_next steps (edges, corners)
      const bool up = direction[ua] > 0;
      if (h.axis < 0) {
        h.axis = a;
        h.side = up ? -1 : 1;
      }
      idx[ua] += up ? 1 : -1;
      if (idx[ua] < 0 || idx[ua] > last) return {};
      t_max[ua] = next_boundary_t(a);
    }
    h.t = t_next;
  }
}

}  // namespace qrm::render

// This header's part of <qrm/render/compiled_render.hpp> (QRM_COMPILED_RENDER).
#define QRM_DETAIL_DDA_INSTANCES(PREFIX)                                                     \
  PREFIX voxel_hit first_hit<0>(const scene&, const vec3&, const vec3&, const dda_options&);
#ifdef QRM_COMPILED_RENDER
namespace qrm::render {
QRM_DETAIL_DDA_INSTANCES(extern template)
}  // namespace qrm::render
#endif
