// qrm/walk/cost.hpp: how the A operator's width and depth grow with the number of steps s, the
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
// Depth of the unpruned circuit (pruning::none), derived from the walk's gate templates (walk/gates.hpp) with
// qrm::circuit_metrics_of's conventions (a multiplexed gate is one layer per entry, a multi-controlled gate
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
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "../circuit/decompose.hpp"
#include "gates.hpp"
#include "directions.hpp"
#include "../circuit/metrics.hpp"
#include "paper_scenes.hpp"
#include "../circuit/program.hpp"
#include "circuit.hpp"
#include "model.hpp"

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
template <int = 0>
inline std::size_t shift_pairs(const direction_set& dirs) {
  std::size_t a = 0;
  for (const auto& d : dirs.displacement)
    for (unsigned axis = 0; axis < dirs.dims; ++axis) a += d[axis] != 0 ? 1 : 0;
  return a;
}

// unpruned_walk_depth(model, start, steps, variant): the closed form of the header comment for
// the logical depth of make_walk_program(model, start, {steps, variant, pruning::none}).
template <int = 0>
std::size_t unpruned_walk_depth(const walk_model& m, const walk_start& start, unsigned steps,
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

// The depth and gate count of each walk layer (walk_layer, walk/gates.hpp) on its own.
struct walk_layer_metrics {
  std::array<std::size_t, 6> depth{};  // logical depth of the layer's ops alone, indexed by walk_layer
  std::array<std::size_t, 6> gates{};  // logical gates (qrm::circuit_metrics_of conventions)
  std::size_t operator[](walk_layer l) const { return depth[static_cast<std::size_t>(l)]; }
};

// recorded_walk_layer(p, i): the walk layer op i of p was recorded in (walk_circuit labels every
// op it emits; the label survives idle-qubit removal, adjoint and append).
template <int = 0>
inline walk_layer recorded_walk_layer(const program& p, std::size_t i) {
  const char* label = p.layer_of(i);
  for (walk_layer l : all_walk_layers)
    if (label != nullptr && std::string_view(label) == walk_layer_name(l)) return l;
  throw std::invalid_argument("recorded_walk_layer: op " + std::to_string(i) +
                              " carries no walk layer (the program was not recorded from a walk circuit)");
}

// walk_layer_programs(p): p's ops split by the layer each was recorded in (indexed by walk_layer).
template <int = 0>
std::array<program, 6> walk_layer_programs(const program& p) {
  std::array<program, 6> parts;
  for (program& part : parts) part = program(p.width());
  for (std::size_t i = 0; i < p.ops().size(); ++i)
    parts[static_cast<std::size_t>(recorded_walk_layer(p, i))].push(p.ops()[i]);
  return parts;
}

// walk_layers(p): depth and gate count of each layer of a walk program on its own.
template <int = 0>
walk_layer_metrics walk_layers(const program& p) {
  const std::array<program, 6> parts = walk_layer_programs(p);
  walk_layer_metrics r;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const circuit_metrics m = circuit_metrics_of(parts[i]);
    r.depth[i] = m.logical_depth;
    r.gates[i] = m.gate_count;
  }
  return r;
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_COST_INSTANCES(PREFIX)                                                                  \
  PREFIX std::size_t unpruned_walk_depth<0>(const walk_model&, const walk_start&, unsigned, walk_variant); \
  PREFIX std::array<program, 6> walk_layer_programs<0>(const program&);                                    \
  PREFIX walk_layer_metrics walk_layers<0>(const program&);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_COST_INSTANCES(extern template)
}  // namespace qrm
#endif
