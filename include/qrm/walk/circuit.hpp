// qrm/walk/circuit.hpp: the quantum ray-marching circuit A for one start point (the paper's Fig. 2-3).
//
//   Init    basis-encode the start position; the start direction basis-encoded, or a uniform
//           superposition of all directions (start in air).
//   step i  Coin    one multiplexed unitary on the direction register, selected by the voxel
//                   index (one entry per non-air voxel: the paper's position-controlled coins);
//           [History: copy the direction into fresh qubits, making paths orthogonal]
//           Shift   per direction d and axis: add d's displacement, controlled by dir == d;
//           Sample  multiplexed Ry(2 asin sqrt(v)) into Le_i (v = Le / scale) and, except after
//                   the last step, into rho_i (v = rho), selected by the voxel index.
//   Path    steps register in uniform superposition over the S = s terms; term i flips `out`
//           when steps = i, Le_i = 1 and rho_k = 1 for all k < i: P(out=1) = E[f] / S with
//           f = sum_i Le_i prod_{k<i} rho_k (Eq. 14-15). Radiance = P(out=1) * S * scale.
//
// Pruning ("simulate only what the scene calls for"):
//   none       the paper's full logical circuit: a coin entry for every voxel (identity in air),
//              a sample entry for every voxel (Ry(0) for zero values), every term and qubit.
//   scene      no coin for air, no sample gate for zero values, no term that can never fire
//              (and no qubits for it), no step after the last useful one.
//   reachable  (default) additionally, at step i only the voxels the walk can occupy at step i
//              (its classical support) get coin and sample entries. Gates on voxels the walker
//              cannot be at act on zero amplitude, so the state and P(out=1) are unchanged.
//
// Register order (first = least significant): out, steps, Le, rho, history, dir, x, y, z, so
// the voxel-index select register sits on the highest qubits (each multiplexer entry then
// touches one contiguous block of the dense state).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/compose.hpp"
#include "../circuit/gates.hpp"
#include "../circuit/layout.hpp"
#include "../circuit/metrics.hpp"
#include "../circuit/ops.hpp"
#include "../circuit/program.hpp"
#include "../circuit/registers.hpp"
#include "model.hpp"

