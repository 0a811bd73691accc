// qrm/paper_scenes.hpp: the paper's 2D scenes, paper_4x4 and paper_8x8, with exactly the data
// and conventions of SPEC.md section 3 (taken from the authors' code).
#pragma once

#include <stdexcept>
#include <string>

#include "scene.hpp"
#include "scene_io.hpp"

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
inline scene paper_8x8() {
  return parse_scene(std::string("qrm-scene 1\nname paper_8x8\ndims 2\nsize 8\n") + detail::paper_palette +
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
inline scene paper_4x4() {
  return parse_scene(std::string("qrm-scene 1\nname paper_4x4\ndims 2\nsize 4\n") + detail::paper_palette +
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

// builtin_scene(name): paper_4x4 or paper_8x8 (the 3D scenes live with the renderer).
inline scene builtin_2d_scene(const std::string& name) {
  if (name == "paper_8x8") return paper_8x8();
  if (name == "paper_4x4") return paper_4x4();
  throw std::invalid_argument("unknown built-in scene '" + name + "' (paper_4x4, paper_8x8)");
}

}  // namespace qrm
