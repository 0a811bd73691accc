// examples/qrm/scaling_study.hpp: the scaling study's scenes, starts and sweep points (used by
// `qrm scaling`, bench_scaling and test_scaling); the formulas it checks are in qrm/walk/cost.hpp.
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <qrm/circuit/decompose.hpp>
#include <qrm/render/voxelize.hpp>
#include <qrm/walk/cost.hpp>
#include <qrm/walk/paper_scenes.hpp>

namespace qrm {

// ---- the scaling study's scenes, starts and sweeps ---------------------------------------------

// scaling_model(dims, size, directions): 2D box_2d(size) with the paper's 8 king directions
// (directions must be 8), or 3D cornell_box(size) with sphere_directions(directions, 3)
// (size >= 8: the Cornell box needs a shell and a wall layer on each side).
template <int = 0>
inline walk_model scaling_model(unsigned dims, unsigned size, std::size_t directions) {
  if (dims == 2) {
    if (directions != 8)
      throw std::invalid_argument("scaling_model: 2D walks use the paper's 8 directions, got " +
                                  std::to_string(directions));
    return walk_model(box_2d(size), king_2d());
  }
  if (dims == 3) return walk_model(render::cornell_box(size), sphere_directions(directions, 3));
  throw std::invalid_argument("scaling_model: dims must be 2 or 3, got " + std::to_string(dims));
}

// Where the scaling study's walks start (a light-map start: all directions in air, the inward
// direction on a surface).
//   near_light: two cells below the light: 2D (p/2 - 1, 2), under the top wall's light at
//               (p/2 - 1, 0); 3D (p/2, p - 4, p/2), under the ceiling light's centre voxel
//               (p/2, p - 2, p/2). Light is reachable in 2 steps at every p, so the pruned
//               circuits stay meaningful as p grows.
//   centre:     2D (p/2 - 2, p/2 - 2) (the air cell diagonally next to box_2d's central block;
//               its block cell at p = 4), 3D (p/2, p/2, p/2). At p >= 16 the light is more than
//               s steps away at most of scaling_sweep()'s points (2D p = 16 with s <= 6, 2D
//               p >= 32, 3D p >= 16), where the reachable-pruned circuit is empty (no path term
//               can fire).
enum class scaling_start { near_light, centre };
template <int = 0>
inline walk_start scaling_start_of(const walk_model& m, scaling_start where) {
  const unsigned p = m.scene_data().size();
  if (m.dims() == 2) {
    const unsigned c = p / 2 >= 2 ? p / 2 - 2 : 0;
    return m.light_map_start(where == scaling_start::near_light
                                 ? std::array<unsigned, 3>{p / 2 - 1, 2, 0}
                                 : std::array<unsigned, 3>{std::max(c, 1u), std::max(c, 1u), 0});
  }
  return m.light_map_start(where == scaling_start::near_light ? std::array<unsigned, 3>{p / 2, p - 4, p / 2}
                                                              : std::array<unsigned, 3>{p / 2, p / 2, p / 2});
}

// One point of the study: which parameter its sweep varies ("p", "s" or "d") and the circuit.
struct scaling_case {
  char sweep = 'p';
  unsigned dims = 2, size = 8, steps = 3;
  std::size_t directions = 8;
  walk_variant variant = walk_variant::faithful;
  pruning prune = pruning::none;
  bool decompose = false;  // lower to 1q + CNOT too (expensive: see scaling_sweep)
};

template <int = 0>
inline std::string scaling_case_name(const scaling_case& c) {
  return std::string(1, c.sweep) + "/" + std::to_string(c.dims) + "d/p" + std::to_string(c.size) + "/s" +
         std::to_string(c.steps) + "/d" + std::to_string(c.directions) + "/" +
         (c.variant == walk_variant::faithful ? "faithful" : "history") + "/" + pruning_name(c.prune);
}

// scaling_sweep(): the study's points, every variant and pruning level at each:
//   p (2D): p = 4..256, s = 3, d = 8          p (3D): p = 8..64, s = 2, d = 15
//   s (2D): p = 16, s = 1..8, d = 8           s (3D): p = 8, s = 1..8, d = 15
//   d (3D): p = 8, s = 3, d in {6, 14, 15, 26, 32, 64, 128}
// Decomposition into 1q + CNOT gates (hundreds of thousands to millions of gates, each held in
// memory: ~1.6 GB and 2.3 s for the unpruned 3D p = 8, s = 3 circuit) is done where it takes at
// most a few seconds: 2D p <= 64; 3D p = 8 with s <= 3 and d <= 15; and every reachable-pruned
// 3D circuit with p <= 16 or s <= 3 (they are small).
template <int = 0>
inline std::vector<scaling_case> scaling_sweep() {
  std::vector<scaling_case> out;
  auto add = [&](scaling_case c, auto decompose_if) {
    for (walk_variant v : {walk_variant::faithful, walk_variant::history})
      for (pruning pr : {pruning::none, pruning::scene, pruning::reachable}) {
        c.variant = v;
        c.prune = pr;
        c.decompose = decompose_if(c);
        out.push_back(c);
      }
  };
  auto small_3d = [](const scaling_case& c) {
    return (c.size == 8 && c.steps <= 3 && c.directions <= 15) ||
           (c.prune == pruning::reachable && (c.size <= 16 || c.steps <= 3) && c.directions <= 32);
  };
  for (unsigned p = 4; p <= 256; p *= 2) add({'p', 2, p, 3, 8}, [](const scaling_case& c) { return c.size <= 64; });
  for (unsigned p = 8; p <= 64; p *= 2) add({'p', 3, p, 2, 15}, small_3d);
  for (unsigned s = 1; s <= 8; ++s) add({'s', 2, 16, s, 8}, [](const scaling_case&) { return true; });
  for (unsigned s = 1; s <= 8; ++s) add({'s', 3, 8, s, 15}, small_3d);
  for (std::size_t d : {6, 14, 15, 26, 32, 64, 128}) add({'d', 3, 8, 3, d}, small_3d);
  return out;
}

// What the study reports for one point.
struct scaling_result {
  scaling_case where;
  walk_start start;
  std::size_t width = 0, width_formula = 0, full_width = 0;
  circuit_metrics logical;
  walk_layer_metrics layers;
  std::size_t unpruned_depth_formula = 0;  // the closed form (pruning::none points only; else 0)
  std::size_t shift_pairs = 0;             // a: adds per Shift layer
  std::optional<decomposed_counts> decomposed;
};

// measure_scaling_case(c, start): build the point's circuit and measure it.
template <int = 0>
inline scaling_result measure_scaling_case(const scaling_case& c, scaling_start where = scaling_start::near_light) {
  const walk_model m = scaling_model(c.dims, c.size, c.directions);
  scaling_result r;
  r.where = c;
  r.start = scaling_start_of(m, where);
  walk_options o;
  o.steps = c.steps;
  o.variant = c.variant;
  o.prune = c.prune;
  const walk_program w = make_walk_program(m, r.start, o);
  r.logical = circuit_metrics_of(w.circuit);
  r.width = r.logical.width;
  r.full_width = w.full_width;
  r.width_formula =
      walk_width_formula(m.dims(), m.position_bits(), m.fractional_bits(), m.direction_bits(), c.steps, c.variant);
  r.layers = walk_layers(w.circuit);
  r.shift_pairs = shift_pairs(m.directions());
  if (c.prune == pruning::none) r.unpruned_depth_formula = unpruned_walk_depth(m, r.start, c.steps, c.variant);
  if (c.decompose) r.decomposed = decomposed_metrics(w.circuit);
  return r;
}

}  // namespace qrm