namespace qrm {

enum class walk_variant : unsigned char { faithful, history };
enum class pruning : unsigned char { none, scene, reachable };

constexpr const char* pruning_name(pruning p) {
  return p == pruning::none ? "none" : p == pruning::scene ? "scene" : "reachable";
}

struct walk_options {
  unsigned steps = 3;
  walk_variant variant = walk_variant::faithful;
  pruning prune = pruning::reachable;
  int channel = 0;  // 0 R, 1 G, 2 B
};

// The qubits of a walk circuit, as run-time indices.
struct walk_qubits {
  std::array<std::vector<qubit_index>, 3> axis;  // per axis, least significant (fractional) bit first
  std::vector<qubit_index> select;               // voxel index: integer bits of x, then y, then z
  std::vector<qubit_index> dir, le, rho, steps, history;
  qubit_index out = 0;
  std::size_t width = 0;
  std::vector<register_info> registers;
};

// Bits of the steps register for S path terms.
constexpr std::size_t steps_register_bits(std::size_t terms) { return bits_for(terms); }

// make_walk_qubits(...): the register order documented above, for run-time sizes.
template <int = 0>
inline walk_qubits make_walk_qubits(unsigned dims, unsigned position_bits, unsigned fractional_bits,
                                    unsigned direction_bits, unsigned steps, walk_variant variant) {
  if (steps < 1) throw std::invalid_argument("walk: steps must be at least 1");
  walk_qubits q;
  qubit_index next = 0;
  auto take = [&](std::vector<qubit_index>& v, std::size_t n, std::string_view name, role r) {
    if (n == 0) return;
    q.registers.push_back({name, r, next, n});
    for (std::size_t i = 0; i < n; ++i) v.push_back(next++);
  };
  std::vector<qubit_index> out;
  take(out, 1, "out", role::out);
  q.out = out[0];
  take(q.steps, steps_register_bits(steps), "steps", role::steps);
  take(q.le, steps, "Le", role::emission);
  take(q.rho, steps - 1, "rho", role::reflectance);
  if (variant == walk_variant::history) take(q.history, (steps - 1) * direction_bits, "hist", role::history);
  take(q.dir, direction_bits, "dir", role::direction);
  const char* names[3] = {"x", "y", "z"};
  for (unsigned a = 0; a < dims; ++a) take(q.axis[a], position_bits + fractional_bits, names[a], role::position);
  for (unsigned a = 0; a < dims; ++a)
    for (unsigned b = 0; b < position_bits; ++b) q.select.push_back(q.axis[a][fractional_bits + b]);
  q.width = next;
  return q;
}

// The scene-dependent tables of one A operator.
struct walk_tables {
  unsigned steps = 0;          // s
  unsigned emitted_steps = 0;  // steps actually emitted (pruning drops useless trailing steps)
  walk_variant variant = walk_variant::faithful;
  pruning prune = pruning::reachable;
  int channel = 0;
  double emission_scale = 1.0;
  std::array<std::uint64_t, 3> start_pos{};
  int start_dir = -1;
  std::size_t dir_count = 0;
  unsigned dims = 2;
  std::vector<std::array<std::int64_t, 3>> displacement;
  std::vector<dense_matrix> coin_matrices;
  std::vector<std::vector<mux_unitary_entry>> coin_entries;  // per step
  std::vector<std::vector<mux1_entry>> le_entries;           // per step
  std::vector<std::vector<mux1_entry>> rho_entries;          // per step (s - 1 of them)
  std::vector<bool> term_kept;                               // per path term
};

namespace detail {
// Ry(2 asin sqrt v), with the matrix entries sqrt(1 - v) and sqrt(v) computed directly rather
// than as cos and sin of the angle: v = 1 (a white reflectance, an emission equal to the scale)
// then gives exactly |1>, not |1> plus a 6e-17 |0> branch. Such branches are invisible in P(out=1)
// but the compact backend stores them, and they doubled its support at every step through air.
template <int = 0>
inline gate1 sample_rotation(double v) {
  const double clipped = std::min(1.0, std::max(0.0, v));
  gate1 g = gate::ry(2.0 * std::asin(std::sqrt(clipped)));
  const double s = std::sqrt(clipped), c = std::sqrt(1.0 - clipped);
  g.m[0][0] = c;
  g.m[0][1] = -s;
  g.m[1][0] = s;
  g.m[1][1] = c;
  return g;
}
}  // namespace detail

// build_walk_tables(model, start, options): coins, samples and path terms for one start point.
template <int = 0>
inline walk_tables build_walk_tables(const walk_model& m, const walk_start& start, const walk_options& o) {
  if (o.channel < 0 || o.channel > 2) throw std::invalid_argument("walk: channel must be 0, 1 or 2");
  if (o.steps < 1 || o.steps > 64) throw std::invalid_argument("walk: steps must be in [1, 64], got " + std::to_string(o.steps));
  const scene& sc = m.scene_data();
  walk_tables t;
  t.steps = o.steps;
  t.variant = o.variant;
  t.prune = o.prune;
  t.channel = o.channel;
  t.emission_scale = sc.emission_scale(o.channel);
  t.dims = m.dims();
  t.dir_count = m.direction_count();
  t.displacement = m.directions().displacement;
  t.coin_matrices = m.coins();
  const auto init = m.initial_states(start);
  t.start_pos = init[0].first.pos;
  t.start_dir = start.direction;

  const std::size_t voxels = sc.voxel_count();
  const unsigned s = o.steps;
  // Voxels whose gates step i needs: before the coin (coin) and after the shift (samples).
  std::vector<std::vector<std::size_t>> coin_voxels(s), sample_voxels(s);
  if (o.prune == pruning::reachable) {
    std::set<walk_state> support;
    for (const auto& [w, a] : init) support.insert(w);
    for (unsigned i = 0; i < s; ++i) {
      std::set<std::size_t> here, there;
      std::set<walk_state> next;
      for (const walk_state& w : support) {
        const std::size_t v = m.voxel_of(w.pos);
        here.insert(v);
        for (const auto& [d, amp] : m.scatter(v, w.dir)) {
          walk_state n{m.shifted(w.pos, d), d};
          next.insert(n);
          there.insert(m.voxel_of(n.pos));
        }
      }
      coin_voxels[i].assign(here.begin(), here.end());
      sample_voxels[i].assign(there.begin(), there.end());
      support = std::move(next);
    }
  } else {
    std::vector<std::size_t> all(voxels);
    for (std::size_t v = 0; v < voxels; ++v) all[v] = v;
    for (unsigned i = 0; i < s; ++i) coin_voxels[i] = sample_voxels[i] = all;
  }

  const bool keep_identities = o.prune == pruning::none;
  t.coin_entries.resize(s);
  t.le_entries.resize(s);
  t.rho_entries.resize(s > 0 ? s - 1 : 0);
  std::vector<std::uint32_t> identity_slot;  // lazily added identity coin, for pruning::none
  for (unsigned i = 0; i < s; ++i) {
    for (std::size_t v : coin_voxels[i]) {
      const int c = m.coin_of(v);
      if (c >= 0) {
        t.coin_entries[i].push_back({v, static_cast<std::uint32_t>(c)});
      } else if (keep_identities) {
        if (identity_slot.empty()) {
          identity_slot.push_back(static_cast<std::uint32_t>(t.coin_matrices.size()));
          t.coin_matrices.push_back(dense_matrix::identity(std::size_t{1} << m.direction_bits()));
        }
        t.coin_entries[i].push_back({v, identity_slot[0]});
      }
    }
    for (std::size_t v : sample_voxels[i]) {
      const double le = m.emission(v, o.channel) / t.emission_scale;
      if (le > 0 || keep_identities) t.le_entries[i].push_back({v, detail::sample_rotation(le)});
      if (i + 1 < s) {
        const double rho = m.reflectance(v, o.channel);
        if (rho > 0 || keep_identities) t.rho_entries[i].push_back({v, detail::sample_rotation(rho)});
      }
    }
  }
  // Path terms: term i needs some Le_i and every rho_k (k < i) to be possibly nonzero.
  t.term_kept.assign(s, true);
  if (!keep_identities) {
    bool rho_possible = true;
    for (unsigned i = 0; i < s; ++i) {
      t.term_kept[i] = rho_possible && !t.le_entries[i].empty();
      if (!t.term_kept[i]) t.le_entries[i].clear();
      if (i + 1 < s) rho_possible = rho_possible && !t.rho_entries[i].empty();
    }
    // rho_k is needed only by kept terms i > k; steps after the last kept term change nothing.
    unsigned last = 0;
    for (unsigned i = 0; i < s; ++i)
      if (t.term_kept[i]) last = i + 1;
    for (unsigned k = 0; k + 1 < s; ++k)
      if (k + 1 >= last) t.rho_entries[k].clear();
    t.emitted_steps = last;
    for (unsigned i = last; i < s; ++i) t.coin_entries[i].clear();
  } else {
    t.emitted_steps = s;
  }
  return t;
}

// emit_walk(sink, tables, qubits): the A operator's primitive ops.
template <gate_sink S>
void emit_walk(S& sink, const walk_tables& t, const walk_qubits& q) {
  const std::span<const control> none;
  // Init: position, then direction.
  for (unsigned a = 0; a < t.dims; ++a)
    for (std::size_t b = 0; b < q.axis[a].size(); ++b)
      if ((t.start_pos[a] >> b) & 1u) sink.apply_gate1(gate::x(), q.axis[a][b], none);
  if (t.start_dir >= 0) {
    for (std::size_t b = 0; b < q.dir.size(); ++b)
      if ((static_cast<unsigned>(t.start_dir) >> b) & 1u) sink.apply_gate1(gate::x(), q.dir[b], none);
  } else if (t.dir_count == (std::size_t{1} << q.dir.size())) {
    for (qubit_index b : q.dir) sink.apply_gate1(gate::h(), b, none);
  } else {
    detail::emit_uniform_preparation(sink, std::span<const qubit_index>(q.dir), t.dir_count, false, none);
  }
  std::vector<control> dir_is(q.dir.size());
  const std::size_t dbits = q.dir.size();
  for (unsigned i = 0; i < t.emitted_steps; ++i) {
    if (!t.coin_entries[i].empty())
      sink.apply_mux_unitary(t.coin_matrices, t.coin_entries[i], q.dir, q.select, none);
    if (t.variant == walk_variant::history && i + 1 < t.emitted_steps)
      for (std::size_t b = 0; b < dbits; ++b) {
        const control c{q.dir[b], true};
        sink.apply_gate1(gate::x(), q.history[i * dbits + b], std::span<const control>(&c, 1));
      }
    for (std::size_t d = 0; d < t.dir_count; ++d) {
      for (std::size_t b = 0; b < dbits; ++b) dir_is[b] = {q.dir[b], ((d >> b) & 1u) != 0};
      for (unsigned a = 0; a < t.dims; ++a)
        if (t.displacement[d][a] != 0) sink.apply_add(t.displacement[d][a], q.axis[a], dir_is);
    }
    if (!t.le_entries[i].empty()) sink.apply_mux1(t.le_entries[i], q.le[i], q.select, none);
    if (i + 1 < t.steps && !t.rho_entries[i].empty()) sink.apply_mux1(t.rho_entries[i], q.rho[i], q.select, none);
  }
  // Path.
  detail::emit_uniform_preparation(sink, std::span<const qubit_index>(q.steps), t.steps, false, none);
  std::vector<control> cs;
  for (unsigned i = 0; i < t.steps; ++i) {
    if (!t.term_kept[i]) continue;
    cs.clear();
    for (std::size_t b = 0; b < q.steps.size(); ++b) cs.push_back({q.steps[b], ((i >> b) & 1u) != 0});
    cs.push_back({q.le[i], true});
    for (unsigned k = 0; k < i; ++k) cs.push_back({q.rho[k], true});
    sink.apply_gate1(gate::x(), q.out, cs);
  }
}

// ---- the typed circuit ------------------------------------------------------------------------

// ray_marching_circuit<Dims, PosBits, DirBits, Steps, Variant, FracBits>: the A operator with
// compile-time register sizes (P position bits per axis, the direction register, s steps) and
// the scene as run-time data. Its width and a depth bound are constexpr; the bound is the
// unpruned circuit's O(s (p^dims + d)) (Section 6): per step a coin layer of p^dims entries, a
// shift of at most d * dims adds, two sample layers of p^dims entries; then the Path gate.
template <std::size_t Dims, std::size_t PosBits, std::size_t DirBits, std::size_t Steps,
          walk_variant Variant = walk_variant::faithful, std::size_t FracBits = 0>
class ray_marching_circuit {
  static constexpr bool dims_must_be_2_or_3 = Dims == 2 || Dims == 3;
  static_assert(dims_must_be_2_or_3, "dims_must_be_2_or_3: ray_marching_circuit<Dims, ...> needs Dims = 2 or 3");
  static constexpr bool steps_must_be_positive = Steps >= 1;
  static_assert(steps_must_be_positive, "steps_must_be_positive: a walk takes at least one step");
  static constexpr bool position_bits_must_be_positive = PosBits >= 1;
  static_assert(position_bits_must_be_positive, "position_bits_must_be_positive: a grid has at least 2 cells per axis");
  static constexpr bool two_d_walks_move_whole_cells = Dims == 3 || FracBits == 0;
  static_assert(two_d_walks_move_whole_cells, "two_d_walks_move_whole_cells: 2D walks have no fractional position bits");

