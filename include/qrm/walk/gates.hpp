// qrm/walk/gates.hpp: the walk's registers and its gate templates, one per layer of the paper's
// Fig. 2-3. Each template names its registers by type, carries its run-time tables (coins,
// angles, the entries pruning kept) and lowers itself through a layout object, static or
// dynamic (circuit/layout.hpp), so the same templates run with compile-time widths
// (ray_marching_circuit<2, 3, 3, 3>) and with the widths a scene file gives at run time.
//
// Every template follows one protocol:
//   registers            the registers it touches (a type_list)
//   layer                its walk_layer (program records it with each op: enter_layer)
//   emit(layout, sink)   lowers itself to the primitive ops of circuit/ops.hpp
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "../circuit/gates.hpp"
#include "../circuit/layout.hpp"
#include "../circuit/ops.hpp"
#include "../circuit/registers.hpp"

namespace qrm {

// The parts of the A operator, in the order they act within a step.
enum class walk_layer : unsigned char { init, coin, history, shift, sample, path };
inline constexpr std::array<walk_layer, 6> all_walk_layers = {
    walk_layer::init, walk_layer::coin, walk_layer::history, walk_layer::shift, walk_layer::sample, walk_layer::path};
constexpr const char* walk_layer_name(walk_layer l) {
  constexpr const char* names[] = {"init", "coin", "history", "shift", "sample", "path"};
  return names[static_cast<std::size_t>(l)];
}

// The walk's registers: names and roles fixed, widths a constant or dynamic_width.
namespace walk_registers {
using out = output<"out">;
template <std::size_t W>
using steps = qrm::steps<W, "steps">;
template <std::size_t W>
using emission = qrm::emission<W, "Le">;
template <std::size_t W>
using reflectance = qrm::reflectance<W, "rho">;
template <std::size_t W>
using history = qrm::history<"hist", W>;
template <std::size_t W>
using distance = qrm::distance<"dist", W>;
template <std::size_t W>
using direction = qrm::direction<W, "dir">;
template <std::size_t W>
using x = position<"x", W>;
template <std::size_t W>
using y = position<"y", W>;
template <std::size_t W>
using z = position<"z", W>;
}  // namespace walk_registers

namespace detail {
// The voxel index: the integer bits (above `fractional_bits`) of each axis, x first.
template <class L, class... Axes>
std::vector<qubit_index> voxel_select(const L& l, type_list<Axes...>, std::size_t fractional_bits) {
  std::vector<qubit_index> q;
  (
      [&] {
        for (std::size_t b = fractional_bits; b < l.template width_of<Axes>(); ++b)
          q.push_back(l.template offset_of<Axes>() + static_cast<qubit_index>(b));
      }(),
      ...);
  return q;
}
}  // namespace detail

// walk_init<Axes, Dir>{start, direction}: basis-encode the start position; the start direction
// basis-encoded, or (direction < 0: a start in air) a uniform superposition of dir_count directions.
template <class Axes, class Dir>
struct walk_init;
template <class... Axes, class Dir>
struct walk_init<detail::type_list<Axes...>, Dir> {
  using registers = detail::type_list<Axes..., Dir>;
  static constexpr walk_layer layer = walk_layer::init;

  std::array<std::uint64_t, 3> start_pos{};  // per axis, fixed point (fractional bits included)
  int start_dir = -1;
  std::size_t dir_count = 0;

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    const std::span<const control> none;
    std::size_t axis = 0;
    (
        [&] {
          const std::uint64_t v = start_pos[axis++];
          for (std::size_t b = 0; b < l.template width_of<Axes>(); ++b)
            if ((v >> b) & 1u) sink.apply_gate1(gate::x(), l.template qubit_of<Axes>(b), none);
        }(),
        ...);
    const std::vector<qubit_index> dir = l.template qubits_of<Dir>();
    if (start_dir >= 0) {
      for (std::size_t b = 0; b < dir.size(); ++b)
        if ((static_cast<unsigned>(start_dir) >> b) & 1u) sink.apply_gate1(gate::x(), dir[b], none);
    } else if (dir_count == (std::size_t{1} << dir.size())) {
      for (qubit_index b : dir) sink.apply_gate1(gate::h(), b, none);
    } else {
      detail::emit_uniform_preparation(sink, std::span<const qubit_index>(dir), dir_count, false, none);
    }
  }
};

// walk_coin<Dir, Axes>{matrices, entries}: the Coin layer, one multiplexed unitary on Dir selected
// by the voxel index: where the voxel is entry.select, matrices[entry.matrix] acts (the paper's
// position-controlled coins; the matrices are shared by every step).
template <class Dir, class Axes>
struct walk_coin {
  using registers = detail::list_join_t<detail::type_list<Dir>, Axes>;
  static constexpr walk_layer layer = walk_layer::coin;

  std::shared_ptr<const std::vector<dense_matrix>> matrices;
  std::vector<mux_unitary_entry> entries;
  std::size_t fractional_bits = 0;

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    if (entries.empty()) return;
    sink.apply_mux_unitary(*matrices, entries, l.template qubits_of<Dir>(),
                           detail::voxel_select(l, Axes{}, fractional_bits), std::span<const control>());
  }
};

