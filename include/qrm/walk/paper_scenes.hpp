// qrm/walk/paper_scenes.hpp: the paper's 2D scenes, paper_4x4 and paper_8x8, with exactly the data
// and conventions of the authors' code (x = column, y = row growing downwards, directions 0 N,
// 1 NE, ..., 7 NW; the cell tables below are theirs).
#pragma once

#include <stdexcept>
#include <string>

#include "scene.hpp"
#include "scene_format.hpp"

namespace qrm {

namespace detail {
inline constexpr const char* paper_palette =
    "color k 0 0 0\n"
    "color w 1 1 1\n"
    "color W 1 1 1\n"
    "color A 1 1 1\n"
    "color R 0.5 0 0\n"
    "color G 0 0.5 0\n"
    "color Bl 0 0 0.5\n"
    "color Gy 0.75 0.75 0.75\n";
}

// paper_8x8(): the 8x8 scene of the paper's Fig. 4.
template <int = 0>
inline scene paper_8x8() {
  return parse_scene(std::string("qrm-scene 1\nname paper_8x8\ndims 2\nsize 8\nmarch voxel\n") + detail::paper_palette +
                         "kinds\n"
                         "B3 L4 L4 L4 L4 L4 L4 B5\n"
                         "L2 .  .  .  .  .  .  L6\n"
                         "L2 .  .  .  .  .  .  L6\n"
                         "L2 .  L7 L0 L1 .  .  L6\n"
                         "L2 .  L6 B0 L2 .  .  L6\n"
                         "L2 .  L5 L4 L3 .  .  L6\n"
                         "L2 .  .  .  .  .  .  L6\n"
                         "B1 L0 L0 L0 L0 L0 L0 B7\n"
                         "emission\n"
                         "k k k w w k k k\n"
                         "w k k k k k k k\n"
                         "w k k k k k k k\n"
                         "w k k k k k k w\n"
                         "w k k k w k k w\n"
                         "w k k k k k k k\n"
                         "w k k k k k k k\n"
                         "k k k w w k k k\n"
                         "reflectance\n"
                         "Gy G G W W G G Gy\n"
                         "W A A A A A A R\n"
                         "W A A A A A A R\n"
                         "W A Bl R Bl A A W\n"
                         "W A R Bl W A A W\n"
                         "W A Bl R Bl A A R\n"
                         "W A A A A A A Gy\n"
                         "Gy Gy Gy W W Gy Gy Gy\n",
                     "paper_8x8");
}

// paper_4x4(): the paper's small 4x4 scene.
template <int = 0>
inline scene paper_4x4() {
  return parse_scene(std::string("qrm-scene 1\nname paper_4x4\ndims 2\nsize 4\nmarch voxel\n") + detail::paper_palette +
                         "kinds\n"
                         "B3 L4 L4 B5\n"
                         "L2 .  .  L6\n"
                         "L2 .  .  L6\n"
                         "B1 L0 L0 B7\n"
                         "emission\n"
                         "k k w k\n"
                         "k k k k\n"
                         "w k k k\n"
                         "k k k k\n"
                         "reflectance\n"
                         "Gy Gy Gy Gy\n"
                         "Gy A A R\n"
                         "Gy A A R\n"
                         "Gy Bl G Gy\n",
                     "paper_4x4");
}

// box_2d(N): the 8x8 scene's layout at any size N = 2^P >= 4, for scaling studies: boundary
// corners, Lambertian walls facing inward (grey, red right wall, green top wall), two lights on
// the top wall and one on the left wall, and a Lambertian block in the middle.
template <int = 0>
inline scene box_2d(unsigned n) {
  if (n < 4) throw std::invalid_argument("box_2d: size must be at least 4, got " + std::to_string(n));
  scene s("box_" + std::to_string(n), 2, n);
  const rgb grey{0.75, 0.75, 0.75}, red{0.5, 0, 0}, green{0, 0.5, 0}, white{1, 1, 1};
  auto wall = [&](unsigned x, unsigned y, material k, int normal, rgb rho, rgb le = {}) {
    voxel& v = s.at(x, y);
    v.kind = k;
    v.normal_index = normal;
    static const int dxy[8][2] = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}};
    v.normal = normalized({double(dxy[normal][0]), double(dxy[normal][1]), 0.0});
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
inline scene builtin_2d_scene(const std::string& name) {
  if (name == "paper_8x8") return paper_8x8();
  if (name == "paper_4x4") return paper_4x4();
  throw std::invalid_argument("unknown built-in scene '" + name + "' (paper_4x4, paper_8x8)");
}

}  // namespace qrm