 public:
  static constexpr std::size_t dims = Dims, position_bits = PosBits, direction_bits = DirBits, steps = Steps;
  static constexpr std::size_t fractional_bits = FracBits;
  static constexpr walk_variant variant = Variant;
  static constexpr std::size_t history_bits = Variant == walk_variant::history ? (Steps - 1) * DirBits : 0;
  static constexpr std::size_t width = 1 + steps_register_bits(Steps) + Steps + (Steps - 1) + history_bits + DirBits +
                                       Dims * (PosBits + FracBits);
  static constexpr std::size_t voxel_count = std::size_t{1} << (Dims * PosBits);
  static constexpr std::size_t depth_bound =
      Steps * (voxel_count + (history_bits ? 1 : 0) + (std::size_t{1} << DirBits) * Dims + 2 * voxel_count) +
      steps_register_bits(Steps) + Steps + DirBits + 1;
  // The 2D coins (+-1/2 Lambertian, permutations) are real; 3D Lambertian coins may need
  // complex phases.
  static constexpr bool is_real = Dims == 2;

  // A layout type for program::from and typed queries (registers as in make_walk_qubits).
  struct layout_type {
    static inline const std::vector<register_info> register_table =
        make_walk_qubits(Dims, PosBits, FracBits, DirBits, Steps, Variant).registers;
    static constexpr std::size_t width = ray_marching_circuit::width;
  };

