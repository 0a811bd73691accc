// examples/qrm/scene_arg.hpp: `--scene NAME|FILE` for the qrm tool.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <qrm/walk/paper_scenes.hpp>
#include <qrm/walk/scene_format.hpp>
#include <qrm/walk/circuit.hpp>

#include "args.hpp"

namespace qrm_cli {

// A built-in 2D scene name, or a scene file. `builtins` lists the names the calling command
// accepts, for the error message (render also takes the 3D scenes).
inline qrm::scene scene_from_arg(const std::string& value, const std::string& builtins = "paper_4x4, paper_8x8") {
  if (value == "paper_8x8" || value == "paper_4x4") return qrm::builtin_2d_scene(value);
  if (!std::filesystem::exists(value))
    throw usage_error("--scene: '" + value + "' is neither a built-in scene (" + builtins + ") nor an existing file");
  if (std::filesystem::is_directory(value))
    throw usage_error("--scene: '" + value + "' is a directory, not a scene file");
  return qrm::load_scene(value);
}

// --march voxel|surface, if given.
inline std::optional<qrm::march_mode> march_flag(const args& a) {
  if (!a.has("march")) return std::nullopt;
  const std::string m = a.str("march", "");
  if (m != "voxel" && m != "surface") throw usage_error("--march must be voxel or surface, got '" + m + "'");
  return m == "voxel" ? qrm::march_mode::voxel : qrm::march_mode::surface;
}

// The walk every command runs on `sc`: --march, else the scene's own `march` line, else the
// surface march (one bounce per step). The paper's scenes declare the voxel march, so their
// numbers stay the paper's; a user's room is walked the same way by render, lightmap, circuit,
// resources and crossover.
inline qrm::march_mode march_for(std::optional<qrm::march_mode> flag, const qrm::scene& sc) {
  return flag.value_or(sc.march().value_or(qrm::march_mode::surface));
}

// --march's row in a command's --help.
inline flag march_flag_row(const char* group) {
  return {"march", "voxel|surface", "the scene's, else surface",
          "how the walk moves: voxel = one voxel per step (the paper's Section 4; paper_4x4 and paper_8x8 ask for it), "
          "surface = one bounce per step (to the next non-air voxel)",
          group};
}

inline qrm::pruning pruning_from_arg(const std::string& v) {
  if (v == "none") return qrm::pruning::none;
  if (v == "scene") return qrm::pruning::scene;
  if (v == "reachable") return qrm::pruning::reachable;
  throw usage_error("--prune must be none, scene or reachable, got '" + v + "'");
}

// One light-map cell's walk circuit as the flags name it: --x, --y (in the grid), --steps
// (1..16, default 3), --channel (0..2), --prune (default reachable). `sc` must be 2D.
struct walk_cell {
  std::array<unsigned, 3> cell{};
  qrm::walk_options options;
};
inline walk_cell walk_cell_from_flags(const args& a, const qrm::scene& sc, unsigned default_x, unsigned default_y) {
  if (sc.dims() != 2) throw usage_error("--scene must be a 2D scene, got the 3D scene '" + sc.name() + "'");
  const auto n = static_cast<std::int64_t>(sc.size()) - 1;
  walk_cell w;
  w.cell = {static_cast<unsigned>(a.integer("x", default_x, 0, n)), static_cast<unsigned>(a.integer("y", default_y, 0, n)), 0};
  w.options.steps = static_cast<unsigned>(a.integer("steps", 3, 1, 16));
  w.options.channel = static_cast<int>(a.integer("channel", 0, 0, 2));
  w.options.prune = pruning_from_arg(a.str("prune", "reachable"));
  return w;
}

}  // namespace qrm_cli