// walk_history<Dir, Hist>{step}: copy the direction into the step's slot of Hist (CNOTs), which
// makes different paths orthogonal: P(out = 1) becomes the classical path sum.
template <class Dir, class Hist>
struct walk_history {
  using registers = detail::type_list<Dir, Hist>;
  static constexpr walk_layer layer = walk_layer::history;

  std::size_t step = 0;

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    if constexpr (L::template contains<Hist>) {  // a static one-step walk has none
      const std::size_t bits = l.template width_of<Dir>();
      for (std::size_t b = 0; b < bits; ++b) {
        const control c{l.template qubit_of<Dir>(b), true};
        sink.apply_gate1(gate::x(), l.template qubit_of<Hist>(step * bits + b), std::span<const control>(&c, 1));
      }
    }
  }
};

// walk_shift<Dir, Axes>{displacement}: for each direction d and axis, add d's displacement to
// the axis (fixed point) where Dir reads d.
template <class Dir, class Axes>
struct walk_shift;
template <class Dir, class... Axes>
struct walk_shift<Dir, detail::type_list<Axes...>> {
  using registers = detail::type_list<Dir, Axes...>;
  static constexpr walk_layer layer = walk_layer::shift;

  std::shared_ptr<const std::vector<std::array<std::int64_t, 3>>> displacement;  // per direction

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    const std::vector<qubit_index> dir = l.template qubits_of<Dir>();
    const std::array<std::vector<qubit_index>, sizeof...(Axes)> axes{l.template qubits_of<Axes>()...};
    std::vector<control> dir_is(dir.size());
    for (std::size_t d = 0; d < displacement->size(); ++d) {
      for (std::size_t b = 0; b < dir.size(); ++b) dir_is[b] = {dir[b], ((d >> b) & 1u) != 0};
      for (std::size_t a = 0; a < axes.size(); ++a)
        if ((*displacement)[d][a] != 0) sink.apply_add((*displacement)[d][a], axes[a], dir_is);
    }
  }
};

// One entry of the surface march's lookup: where the walker's voxel index and direction read
// `select` (voxel index | direction << voxel bits), the march takes `distance` displacements.
struct march_entry {
  std::uint64_t select;
  std::uint64_t distance;
};

// walk_march<Dir, Axes, Dist>{step, distance_bits, fractional_bits, lookup, displacement}: the
// bounce-driven move (walk_model's surface march), from a voxel centre to the centre of the
// next surface voxel, as three permutations:
//   1. k, the number of displacements, is looked up from (voxel, direction) into slot `step` of
//      Dist, which is fresh (zero): one multiplexed X per bit of k over the lookup's entries;
//   2. position += k * displacement: per direction d, bit j of k and axis, add 2^j * d's
//      displacement where Dir reads d and bit j is set;
//   3. the sub-voxel bits, now centre + k * displacement mod 2^F, a function of (k, d), are
//      reset to the centre by a multiplexed X selected by (k, d) (nothing when F = 0).
// Together they map (centre c, d, 0) to (centre of the surface voxel, d, k).
template <class Dir, class Axes, class Dist>
struct walk_march;
template <class Dir, class... Axes, class Dist>
struct walk_march<Dir, detail::type_list<Axes...>, Dist> {
  using registers = detail::type_list<Dir, Axes..., Dist>;
  static constexpr walk_layer layer = walk_layer::shift;

