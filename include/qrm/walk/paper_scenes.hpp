// qrm/walk/paper_scenes.hpp: the paper's 2D scenes, paper_4x4 and paper_8x8, with exactly the data
// and conventions of the authors' code (x = column, y = row growing downwards, directions 0 N,
// 1 NE, ..., 7 NW; the cell tables below are theirs).
#pragma once

#include <stdexcept>
#include <string>

#include "scene.hpp"

namespace qrm {

namespace detail {
// The authors' tables, cell by cell: a kinds table gives each cell a material and a normal
// (compass index 0 N, 1 NE, ..., 7 NW), the colour tables its emission and reflectance. They are
// C++ data rather than scene-format text, so a program that uses the paper's scenes does not
// compile the scene parser; examples/scenes/paper_*.txt hold the same tables as text (a test
// parses them and compares voxel by voxel).
struct paper_cell {
  material kind;
  int normal;
};
namespace paper_table {
inline constexpr paper_cell air{material::air, -1};
inline constexpr paper_cell L0{material::lambertian, 0}, L1{material::lambertian, 1}, L2{material::lambertian, 2},
    L3{material::lambertian, 3}, L4{material::lambertian, 4}, L5{material::lambertian, 5}, L6{material::lambertian, 6},
    L7{material::lambertian, 7};
inline constexpr paper_cell B0{material::boundary, 0}, B1{material::boundary, 1}, B3{material::boundary, 3},
    B5{material::boundary, 5}, B7{material::boundary, 7};
// Emission: k none, w a light. Reflectance: W white, A air (unused), R red, G green, Bl blue, Gy grey.
inline constexpr rgb k{0, 0, 0}, w{1, 1, 1};
inline constexpr rgb W{1, 1, 1}, A{1, 1, 1}, R{0.5, 0, 0}, G{0, 0.5, 0}, Bl{0, 0, 0.5}, Gy{0.75, 0.75, 0.75};
}  // namespace paper_table

// A 2D scene of the paper's kind from its three tables (rows y = 0 first, x = column), made for
// the voxel march.
template <std::size_t N>
scene paper_scene(const char* name, const paper_cell (&kinds)[N][N], const rgb (&emission)[N][N],
                  const rgb (&reflectance)[N][N]) {
  scene s(name, 2, static_cast<unsigned>(N));
  s.set_march(march_mode::voxel);
  for (unsigned y = 0; y < N; ++y)
    for (unsigned x = 0; x < N; ++x) {
      voxel& v = s.at(x, y);
      v.kind = kinds[y][x].kind;
      v.normal_index = kinds[y][x].normal;
      v.normal = v.normal_index < 0 ? vec3{0, 0, 0} : compass_vector_2d(v.normal_index);
      v.emission = emission[y][x];
      v.reflectance = reflectance[y][x];
    }
  s.validate();
  return s;
}
}  // namespace detail

// paper_8x8(): the 8x8 scene of the paper's Fig. 4.
template <int = 0>
scene paper_8x8() {
  using namespace detail::paper_table;
  static constexpr detail::paper_cell kinds[8][8] = {
      {B3, L4,  L4,  L4,  L4,  L4,  L4,  B5},
      {L2, air, air, air, air, air, air, L6},
      {L2, air, air, air, air, air, air, L6},
      {L2, air, L7,  L0,  L1,  air, air, L6},
      {L2, air, L6,  B0,  L2,  air, air, L6},
      {L2, air, L5,  L4,  L3,  air, air, L6},
      {L2, air, air, air, air, air, air, L6},
      {B1, L0,  L0,  L0,  L0,  L0,  L0,  B7}};
  static constexpr rgb emission[8][8] = {
      {k, k, k, w, w, k, k, k},
      {w, k, k, k, k, k, k, k},
      {w, k, k, k, k, k, k, k},
      {w, k, k, k, k, k, k, w},
      {w, k, k, k, w, k, k, w},
      {w, k, k, k, k, k, k, k},
      {w, k, k, k, k, k, k, k},
      {k, k, k, w, w, k, k, k}};
  static constexpr rgb reflectance[8][8] = {
      {Gy, G,  G,  W,  W,  G, G, Gy},
      {W,  A,  A,  A,  A,  A, A, R},
      {W,  A,  A,  A,  A,  A, A, R},
      {W,  A,  Bl, R,  Bl, A, A, W},
      {W,  A,  R,  Bl, W,  A, A, W},
      {W,  A,  Bl, R,  Bl, A, A, R},
      {W,  A,  A,  A,  A,  A, A, Gy},
      {Gy, Gy, Gy, W,  W,  Gy, Gy, Gy}};
  return detail::paper_scene("paper_8x8", kinds, emission, reflectance);
}

// paper_4x4(): the paper's small 4x4 scene.
template <int = 0>
scene paper_4x4() {
  using namespace detail::paper_table;
  static constexpr detail::paper_cell kinds[4][4] = {
      {B3, L4,  L4,  B5},
      {L2, air, air, L6},
      {L2, air, air, L6},
      {B1, L0,  L0,  B7}};
  static constexpr rgb emission[4][4] = {
      {k, k, w, k},
      {k, k, k, k},
      {w, k, k, k},
      {k, k, k, k}};
  static constexpr rgb reflectance[4][4] = {
      {Gy, Gy, Gy, Gy},
      {Gy, A,  A,  R},
      {Gy, A,  A,  R},
      {Gy, Bl, G,  Gy}};
  return detail::paper_scene("paper_4x4", kinds, emission, reflectance);
}

// box_2d(N): the 8x8 scene's layout at any size N = 2^P >= 4, for scaling studies: boundary
// corners, Lambertian walls facing inward (grey, red right wall, green top wall), two lights on
// the top wall and one on the left wall, and a Lambertian block in the middle.
template <int = 0>
scene box_2d(unsigned n) {
  if (n < 4) throw std::invalid_argument("box_2d: size must be at least 4, got " + std::to_string(n));
  scene s("box_" + std::to_string(n), 2, n);
  const rgb grey{0.75, 0.75, 0.75}, red{0.5, 0, 0}, green{0, 0.5, 0}, white{1, 1, 1};
  auto wall = [&](unsigned x, unsigned y, material k, int normal, rgb rho, rgb le = {}) {
    voxel& v = s.at(x, y);
    v.kind = k;
    v.normal_index = normal;
    v.normal = compass_vector_2d(normal);
    v.reflectance = rho;
    v.emission = le;
  };
  for (unsigned i = 1; i + 1 < n; ++i) {
    const bool light = i == n / 2 || i + 1 == n / 2;
    wall(i, 0, material::lambertian, 4, green, light ? white : rgb{});
    wall(i, n - 1, material::lambertian, 0, grey);
    wall(0, i, material::lambertian, 2, grey, i == n / 2 ? white : rgb{});
    wall(n - 1, i, material::lambertian, 6, red);
  }
  wall(0, 0, material::boundary, 3, grey);
  wall(n - 1, 0, material::boundary, 5, grey);
  wall(0, n - 1, material::boundary, 1, grey);
  wall(n - 1, n - 1, material::boundary, 7, grey);
  const unsigned c = n / 2;
  wall(c - 1, c - 1, material::lambertian, 7, grey);
  wall(c, c - 1, material::lambertian, 1, grey);
  wall(c - 1, c, material::lambertian, 5, grey);
  wall(c, c, material::lambertian, 3, grey);
  s.validate();
  return s;
}

// builtin_scene(name): paper_4x4 or paper_8x8 (the 3D scenes live with the renderer).
template <int = 0>
scene builtin_2d_scene(const std::string& name) {
  if (name == "paper_8x8") return paper_8x8();
  if (name == "paper_4x4") return paper_4x4();
  throw std::invalid_argument("unknown built-in scene '" + name + "' (paper_4x4, paper_8x8)");
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_PAPER_SCENES_INSTANCES(PREFIX)       \
  PREFIX scene paper_8x8<0>();                          \
  PREFIX scene paper_4x4<0>();                          \
  PREFIX scene box_2d<0>(unsigned);                     \
  PREFIX scene builtin_2d_scene<0>(const std::string&);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_PAPER_SCENES_INSTANCES(extern template)
}  // namespace qrm
#endif