  ray_marching_circuit(const walk_model& m, const walk_start& start, int channel = 0,
                       pruning prune = pruning::reachable)
      : qubits_(make_walk_qubits(Dims, PosBits, FracBits, DirBits, Steps, Variant)) {
    if (m.dims() != Dims || m.position_bits() != PosBits || m.fractional_bits() != FracBits ||
        m.direction_bits() > DirBits)
      throw std::invalid_argument("ray_marching_circuit<" + std::to_string(Dims) + ", " + std::to_string(PosBits) + ", " +
                                  std::to_string(DirBits) + ", ...>: the scene has dims " + std::to_string(m.dims()) +
                                  ", " + std::to_string(m.position_bits()) + " position bits, " +
                                  std::to_string(m.fractional_bits()) + " fractional bits and needs " +
                                  std::to_string(m.direction_bits()) + " direction bits");
    walk_options o;
    o.steps = Steps;
    o.variant = Variant;
    o.prune = prune;
    o.channel = channel;
    tables_ = build_walk_tables(m, start, o);
  }

  const walk_tables& tables() const { return tables_; }
  const walk_qubits& qubits() const { return qubits_; }
  qubit_index out_qubit() const { return qubits_.out; }

  template <gate_sink S>
  void emit(S& sink) const {
    emit_walk(sink, tables_, qubits_);
  }

