// qrm/scaling.hpp: how the A operator's width and depth grow with the number of steps s, the
// positions per axis p and the directions d, against the paper's Section 6 (width
// O(s + log p + log d), depth O(s (p^3 + d))). Used by `qrm scaling` (the report), bench_scaling
// (the same points, timed) and test_scaling.
//
// Width, exactly (make_walk_qubits; P = log2 p position bits, F fractional bits per axis, D the
// direction register's bits, history = (s - 1) D extra qubits in the history variant):
//     width = 1 (out) + bits_for(s) (steps) + s (Le) + (s - 1) (rho) [+ (s - 1) D] + D + dims (P + F)
// where bits_for(s) = max(1, ceil(log2 s)). One more step adds 2 qubits (Le_s and rho_{s-1}),
// plus 1 when s crosses a power of two (the steps register grows), plus D in the history variant.
//
// Depth of the unpruned circuit (pruning::none), derived from emit_walk's construction with
// qrm::measure's conventions (a multiplexed gate is one layer per entry, a multi-controlled gate
// one layer; ASAP layering):
//   - Init: X gates on the start position's set bits (one layer, parallel) and on the start
//     direction's bits (one layer), or H on every direction qubit (one layer, d = 2^D), or the Ry
//     cascade of a uniform superposition over d values (uniform_preparation_depth(d) layers).
//     The first coin waits for the position bits it selects on and for the direction register:
//     init = max([start voxel != 0], direction preparation depth).
//   - Each step i: Coin (p^dims entries, on direction + voxel index); [History copy: D CNOTs on
//     distinct direction qubits, 1 layer, except after the last step]; Shift (one add per
//     (direction, axis) pair with a nonzero displacement, all controlled by the whole direction
//     register, so a = number of such pairs layers in sequence); Sample Le_i (p^dims entries on
//     the voxel index) and, except in the last step, rho_i (p^dims entries). Each of these shares
//     qubits with the one before (voxel index or direction register), so the layers add up.
//   - Path: the steps register's preparation runs in parallel with the walk (its qubits are
//     untouched before); term i waits for Le_i; the last term waits for the last Le sample,
//     which ends the walk, so the Path adds 1 layer whenever 3 p^dims > s + its preparation
//     depth (every grid of 4 or more cells per axis and s <= 48).
//   depth = init + (3 s - 1) p^dims + s a + [history] (s - 1) + 1.
// a <= dims * d, so this is the paper's O(s (p^3 + d)) in 3D (O(s (p^2 + d)) in 2D).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "decompose.hpp"
#include "directions.hpp"
#include "metrics.hpp"
#include "paper_scenes.hpp"
#include "program.hpp"
#include "render/voxelize.hpp"
#include "walk.hpp"
#include "walk_model.hpp"

