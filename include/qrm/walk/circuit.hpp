// qrm/walk/circuit.hpp: the quantum ray-marching circuit A for one start point (the paper's Fig. 2-3).
//
//   Init    basis-encode the start position; the start direction basis-encoded, or a uniform
//           superposition of all directions (start in air).
//   step i  Coin    one multiplexed unitary on the direction register, selected by the voxel
//                   index (one entry per non-air voxel: the paper's position-controlled coins);
//           [History: copy the direction into fresh qubits, making paths orthogonal]
//           Shift   per direction d and axis: add d's displacement, controlled by dir == d
//                   (the voxel march); or March (the surface march, walk_model.hpp): look up
//                   the distance k to the next surface into fresh qubits, add k times d's
//                   displacement;
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
// Register order (first = least significant): out, steps, Le, rho, history, dist, dir, x, y, z, so
// the voxel-index select register sits on the highest qubits (each multiplexer entry then
// touches one contiguous block of the dense state).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
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
#include "../support/detail/meta.hpp"
#include "gates.hpp"
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

// Bits of the steps register for S path terms.
constexpr std::size_t steps_register_bits(std::size_t terms) { return bits_for(terms); }

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
  march_mode march = march_mode::voxel;
  unsigned distance_bits = 0;                                // surface march: qubits of k per step
  std::vector<std::vector<march_entry>> march_lookup;        // surface march: per step
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
template <int Deferred = 0>
walk_tables build_walk_tables(const walk_model& m, const walk_start& start, const walk_options& o) {
  using detail::deferred;
  if (o.channel < 0 || o.channel > 2) throw std::invalid_argument("walk: channel must be 0, 1 or 2");
  if (o.steps < 1 || o.steps > 64) throw std::invalid_argument("walk: steps must be in [1, 64], got " + std::to_string(o.steps));
  const scene& sc = m.scene_data();
  deferred<walk_tables, Deferred> t;
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

  t.march = m.march();
  t.distance_bits = m.distance_bits();
  const bool surface = m.march() == march_mode::surface;
  const unsigned voxel_bits = m.dims() * m.position_bits();
  auto march_select = [&](const std::array<std::uint64_t, 3>& pos, std::uint32_t d) {
    return static_cast<std::uint64_t>(m.voxel_of(pos)) | (std::uint64_t{d} << voxel_bits);
  };

  const std::size_t voxels = sc.voxel_count();
  const unsigned s = o.steps;
  if (surface) t.march_lookup.resize(s);
  // Voxels whose gates step i needs: before the coin (coin) and after the shift (samples).
  deferred<std::vector<std::vector<std::size_t>>, Deferred> coin_voxels(s), sample_voxels(s);
  if (o.prune == pruning::reachable) {
    deferred<std::set<walk_state>, Deferred> support;
    deferred<std::set<std::pair<std::uint64_t, std::uint64_t>>, Deferred> lookup;
    for (const auto& [w, a] : init) support.insert(w);
    for (unsigned i = 0; i < s; ++i) {
      deferred<std::set<std::size_t>, Deferred> here, there;
      deferred<std::set<walk_state>, Deferred> next;
      for (const walk_state& w : support) {
        const std::size_t v = m.voxel_of(w.pos);
        here.insert(v);
        for (const auto& [d, amp] : m.scatter(v, w.dir)) {
          const walk_model::move mv = m.moved_by(w.pos, d);
          if (surface) lookup.insert({march_select(w.pos, d), mv.distance});
          walk_state n{mv.pos, d};
          next.insert(n);
          there.insert(m.voxel_of(n.pos));
        }
      }
      coin_voxels[i].assign(here.begin(), here.end());
      sample_voxels[i].assign(there.begin(), there.end());
      if (surface) {
        for (const auto& [sel, k] : lookup) t.march_lookup[i].push_back({sel, k});
        lookup.clear();
      }
      support = std::move(next);
    }
  } else {
    deferred<std::vector<std::size_t>, Deferred> all(voxels);
    for (std::size_t v = 0; v < voxels; ++v) all[v] = v;
    for (unsigned i = 0; i < s; ++i) coin_voxels[i] = sample_voxels[i] = all;
    if (surface) {
      // Every voxel and direction (the walker sits at voxel centres between steps).
      deferred<std::vector<march_entry>, Deferred> table;
      for (std::size_t v = 0; v < voxels; ++v)
        for (std::uint32_t d = 0; d < m.direction_count(); ++d) {
          const auto centre = m.centre_of(sc.coords(v));
          table.push_back({march_select(centre, d), m.moved_by(centre, d).distance});
        }
      for (unsigned i = 0; i < s; ++i) t.march_lookup[i] = table;
    }
  }

  const bool keep_identities = o.prune == pruning::none;
  t.coin_entries.resize(s);
  t.le_entries.resize(s);
  t.rho_entries.resize(s > 0 ? s - 1 : 0);
  deferred<std::vector<std::uint32_t>, Deferred> identity_slot;  // lazily added identity coin, for pruning::none
  // A start in a medium with every direction (a light-map cell of fog): the uniform
  // superposition stands for light arriving from every direction, the uniform mixture, which
  // any coin maps to itself (a unitary's rows have unit norm, so every first direction stays
  // 1/D likely), so the classical references are the same with or without the first coin. Run
  // on the superposition, though, the dense medium coin would let the unrecorded start
  // directions interfere; so the first step applies no coin at the start voxel.
  const std::size_t start_voxel = m.voxel_of(t.start_pos);
  const bool skip_start_coin = start.direction < 0 && sc[start_voxel].kind == material::medium;
  for (unsigned i = 0; i < s; ++i) {
    for (std::size_t v : coin_voxels[i]) {
      const int c = i == 0 && skip_start_coin && v == start_voxel ? -1 : m.coin_of(v);
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
  // Path terms: term i needs some Le_i and every rho_k (k < i) to be possibly nonzero; with
  // reachable pruning, on one path: an emitter reached at step i through voxels of non-zero
  // reflectance (the live support), so a start whose value is exactly 0 keeps no term.
  deferred<std::vector<bool>, Deferred> live_term(s, true);
  if (o.prune == pruning::reachable) {
    deferred<std::set<walk_state>, Deferred> live;
    for (const auto& [w, a] : init) live.insert(w);
    for (unsigned i = 0; i < s; ++i) {
      deferred<std::set<walk_state>, Deferred> next;
      bool fires = false;
      for (const walk_state& w : live)
        for (const auto& [d, amp] : m.scatter(m.voxel_of(w.pos), w.dir)) {
          const walk_state n{m.moved(w.pos, d), d};
          const std::size_t v = m.voxel_of(n.pos);
          fires = fires || m.emission(v, o.channel) > 0;
          if (m.reflectance(v, o.channel) > 0) next.insert(n);
        }
      live_term[i] = fires;
      live = std::move(next);
    }
  }
  t.term_kept.assign(s, true);
  if (!keep_identities) {
    bool rho_possible = true;
    for (unsigned i = 0; i < s; ++i) {
      t.term_kept[i] = rho_possible && !t.le_entries[i].empty() && live_term[i];
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
    if (surface) t.march_lookup.resize(last);
  } else {
    t.emitted_steps = s;
  }
  return t;
}

// ---- the walk as a typed circuit -------------------------------------------------------------

namespace detail {
// Stands for a register a static walk does not have (rho at s = 1, hist in the faithful walk):
// dropped from the layout, and the gates that would use it check layout::contains.
struct absent_register {};
template <class Kept, class Rest>
struct drop_absent_registers {
  using type = Kept;
};
template <class... Kept, class R, class... Rest>
struct drop_absent_registers<type_list<Kept...>, type_list<R, Rest...>> {
  using type = typename drop_absent_registers<
      std::conditional_t<std::is_same_v<R, absent_register>, type_list<Kept...>, type_list<Kept..., R>>,
      type_list<Rest...>>::type;
};
template <class List>
struct layout_of_list;
template <class... R>
struct layout_of_list<type_list<R...>> {
  using type = layout<R...>;
};
constexpr std::size_t width_or_dynamic(bool dynamic, std::size_t w) { return dynamic ? dynamic_width : w; }
}  // namespace detail

// walk_shape<Dims, PositionBits, DirectionBits, Steps, Variant, FractionalBits>: the sizes of an A
// operator, each a constant or dynamic_width, and the registers and layout they give. Register
// order (first = least significant): out, steps, Le, rho, hist, dir, x, y, z, so the voxel-index
// select register sits on the highest qubits (each multiplexer entry then touches one contiguous
// block of the dense state). A static one-step walk has no rho register; only the history variant
// has hist ((s - 1) direction copies).
template <std::size_t Dims, std::size_t PositionBits, std::size_t DirectionBits, std::size_t Steps,
          walk_variant Variant = walk_variant::faithful, std::size_t FractionalBits = 0>
struct walk_shape {
  static constexpr bool dims_must_be_2_or_3 = Dims == 2 || Dims == 3;
  static_assert(dims_must_be_2_or_3, "dims_must_be_2_or_3: a walk runs on a 2D grid or 3D voxels");
  static constexpr bool steps_must_be_positive = Steps == dynamic_width || Steps >= 1;
  static_assert(steps_must_be_positive, "steps_must_be_positive: a walk takes at least one step");
  static constexpr bool position_bits_must_be_positive = PositionBits == dynamic_width || PositionBits >= 1;
  static_assert(position_bits_must_be_positive, "position_bits_must_be_positive: a grid has at least 2 cells per axis");
  static constexpr bool two_d_walks_move_whole_cells = Dims == 3 || FractionalBits == 0;
  static_assert(two_d_walks_move_whole_cells, "two_d_walks_move_whole_cells: 2D walks have no fractional position bits");

  static constexpr std::size_t dims = Dims;
  static constexpr walk_variant variant = Variant;
  static constexpr bool is_static = PositionBits != dynamic_width && DirectionBits != dynamic_width &&
                                    Steps != dynamic_width && FractionalBits != dynamic_width;

 private:
  static constexpr bool dyn_s = Steps == dynamic_width, dyn_d = DirectionBits == dynamic_width;
  static constexpr bool dyn_p = PositionBits == dynamic_width || FractionalBits == dynamic_width;

 public:
  // A history shape whose hist width is dynamic runs either variant: in the faithful walk its
  // hist register is empty. (So one type serves every run-time walk of a dimension.)
  static constexpr bool variant_at_run_time = Variant == walk_variant::history && (dyn_s || dyn_d);

 public:
  using out = walk_registers::out;
  using steps = walk_registers::steps<detail::width_or_dynamic(dyn_s, dyn_s ? 0 : steps_register_bits(Steps))>;
  using emission = walk_registers::emission<Steps>;
  using reflectance = std::conditional_t<!dyn_s && Steps == 1, detail::absent_register,
                                         walk_registers::reflectance<detail::width_or_dynamic(dyn_s, dyn_s ? 0 : Steps - 1)>>;
  using history = std::conditional_t<
      Variant == walk_variant::faithful || (!dyn_s && Steps == 1), detail::absent_register,
      walk_registers::history<detail::width_or_dynamic(dyn_s || dyn_d, dyn_s || dyn_d ? 0 : (Steps - 1) * DirectionBits)>>;
  // The surface march's distance register: run-time walks only (a static shape is the paper's
  // voxel march).
  using distance = std::conditional_t<is_static, detail::absent_register, walk_registers::distance<dynamic_width>>;
  using direction = walk_registers::direction<DirectionBits>;
  static constexpr std::size_t axis_width = detail::width_or_dynamic(dyn_p, dyn_p ? 0 : PositionBits + FractionalBits);
  using axes = std::conditional_t<Dims == 2, detail::type_list<walk_registers::x<axis_width>, walk_registers::y<axis_width>>,
                                  detail::type_list<walk_registers::x<axis_width>, walk_registers::y<axis_width>,
                                                    walk_registers::z<axis_width>>>;
  using layout = typename detail::layout_of_list<typename detail::drop_absent_registers<
      detail::type_list<>,
      detail::list_join_t<detail::type_list<out, steps, emission, reflectance, history, distance, direction>, axes>>::type>::type;
};

// A walk whose sizes and variant are known only at run time (what the CLI, light maps and
// renderers run): one type per dimension.
template <std::size_t Dims>
using dynamic_walk_shape = walk_shape<Dims, dynamic_width, dynamic_width, dynamic_width, walk_variant::history,
                                      Dims == 2 ? 0 : dynamic_width>;

namespace detail {
// The widths of L's registers for a model and step count (by role: the walk's registers are one
// per role).
template <class... R>
std::array<std::size_t, sizeof...(R)> walk_register_widths(type_list<R...>, const walk_model& m, unsigned s,
                                                           walk_variant v) {
  auto width = [&](role r) -> std::size_t {
    switch (r) {
      case role::out: return 1;
      case role::steps: return steps_register_bits(s);
      case role::emission: return s;
      case role::reflectance: return s - 1;
      case role::history: return v == walk_variant::history ? (s - 1) * m.direction_bits() : 0;
      case role::distance: return s * m.distance_bits();
      case role::direction: return m.direction_bits();
      case role::position: return m.position_bits() + m.fractional_bits();
      case role::ancilla: break;
    }
    return 0;
  };
  return {width(R::kind)...};
}
}  // namespace detail

// walk_circuit<Shape>: the A operator for one start point, composed of the walk's gate templates
// (walk/gates.hpp) over Shape's layout: Init, then per step Coin, [History], Shift, Sample, then
// Path. With a static shape the layout's offsets are constants; with a dynamic one they come
// from the model. Emitting labels each op with its walk_layer.
template <class Shape>
class walk_circuit {
 public:
  using shape = Shape;
  using layout_type = typename Shape::layout;
  // The 2D coins (+-1/2 Lambertian, permutations) are real; 3D Lambertian coins may need
  // complex phases.
  static constexpr bool is_real = Shape::dims == 2;
  using axes = typename Shape::axes;
  using init_gate = walk_init<axes, typename Shape::direction>;
  using coin_gate = walk_coin<typename Shape::direction, axes>;
  using history_gate = walk_history<typename Shape::direction, typename Shape::history>;
  using shift_gate = walk_shift<typename Shape::direction, axes>;
  using march_gate = walk_march<typename Shape::direction, axes, typename Shape::distance>;
  using sample_gate = walk_sample<typename Shape::emission, typename Shape::reflectance, axes>;
  using path_gate = walk_path<typename Shape::steps, typename Shape::emission, typename Shape::reflectance,
                              typename Shape::out>;

  // One step's gates.
  struct step {
    coin_gate coin;
    bool copy_history = false;
    history_gate history;
    shift_gate shift;  // the voxel march
    bool surface_march = false;
    march_gate march;  // the surface march
    sample_gate sample;
  };

  walk_circuit(const walk_model& m, const walk_start& start, const walk_options& o)
      : layout_(make_layout(m, o)), tables_(build_walk_tables(m, start, o)) {
    const walk_tables& t = tables_;
    const std::size_t frac = m.fractional_bits();
    init_.start_pos = t.start_pos;
    init_.start_dir = t.start_dir;
    init_.dir_count = t.dir_count;
    const auto matrices = std::make_shared<const std::vector<dense_matrix>>(t.coin_matrices);
    const auto displacement = std::make_shared<const std::vector<std::array<std::int64_t, 3>>>(
        t.displacement.begin(), t.displacement.begin() + static_cast<std::ptrdiff_t>(t.dir_count));
    steps_.resize(t.emitted_steps);
    for (unsigned i = 0; i < t.emitted_steps; ++i) {
      step& g = steps_[i];
      g.coin = {matrices, t.coin_entries[i], frac};
      g.copy_history = t.variant == walk_variant::history && i + 1 < t.emitted_steps;
      g.history.step = i;
      g.shift.displacement = displacement;
      if (t.march == march_mode::surface) {
        if constexpr (Shape::is_static)
          throw std::invalid_argument("walk: a static walk shape runs the voxel march; the surface march needs a run-time shape");
        g.surface_march = true;
        g.march.step = i;
        g.march.distance_bits = t.distance_bits;
        g.march.fractional_bits = frac;
        g.march.lookup = t.march_lookup[i];
        g.march.displacement = displacement;
      }
      g.sample.step = i;
      g.sample.le = t.le_entries[i];
      if (i + 1 < t.steps) g.sample.rho = t.rho_entries[i];
      g.sample.fractional_bits = frac;
    }
    path_.terms = t.steps;
    path_.kept = t.term_kept;
  }

  const layout_type& layout() const { return layout_; }
  const walk_tables& tables() const { return tables_; }
  const init_gate& init() const { return init_; }
  const std::vector<step>& steps() const { return steps_; }
  const path_gate& path() const { return path_; }
  std::size_t num_qubits() const { return layout_.num_qubits(); }
  qubit_index out_qubit() const { return layout_.template offset_of<typename Shape::out>(); }

  template <gate_sink S>
  void emit(S& sink) const {
    emit_layer(layout_, sink, init_);
    for (const step& g : steps_) {
      emit_layer(layout_, sink, g.coin);
      if (g.copy_history) emit_layer(layout_, sink, g.history);
      if (g.surface_march)
        emit_layer(layout_, sink, g.march);
      else
        emit_layer(layout_, sink, g.shift);
      emit_layer(layout_, sink, g.sample);
    }
    emit_layer(layout_, sink, path_);
    enter_layer(sink, nullptr);
  }

 private:
  static layout_type make_layout(const walk_model& m, const walk_options& o) {
    if (m.dims() != Shape::dims)
      throw std::invalid_argument("walk: the circuit type is for " + std::to_string(Shape::dims) +
                                  "D scenes, the scene is " + std::to_string(m.dims()) + "D");
    if (!Shape::variant_at_run_time && o.variant != Shape::variant)
      throw std::invalid_argument("walk: the circuit type's variant differs from the options'");
    if (o.steps < 1 || o.steps > 64) throw std::invalid_argument("walk: steps must be in [1, 64], got " + std::to_string(o.steps));
    return layout_type::with_widths(
        detail::walk_register_widths(typename layout_type::registers{}, m, o.steps, o.variant));
  }

  layout_type layout_;
  walk_tables tables_;
  init_gate init_;
  std::vector<step> steps_;
  path_gate path_;
};

// ray_marching_circuit<Dims, PosBits, DirBits, Steps, Variant, FracBits>: the A operator with
// compile-time register sizes (P position bits per axis, the direction register, s steps) and
// the scene as run-time data: walk_circuit on a static shape, with its width and a depth bound
// as constants. The bound is the unpruned circuit's O(s (p^dims + d)) (Section 6): per step a
// coin layer of p^dims entries, a shift of at most d * dims adds, two sample layers of p^dims
// entries; then the Path gate.
template <std::size_t Dims, std::size_t PosBits, std::size_t DirBits, std::size_t Steps,
          walk_variant Variant = walk_variant::faithful, std::size_t FracBits = 0>
class ray_marching_circuit : public walk_circuit<walk_shape<Dims, PosBits, DirBits, Steps, Variant, FracBits>> {
  using base = walk_circuit<walk_shape<Dims, PosBits, DirBits, Steps, Variant, FracBits>>;
  static constexpr bool widths_must_be_static = base::shape::is_static;
  static_assert(widths_must_be_static,
                "widths_must_be_static: ray_marching_circuit takes constants; use walk_circuit<dynamic_walk_shape<...>>");

 public:
  static constexpr std::size_t dims = Dims, position_bits = PosBits, direction_bits = DirBits, steps = Steps;
  static constexpr std::size_t fractional_bits = FracBits;
  static constexpr walk_variant variant = Variant;
  static constexpr std::size_t history_bits = Variant == walk_variant::history ? (Steps - 1) * DirBits : 0;
  static constexpr std::size_t width = base::layout_type::width;
  static constexpr std::size_t voxel_count = std::size_t{1} << (Dims * PosBits);
  static constexpr std::size_t depth_bound =
      Steps * (voxel_count + (history_bits ? 1 : 0) + (std::size_t{1} << DirBits) * Dims + 2 * voxel_count) +
      steps_register_bits(Steps) + Steps + DirBits + 1;
  ray_marching_circuit(const walk_model& m, const walk_start& start, int channel = 0,
                       pruning prune = pruning::reachable)
      : base(m, start, walk_options{Steps, Variant, prune, channel}) {}
};

// ---- programs: run-time sizes, idle-qubit removal, metrics ----------------------------------

// remove_idle_qubits(p): p without the qubits no op touches, renumbered in order; `kept[i]` is
// the original index of new qubit i.
template <int = 0>
program remove_idle_qubits(const program& p, std::vector<qubit_index>* kept = nullptr) {
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
  for (std::size_t i = 0; i < p.ops().size(); ++i) {
    op::any o = p.ops()[i];
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
    r.enter_layer(p.layer_of(i));
    r.push(std::move(o));
  }
  if (kept) *kept = orig;
  return r;
}

// A walk circuit as a program, after pruning, with where `out` ended up.
struct walk_program {
  program circuit;      // idle qubits removed; each op labelled with its walk_layer's name
  walk_tables tables;
  qubit_index out = 0;  // in `circuit`
  std::size_t full_width = 0;
};

// with_dynamic_walk<Only>(dims, f): f(std::type_identity<walk_circuit<dynamic_walk_shape<D>>>) for
// the run-time dims D; Only = 2 or 3 compiles that walk alone and refuses scenes of the other.
template <unsigned Only = 0, class F>
decltype(auto) with_dynamic_walk(unsigned dims, F&& f) {
  static_assert(Only == 0 || Only == 2 || Only == 3, "with_dynamic_walk<Only>: Only is 2 or 3 (0: either)");
  if (dims != 2 && dims != 3) throw std::invalid_argument("walk: dims must be 2 or 3, got " + std::to_string(dims));
  if constexpr (Only != 0) {
    if (dims != Only)
      throw std::invalid_argument("walk: the scene has " + std::to_string(dims) + " dimensions; this walk is compiled for " +
                                  std::to_string(Only));
    return f(std::type_identity<walk_circuit<dynamic_walk_shape<Only>>>{});
  } else {
    if (dims == 2) return f(std::type_identity<walk_circuit<dynamic_walk_shape<2>>>{});
    return f(std::type_identity<walk_circuit<dynamic_walk_shape<3>>>{});
  }
}

// record(c): a typed circuit lowered to a program (its layout's non-empty registers kept for
// export, each op labelled with its layer).
template <class C>
program record(const C& c) {
  program p(c.num_qubits());
  std::vector<register_info> regs;
  for (const register_info& r : c.layout().registers_info())
    if (r.width > 0) regs.push_back(r);
  p.set_registers(std::move(regs));
  c.emit(p);
  return p;
}

// make_walk_program(model, start, options): the A operator for run-time sizes (any scene): the
// walk's gate templates on a dynamic layout, recorded, then (pruned levels) without idle qubits.
// make_walk_program<Dims>(...) is the same for a scene known to have Dims dimensions: it compiles
// one walk instead of both (a 2D-only program need not build the 3D one), and refuses other scenes.
template <unsigned Dims = 0>
walk_program make_walk_program(const walk_model& m, const walk_start& start, const walk_options& o) {
  auto build = [&]<class C>(std::type_identity<C>) {
    const C a(m, start, o);
    walk_program w;
    w.tables = a.tables();
    w.full_width = a.num_qubits();
    program p = record(a);
    const qubit_index out = a.out_qubit();
    if (o.prune == pruning::none) {
      w.circuit = std::move(p);
      w.out = out;
      return w;
    }
    std::vector<qubit_index> kept;
    w.circuit = remove_idle_qubits(p, &kept);
    const auto it = std::find(kept.begin(), kept.end(), out);
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
    return w;
  };
  return with_dynamic_walk<Dims>(m.dims(), build);
}

// probability_out(backend, w): run w's circuit on a fresh backend and read P(out = 1).
template <class Backend>
double probability_out(Backend& b, const walk_program& w) {
  run(b, w.circuit);
  const control c{w.out, true};
  return b.probability(std::span<const control>(&c, 1));
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_WALK_CIRCUIT_INSTANCES(PREFIX)                                                      \
  PREFIX walk_tables build_walk_tables<0>(const walk_model&, const walk_start&, const walk_options&);  \
  PREFIX program remove_idle_qubits<0>(const program&, std::vector<qubit_index>*);                     \
  PREFIX walk_program make_walk_program<0>(const walk_model&, const walk_start&, const walk_options&); \
  PREFIX walk_program make_walk_program<2>(const walk_model&, const walk_start&, const walk_options&); \
  PREFIX walk_program make_walk_program<3>(const walk_model&, const walk_start&, const walk_options&);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_WALK_CIRCUIT_INSTANCES(extern template)
}  // namespace qrm
#endif