 private:
  walk_qubits qubits_;
  walk_tables tables_;
};

// ---- programs: run-time sizes, idle-qubit removal, metrics ----------------------------------

// remove_idle_qubits(p): p without the qubits no op touches, renumbered in order; `kept[i]` is
// the original index of new qubit i.
template <int = 0>
inline program remove_idle_qubits(const program& p, std::vector<qubit_index>* kept = nullptr) {
  std::vector<bool> used(p.width(), false);
  for (const op::any& o : p.ops())
    for (qubit_index q : op_qubits(o)) used[q] = true;
  std::vector<qubit_index> map(p.width(), 0), orig;
  for (qubit_index q = 0; q < p.width(); ++q)
    if (used[q]) {
      map[q] = static_cast<qubit_index>(orig.size());
      orig.push_back(q);
    }
  program r(orig.size());
  std::vector<register_info> regs;
  for (const register_info& ri : p.registers()) {
    std::size_t survivors = 0;
    qubit_index first = 0;
    for (std::size_t b = 0; b < ri.width; ++b)
      if (used[ri.offset + b]) {
        if (survivors == 0) first = map[ri.offset + b];
        ++survivors;
      }
    if (survivors) regs.push_back({ri.name, ri.kind, first, survivors});
  }
  r.set_registers(std::move(regs));
  auto remap = [&](auto& v) {
    for (auto& q : v) q = map[q];
  };
  for (op::any o : p.ops()) {
    visit_op(o, [&](auto& x) {
          using T = std::decay_t<decltype(x)>;
          for (control& c : x.controls) c.qubit = map[c.qubit];
          if constexpr (std::is_same_v<T, op::gate1_op>) {
            x.target = map[x.target];
          } else if constexpr (std::is_same_v<T, op::unitary_op>) {
            remap(x.targets);
          } else if constexpr (std::is_same_v<T, op::add_op>) {
            remap(x.bits);
          } else if constexpr (std::is_same_v<T, op::mux1_op>) {
            x.target = map[x.target];
            remap(x.select);
          } else {
            remap(x.targets);
            remap(x.select);
          }
        });
    r.push(std::move(o));
  }
  if (kept) *kept = orig;
  return r;
}

// A walk circuit as a program, after pruning, with where `out` ended up.
struct walk_program {
  program circuit;      // idle qubits removed
  walk_tables tables;
  walk_qubits qubits;   // before idle-qubit removal
  qubit_index out = 0;  // in `circuit`
  std::size_t full_width = 0;
};

// make_walk_program(model, start, options): the A operator for run-time sizes (any scene).
template <int = 0>
inline walk_program make_walk_program(const walk_model& m, const walk_start& start, const walk_options& o) {
  walk_program w;
  w.tables = build_walk_tables(m, start, o);
  w.qubits = make_walk_qubits(m.dims(), m.position_bits(), m.fractional_bits(), m.direction_bits(), o.steps, o.variant);
  w.full_width = w.qubits.width;
  program p(w.qubits.width);
  p.set_registers(w.qubits.registers);
  emit_walk(p, w.tables, w.qubits);
  std::vector<qubit_index> kept;
  w.circuit = o.prune == pruning::none ? p : remove_idle_qubits(p, &kept);
  if (o.prune == pruning::none) {
    w.out = w.qubits.out;
  } else {
    const auto it = std::find(kept.begin(), kept.end(), w.qubits.out);
    // `out` is idle only when no path term can fire; keep a qubit for it so P(out=1) = 0 reads.
    if (it == kept.end()) {
      program q(w.circuit.width() + 1);
      q.set_registers(w.circuit.registers());
      q.append(w.circuit);
      w.out = static_cast<qubit_index>(w.circuit.width());
      w.circuit = std::move(q);
    } else {
      w.out = static_cast<qubit_index>(it - kept.begin());
    }
  }
  return w;
}

// probability_out(backend, w): run w's circuit on a fresh backend and read P(out = 1).
template <class Backend>
double probability_out(Backend& b, const walk_program& w) {
  run(b, w.circuit);
  const control c{w.out, true};
  return b.probability(std::span<const control>(&c, 1));
}

}  // namespace qrm
