// examples/qrm/scene_arg.hpp: `--scene NAME|FILE` for the qrm tool.
#pragma once

#include <filesystem>
#include <string>

#include <qrm/walk/paper_scenes.hpp>
#include <qrm/walk/scene_format.hpp>

#include "args.hpp"

namespace qrm_cli {

// A built-in 2D scene name, or a scene file. `builtins` lists the names the calling command
// accepts, for the error message (render also takes the 3D scenes).
inline qrm::scene scene_from_arg(const std::string& value, const std::string& builtins = "paper_4x4, paper_8x8") {
  if (value == "paper_8x8" || value == "paper_4x4") return qrm::builtin_2d_scene(value);
  if (!std::filesystem::exists(value))
    throw usage_error("--scene: '" + value + "' is neither a built-in scene (" + builtins + ") nor an existing file");
  return qrm::load_scene(value);
}

inline qrm::pruning pruning_from_arg(const std::string& v) {
  if (v == "none") return qrm::pruning::none;
  if (v == "scene") return qrm::pruning::scene;
  if (v == "reachable") return qrm::pruning::reachable;
  throw usage_error("--prune must be none, scene or reachable, got '" + v + "'");
}

}  // namespace qrm_cli