namespace qrm {

// walk_width_formula(dims, P, F, D, s, variant): the A operator's qubits (header comment).
constexpr std::size_t walk_width_formula(unsigned dims, unsigned position_bits, unsigned fractional_bits,
                                         unsigned direction_bits, unsigned steps, walk_variant variant) {
  const std::size_t s = steps;
  const std::size_t history = variant == walk_variant::history ? (s - 1) * direction_bits : 0;
  return 1 + steps_register_bits(s) + s + (s - 1) + history + direction_bits +
         static_cast<std::size_t>(dims) * (position_bits + fractional_bits);
}

// uniform_preparation_depth(count): layers of the Ry cascade preparing a uniform superposition
// of count values on bits_for(count) qubits (detail::emit_uniform_preparation): one Ry on the top
// qubit (count >= 2), then for each lower qubit i a multiplexed Ry with one entry per prefix q
// whose block still has values with bit i set: q 2^(i+1) + 2^i < count.
constexpr std::size_t uniform_preparation_depth(std::uint64_t count) {
  if (count < 2) return 0;
  const std::size_t k = bits_for(count);
  std::size_t depth = 1;
  for (std::size_t i = 0; i + 1 < k; ++i) {
    const std::uint64_t half = std::uint64_t{1} << i, block = half << 1;
    if (count > half) depth += static_cast<std::size_t>((count - half + block - 1) / block);
  }
  return depth;
}

// shift_pairs(directions): (direction, axis) pairs with a nonzero displacement: one add each.
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline std::size_t shift_pairs(const direction_set& dirs) {
  std::size_t a = 0;
  for (const auto& d : dirs.displacement)
    for (unsigned axis = 0; axis < dirs.dims; ++axis) a += d[axis] != 0 ? 1 : 0;
  return a;
}

// unpruned_walk_depth(model, start, steps, variant): the closed form of the header comment for
// the logical depth of make_walk_program(model, start, {steps, variant, pruning::none}).
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline std::size_t unpruned_walk_depth(const walk_model& m, const walk_start& start, unsigned steps,
                                       walk_variant variant) {
  if (steps < 1) throw std::invalid_argument("unpruned_walk_depth: steps must be at least 1");
  const std::size_t d = m.direction_count();
  std::size_t direction_init = 0;
  if (start.direction > 0)
    direction_init = 1;
  else if (start.direction < 0)
    direction_init = d == (std::size_t{1} << m.direction_bits()) ? 1 : uniform_preparation_depth(d);
  const bool voxel_nonzero = start.voxel[0] != 0 || start.voxel[1] != 0 || (m.dims() == 3 && start.voxel[2] != 0);
  const std::size_t init = std::max<std::size_t>(voxel_nonzero ? 1 : 0, direction_init);
  const std::size_t voxels = m.scene_data().voxel_count(), s = steps;
  const std::size_t history = variant == walk_variant::history ? s - 1 : 0;
  if (3 * voxels <= s + uniform_preparation_depth(s))
    throw std::invalid_argument(
        "unpruned_walk_depth: the closed form needs 3 p^dims > s + the steps preparation depth");
  return init + (3 * s - 1) * voxels + s * shift_pairs(m.directions()) + history + 1;
}

// The parts of the A operator (see walk.hpp), and the depth of each on its own.
enum class walk_layer : unsigned char { init, coin, history, shift, sample, path };
inline constexpr std::array<walk_layer, 6> all_walk_layers = {
    walk_layer::init, walk_layer::coin, walk_layer::history, walk_layer::shift, walk_layer::sample, walk_layer::path};
constexpr const char* walk_layer_name(walk_layer l) {
  switch (l) {
    case walk_layer::init:
      return "init";
    case walk_layer::coin:
      return "coin";
    case walk_layer::history:
      return "history";
    case walk_layer::shift:
      return "shift";
    case walk_layer::sample:
      return "sample";
    case walk_layer::path:
      return "path";
  }
  return "?";
}

struct walk_layer_metrics {
  std::array<std::size_t, 6> depth{};  // logical depth of the layer's ops alone, indexed by walk_layer
  std::array<std::size_t, 6> gates{};  // logical gates (qrm::measure conventions)
  std::size_t operator[](walk_layer l) const { return depth[static_cast<std::size_t>(l)]; }
};

// walk_layer_of(p, op): which layer of a walk program an op belongs to, read from the roles of
// p's registers: a multiplexed unitary is the Coin, an add the Shift, a gate on a history qubit
// the History copy, a gate on Le or rho the Sample, on steps or out the Path, anything else
// (position and direction preparation) Init.
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline walk_layer walk_layer_of(const std::vector<role>& roles, const op::any& o) {
  if (std::holds_alternative<op::mux_unitary_op>(o)) return walk_layer::coin;
  if (std::holds_alternative<op::add_op>(o)) return walk_layer::shift;
  qubit_index target = 0;
  if (const auto* g = std::get_if<op::gate1_op>(&o))
    target = g->target;
  else if (const auto* x = std::get_if<op::mux1_op>(&o))
    target = x->target;
  else
    return walk_layer::init;
  switch (roles[target]) {
    case role::history:
      return walk_layer::history;
    case role::emission:
    case role::reflectance:
      return walk_layer::sample;
    case role::steps:
    case role::out:
      return walk_layer::path;
    default:
      return walk_layer::init;
  }
}

// walk_layer_roles(p): the role of each qubit of p, from its register table (ancilla if none).
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline std::vector<role> walk_layer_roles(const program& p) {
  std::vector<role> roles(p.width(), role::ancilla);
  for (const register_info& r : p.registers())
    for (std::size_t b = 0; b < r.width; ++b) roles[r.offset + b] = r.kind;
  return roles;
}

// walk_layer_programs(p): p's ops split by layer (indexed by walk_layer), each on p's qubits.
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline std::array<program, 6> walk_layer_programs(const program& p) {
  const std::vector<role> roles = walk_layer_roles(p);
  std::array<program, 6> parts;
  for (program& part : parts) part = program(p.width());
  for (const op::any& o : p.ops()) parts[static_cast<std::size_t>(walk_layer_of(roles, o))].push(o);
  return parts;
}

// walk_layers(p): depth and gate count of each layer of a walk program on its own.
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
inline walk_layer_metrics walk_layers(const program& p) {
  const std::array<program, 6> parts = walk_layer_programs(p);
  walk_layer_metrics r;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const circuit_metrics m = measure(parts[i]);
    r.depth[i] = m.logical_depth;
    r.gates[i] = m.gate_count;
  }
  return r;
}

// ---- the scaling study's scenes, starts and sweeps ---------------------------------------------

// scaling_model(dims, size, directions): 2D box_2d(size) with the paper's 8 king directions
// (directions must be 8), or 3D cornell_box(size) with sphere_directions(directions, 3)
// (size >= 8: the Cornell box needs a shell and a wall layer on each side).
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
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
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
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

template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
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
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
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
template <int = 0>  // instantiated only where called: keeps qrm.hpp quick to compile
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
  r.logical = measure(w.circuit);
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
