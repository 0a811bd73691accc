// qrm/walk/directions.hpp: the discrete directions a walker can move in, and their displacements.
//
// 2D: the paper's 8 king moves, index -> (dx, dy): 0 N (0,-1), 1 NE (1,-1), 2 E (1,0),
// 3 SE (1,1), 4 S (0,1), 5 SW (-1,1), 6 W (-1,0), 7 NW (-1,-1); one step moves one cell per axis.
// 3D: an even set of D unit vectors on the sphere (golden spiral, as the authors used, or the
// symmetric sets of 6, 14 and 26 directions); positions are fixed point with `fractional_bits`
// sub-voxel bits, and a step moves one voxel length: displacement = round(v * 2^F) per axis.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/registers.hpp"
#include "scene.hpp"

namespace qrm {

struct direction_set {
  std::string name;
  unsigned dims = 2;
  unsigned fractional_bits = 0;
  std::vector<vec3> vectors;                             // unit vectors
  std::vector<std::array<std::int64_t, 3>> displacement;  // per step, in units of 2^-F voxels

  std::size_t size() const { return vectors.size(); }
  // Qubits of the direction register.
  unsigned bits() const { return static_cast<unsigned>(bits_for(vectors.size())); }
};

// king_2d(): the paper's 8 directions (3 qubits).
template <int = 0>
inline direction_set king_2d() {
  direction_set s;
  s.name = "king-8";
  s.dims = 2;
  for (int i = 0; i < 8; ++i) {
    s.vectors.push_back(compass_vector_2d(i));
    s.displacement.push_back({compass_2d[i][0], compass_2d[i][1], 0});
  }
  return s;
}

namespace detail {
template <int = 0>
inline void add_displacements(direction_set& s) {
  const double unit = std::ldexp(1.0, static_cast<int>(s.fractional_bits));
  s.displacement.clear();
  for (const vec3& v : s.vectors) {
    std::array<std::int64_t, 3> d{};
    for (int a = 0; a < 3; ++a) d[static_cast<std::size_t>(a)] = std::llround(v[static_cast<std::size_t>(a)] * unit);
    if (d[0] == 0 && d[1] == 0 && d[2] == 0)
      throw std::invalid_argument("direction set: a direction rounds to no movement with " +
                                  std::to_string(s.fractional_bits) + " fractional bits");
    s.displacement.push_back(d);
  }
}
}  // namespace detail

// golden_spiral(D, F): D directions on the golden spiral (z from 1 - 1/D down to -1 + 1/D).
template <int = 0>
direction_set golden_spiral(std::size_t count, unsigned fractional_bits = 3) {
  if (count < 2 || count > 1024)
    throw std::invalid_argument("golden_spiral: direction count must be in [2, 1024], got " + std::to_string(count));
  direction_set s;
  s.name = "golden-" + std::to_string(count);
  s.dims = 3;
  s.fractional_bits = fractional_bits;
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(count);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden_angle * static_cast<double>(i);
    s.vectors.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  detail::add_displacements(s);
  return s;
}

// antipodal_spiral(D, F): D/2 golden-spiral directions of the upper hemisphere and their
// opposites (D even), so every direction can be reversed exactly.
template <int = 0>
direction_set antipodal_spiral(std::size_t count, unsigned fractional_bits = 3) {
  if (count < 2 || count % 2 != 0 || count > 1024)
    throw std::invalid_argument("antipodal_spiral: direction count must be even and in [2, 1024], got " +
                                std::to_string(count));
  direction_set s = golden_spiral(count, fractional_bits);
  s.name = "antipodal-" + std::to_string(count);
  for (std::size_t i = 0; i < count / 2; ++i) {
    const vec3& v = s.vectors[i];
    s.vectors[count / 2 + i] = {-v[0], -v[1], -v[2]};
  }
  detail::add_displacements(s);
  return s;
}

// cube_directions(D, F): D = 6 (axes), 14 (axes and cube diagonals) or 26 (all king moves).
template <int = 0>
direction_set cube_directions(std::size_t count, unsigned fractional_bits = 3) {
  if (count != 6 && count != 14 && count != 26)
    throw std::invalid_argument("cube_directions: count must be 6, 14 or 26, got " + std::to_string(count));
  direction_set s;
  s.name = "cube-" + std::to_string(count);
  s.dims = 3;
  s.fractional_bits = fractional_bits;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        const int nonzero = (x != 0) + (y != 0) + (z != 0);
        const bool keep = nonzero == 1 || (count >= 14 && nonzero == 3) || (count == 26 && nonzero == 2);
        if (nonzero > 0 && keep) s.vectors.push_back(normalized({double(x), double(y), double(z)}));
      }
  detail::add_displacements(s);
  return s;
}

// sphere_directions(D, F): the symmetric cube sets for D in {6, 14, 26}, else the golden spiral
// (the authors' choice; they used D = 15).
template <int = 0>
inline direction_set sphere_directions(std::size_t count, unsigned fractional_bits = 3) {
  if (count == 6 || count == 14 || count == 26) return cube_directions(count, fractional_bits);
  return golden_spiral(count, fractional_bits);
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_DIRECTIONS_INSTANCES(PREFIX)                    \
  PREFIX direction_set golden_spiral<0>(std::size_t, unsigned);    \
  PREFIX direction_set antipodal_spiral<0>(std::size_t, unsigned); \
  PREFIX direction_set cube_directions<0>(std::size_t, unsigned);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_DIRECTIONS_INSTANCES(extern template)
}  // namespace qrm
#endif