  std::size_t step = 0;
  std::size_t distance_bits = 0;
  std::size_t fractional_bits = 0;
  std::vector<march_entry> lookup;
  std::shared_ptr<const std::vector<std::array<std::int64_t, 3>>> displacement;  // per direction

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    if constexpr (L::template contains<Dist>) {
      const std::span<const control> none;
      const std::vector<qubit_index> dir = l.template qubits_of<Dir>();
      const std::array<std::vector<qubit_index>, sizeof...(Axes)> axes{l.template qubits_of<Axes>()...};
      std::vector<qubit_index> select = detail::voxel_select(l, detail::type_list<Axes...>{}, fractional_bits);
      const std::size_t dir_shift = select.size();
      select.insert(select.end(), dir.begin(), dir.end());
      std::vector<qubit_index> dist(distance_bits);
      for (std::size_t j = 0; j < distance_bits; ++j) dist[j] = l.template qubit_of<Dist>(step * distance_bits + j);
      // 1. the lookup; and which (direction, k) pairs occur, so only their adds and resets are emitted.
      std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs;  // (d, k)
      std::vector<mux1_entry> entries;
      for (std::size_t j = 0; j < distance_bits; ++j) {
        entries.clear();
        for (const march_entry& e : lookup)
          if ((e.distance >> j) & 1u) entries.push_back({e.select, gate::x()});
        if (!entries.empty()) sink.apply_mux1(entries, dist[j], select, none);
      }
      for (const march_entry& e : lookup) pairs.push_back({e.select >> dir_shift, e.distance});
      std::sort(pairs.begin(), pairs.end());
      pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
      // 2. position += k * displacement, bit by bit of k.
      std::vector<std::uint64_t> bits_used(displacement->size(), 0);
      for (const auto& [d, k] : pairs) bits_used[d] |= k;
      std::vector<control> cs(dir.size() + 1);
      for (std::size_t d = 0; d < displacement->size(); ++d)
        for (std::size_t j = 0; j < distance_bits; ++j) {
          if (!((bits_used[d] >> j) & 1u)) continue;
          for (std::size_t b = 0; b < dir.size(); ++b) cs[b] = {dir[b], ((d >> b) & 1u) != 0};
          cs[dir.size()] = {dist[j], true};
          for (std::size_t a = 0; a < axes.size(); ++a)
            if ((*displacement)[d][a] != 0) sink.apply_add((*displacement)[d][a] * (std::int64_t{1} << j), axes[a], cs);
        }
      // 3. back to the voxel centre: X where (centre + k * displacement) mod 2^F differs from it.
      if (fractional_bits == 0) return;
      std::vector<qubit_index> dist_dir = dist;
      dist_dir.insert(dist_dir.end(), dir.begin(), dir.end());
      const std::uint64_t unit = std::uint64_t{1} << fractional_bits, half = unit / 2;
      for (std::size_t a = 0; a < axes.size(); ++a)
        for (std::size_t b = 0; b < fractional_bits; ++b) {
          entries.clear();
          for (const auto& [d, k] : pairs) {
            const auto moved = static_cast<std::uint64_t>(static_cast<std::int64_t>(half) +
                                                          static_cast<std::int64_t>(k) * (*displacement)[d][a]);
            if ((((moved & (unit - 1)) ^ half) >> b) & 1u) entries.push_back({k | (d << distance_bits), gate::x()});
          }
          if (!entries.empty()) sink.apply_mux1(entries, axes[a][b], dist_dir, none);
        }
    }
  }
};

// walk_sample<Le, Rho, Axes>{step, le, rho}: the Sample layer: multiplexed Ry(2 asin sqrt v) into
// qubit `step` of Le (v = Le / scale) and of Rho (v = rho; none after the last step), selected
// by the voxel index; voxels without an entry are left alone (pruned: a zero value).
template <class Le, class Rho, class Axes>
struct walk_sample {
  using registers = detail::list_join_t<detail::type_list<Le, Rho>, Axes>;
  static constexpr walk_layer layer = walk_layer::sample;

  std::size_t step = 0;
  std::vector<mux1_entry> le, rho;
  std::size_t fractional_bits = 0;

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    if (le.empty() && rho.empty()) return;
    const std::vector<qubit_index> select = detail::voxel_select(l, Axes{}, fractional_bits);
    const std::span<const control> none;
    if (!le.empty()) sink.apply_mux1(le, l.template qubit_of<Le>(step), select, none);
    if constexpr (L::template contains<Rho>)  // a static one-step walk has no Rho register
      if (!rho.empty()) sink.apply_mux1(rho, l.template qubit_of<Rho>(step), select, none);
  }
};

// walk_path<Steps, Le, Rho, Out>{terms, kept}: the Path gate: Steps in uniform superposition over
// the `terms` path terms, then term i flips Out where Steps = i, Le_i = 1 and Rho_k = 1 for every
// k < i, so P(Out = 1) = E[f] / terms with f = sum_i Le_i prod_{k<i} rho_k (Eq. 14-15).
template <class Steps, class Le, class Rho, class Out>
struct walk_path {
  using registers = detail::type_list<Steps, Le, Rho, Out>;
  static constexpr walk_layer layer = walk_layer::path;

  std::size_t terms = 0;
  std::vector<bool> kept;  // per term: pruning drops terms that can never fire

  template <class L, gate_sink S>
  void emit(const L& l, S& sink) const {
    const std::vector<qubit_index> steps = l.template qubits_of<Steps>();
    detail::emit_uniform_preparation(sink, std::span<const qubit_index>(steps), terms, false, {});
    std::vector<control> cs;
    for (std::size_t i = 0; i < terms; ++i) {
      if (!kept[i]) continue;
      cs.clear();
      for (std::size_t b = 0; b < steps.size(); ++b) cs.push_back({steps[b], ((i >> b) & 1u) != 0});
      cs.push_back({l.template qubit_of<Le>(i), true});
      if constexpr (L::template contains<Rho>)
        for (std::size_t k = 0; k < i; ++k) cs.push_back({l.template qubit_of<Rho>(k), true});
      sink.apply_gate1(gate::x(), l.template qubit_of<Out>(0), cs);
    }
  }
};

// emit_layer(layout, sink, gate): gate.emit, with its ops labelled by its layer.
template <class L, gate_sink S, class G>
void emit_layer(const L& l, S& sink, const G& g) {
  enter_layer(sink, walk_layer_name(G::layer));
  g.emit(l, sink);
}

}  // namespace qrm
