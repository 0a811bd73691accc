// qrm/circuit/gates.hpp: gate templates placed on registers of a layout.
//
// A gate template names its qubits by type (registers, bit<>, slice<>, qubits<>) and its
// controls by type (when<S, V>, on<S>, off<S>); run-time data (angles, matrices, tables) lives
// in the object. Every gate follows one protocol, used by circuits (circuit.hpp):
//   registers               the registers it touches (a type_list)
//   is_real                 all its matrices are real (it may run on a real-valued backend)
//   gate_count_bound        logical gates it emits at most (a multiplexed gate: one per entry)
//   schedule<L>(level)      ASAP depth update of per-qubit levels (compile time)
//   touch<L>(used)          marks its qubits (compile time)
//   emit<L>(sink)           lowers itself to the primitive operations of ops.hpp
//   adjoint()               its inverse, as a gate object
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "../support/detail/formatted_error.hpp"
#include "detail/gate_base.hpp"
#include "layout.hpp"
#include "ops.hpp"

namespace qrm {

namespace detail {

template <int = 0>
inline double checked_angle(const char* gate, double theta) {
  if (!std::isfinite(theta))
    throw_formatted<std::invalid_argument>("%s: angle must be finite, got %f", gate, theta);
  return theta;
}

// Saturating 2^m for depth bounds of multiplexed gates.
constexpr std::size_t pow2_saturated(std::size_t m) {
  return m >= 63 ? std::numeric_limits<std::size_t>::max() / 4 : std::size_t{1} << m;
}

template <class L, std::size_t W, std::size_t N>
constexpr void mark(std::array<bool, W>& used, const std::array<qubit_index, N>& qs) {
  for (qubit_index q : qs) used[q] = true;
}

// gate1_base: a single-qubit gate applied to each qubit of Target, under the same controls.
template <class Derived, bool Real, class Target, class... Ctrls>
struct gate1_base {
  using checked = checked_qubits<type_list<Target>, Ctrls...>;
  QRM_DETAIL_ASSERT_GATE_ARGS(checked);

  using registers = typename checked::registers;
  static constexpr bool is_real = Real;
  static constexpr std::size_t gate_count_bound = selector_traits<Target>::count;

  template <class L, std::size_t W>
  static constexpr void schedule(std::array<std::size_t, W>& level) {
    constexpr auto cs = resolve_controls<L, Ctrls...>();
    for (qubit_index t : resolve<L, Target>()) {
      std::array<qubit_index, cs.size() + 1> qs{};
      qs[0] = t;
      for (std::size_t i = 0; i < cs.size(); ++i) qs[i + 1] = cs[i].qubit;
      schedule_block(level, qs, 1);
    }
  }
  template <class L, std::size_t W>
  static constexpr void touch(std::array<bool, W>& used) {
    mark<L>(used, checked::template all_qubits<L>());
  }
  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto targets = resolve<L, Target>();
    static constexpr auto controls = resolve_controls<L, Ctrls...>();
    const gate1 g = static_cast<const Derived&>(*this).matrix();
    for (qubit_index t : targets) sink.apply_gate1(g, t, std::span<const control>(controls));
  }
};

// block_gate_base: one operation on all its qubits at once (depth `Layers` on all of them).
template <bool Real, std::size_t Layers, class Operands, class... Ctrls>
struct block_gate_base {
  using checked = checked_qubits<Operands, Ctrls...>;
  QRM_DETAIL_ASSERT_GATE_ARGS(checked);

  using registers = typename checked::registers;
  static constexpr bool is_real = Real;
  static constexpr std::size_t gate_count_bound = Layers;

  template <class L, std::size_t W>
  static constexpr void schedule(std::array<std::size_t, W>& level) {
    schedule_block(level, checked::template all_qubits<L>(), Layers);
  }
  template <class L, std::size_t W>
  static constexpr void touch(std::array<bool, W>& used) {
    mark<L>(used, checked::template all_qubits<L>());
  }
};

}  // namespace detail

// ---- single-qubit gates (applied to every qubit of Target) ----------------------------------

// x<Target, Ctrls...>: Pauli X (NOT); with controls, a (multi-)controlled X.
template <class Target, class... Ctrls>
struct x : detail::gate1_base<x<Target, Ctrls...>, true, Target, Ctrls...> {
  static gate1 matrix() { return gate::x(); }
  x adjoint() const { return *this; }
};

// y<Target, Ctrls...>: Pauli Y (complex).
template <class Target, class... Ctrls>
struct y : detail::gate1_base<y<Target, Ctrls...>, false, Target, Ctrls...> {
  static gate1 matrix() { return gate::y(); }
  y adjoint() const { return *this; }
};

// z<Target, Ctrls...>: Pauli Z.
template <class Target, class... Ctrls>
struct z : detail::gate1_base<z<Target, Ctrls...>, true, Target, Ctrls...> {
  static gate1 matrix() { return gate::z(); }
  z adjoint() const { return *this; }
};

// h<Target, Ctrls...>: Hadamard.
template <class Target, class... Ctrls>
struct h : detail::gate1_base<h<Target, Ctrls...>, true, Target, Ctrls...> {
  static gate1 matrix() { return gate::h(); }
  h adjoint() const { return *this; }
};

// ry<Target, Ctrls...>{theta}: rotation about Y; ry{2 asin(sqrt(v))}|0> has P(|1>) = v.
template <class Target, class... Ctrls>
struct ry : detail::gate1_base<ry<Target, Ctrls...>, true, Target, Ctrls...> {
  double theta = 0;
  ry() = default;
  explicit ry(double t) : theta(detail::checked_angle("ry", t)) {}
  gate1 matrix() const { return gate::ry(theta); }
  ry adjoint() const { return ry{-theta}; }
};

// rz<Target, Ctrls...>{theta}: rotation about Z (complex).
template <class Target, class... Ctrls>
struct rz : detail::gate1_base<rz<Target, Ctrls...>, false, Target, Ctrls...> {
  double theta = 0;
  rz() = default;
  explicit rz(double t) : theta(detail::checked_angle("rz", t)) {}
  gate1 matrix() const { return gate::rz(theta); }
  rz adjoint() const { return rz{-theta}; }
};

// phase<Target, Ctrls...>{theta}: diag(1, e^{i theta}) (complex).
template <class Target, class... Ctrls>
struct phase : detail::gate1_base<phase<Target, Ctrls...>, false, Target, Ctrls...> {
  double theta = 0;
  phase() = default;
  explicit phase(double t) : theta(detail::checked_angle("phase", t)) {}
  gate1 matrix() const { return gate::phase(theta); }
  phase adjoint() const { return phase{-theta}; }
};

namespace detail {
template <int = 0>
inline gate1 checked_gate1(const gate1& g, bool need_real) {
  const double err = unitarity_error(dense_matrix::of(g));
  if (!(err <= 1e-10))
    throw_formatted<std::invalid_argument>("u: the 2x2 matrix is not unitary (max |U^dagger U - I| = %f)", err);
  if (need_real && !g.is_real()) throw std::invalid_argument("real_u: the 2x2 matrix has an imaginary part");
  return g;
}
}  // namespace detail

// u<Target, Ctrls...>{gate1}: any single-qubit unitary (checked unitary on construction).
template <class Target, class... Ctrls>
struct u : detail::gate1_base<u<Target, Ctrls...>, false, Target, Ctrls...> {
  gate1 g = gate::u(1, 0, 0, 1);
  u() = default;
  explicit u(const gate1& m) : g(detail::checked_gate1(m, false)) {}
  gate1 matrix() const { return g; }
  u adjoint() const { return u{qrm::adjoint(g)}; }
};

// ---- dense unitaries on k qubits (coins) ----------------------------------------------------

namespace detail {
template <int = 0>
inline dense_matrix checked_unitary(dense_matrix m, std::size_t k, bool need_real, const char* what) {
  const std::size_t dim = std::size_t{1} << k;
  if (m.dim != dim || m.data.size() != dim * dim)
    throw_formatted<std::invalid_argument>("%s: matrix is %zux%zu but the targets need %zux%zu", what, m.dim, m.dim, dim,
                                           dim);
  for (const complex& z : m.data)
    if (!std::isfinite(z.real()) || !std::isfinite(z.imag()))
      throw_formatted<std::invalid_argument>("%s: matrix has a non-finite entry", what);
  if (need_real && !m.is_real())
    throw_formatted<std::invalid_argument>("%s: matrix has an imaginary part; use the complex form", what);
  // 1e-10 * dim: rows of a unitary built in double precision sum dim products.
  const double err = unitarity_error(m);
  if (!(err <= 1e-10 * static_cast<double>(dim)))
    throw_formatted<std::invalid_argument>("%s: matrix is not unitary (max |U^dagger U - I| = %f)", what, err);
  return m;
}
}  // namespace detail

// basic_unitary<Real, Targets, Ctrls...>{matrix}: a 2^k x 2^k unitary on the k qubits of Targets
// (qubit j of Targets = bit j of the matrix index), checked unitary on construction.
template <bool Real, class Targets, class... Ctrls>
struct basic_unitary : detail::block_gate_base<Real, 1, detail::type_list<Targets>, Ctrls...> {
  static constexpr std::size_t k = detail::selector_traits<Targets>::count;
  static constexpr bool unitary_must_act_on_at_most_16_qubits = k <= 16;
  static_assert(unitary_must_act_on_at_most_16_qubits,
                "unitary_must_act_on_at_most_16_qubits: a dense matrix on more qubits would not fit in memory");

  dense_matrix matrix = dense_matrix::identity(std::size_t{1} << k);
  basic_unitary() = default;
  explicit basic_unitary(dense_matrix m)
      : matrix(detail::checked_unitary(std::move(m), k, Real, Real ? "real_unitary" : "unitary")) {}

  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto targets = resolve<L, Targets>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    sink.apply_unitary(matrix, std::span<const qubit_index>(targets), std::span<const control>(controls));
  }
  basic_unitary adjoint() const { return basic_unitary{qrm::adjoint(matrix)}; }
};
template <class Targets, class... Ctrls>
using unitary = basic_unitary<false, Targets, Ctrls...>;
template <class Targets, class... Ctrls>
using real_unitary = basic_unitary<true, Targets, Ctrls...>;

// ---- permutations: add a constant modulo 2^k ------------------------------------------------

// add<Reg, Constant, Ctrls...>: |v> -> |v + Constant mod 2^k> on the k qubits of Reg.
template <class Reg, std::int64_t Constant, class... Ctrls>
struct add : detail::block_gate_base<true, 1, detail::type_list<Reg>, Ctrls...> {
  static constexpr std::size_t k = detail::selector_traits<Reg>::count;
  static constexpr bool constant_must_fit_register =
      k >= 63 || (Constant < (std::int64_t{1} << k) && Constant > -(std::int64_t{1} << k));
  static_assert(constant_must_fit_register,
                "constant_must_fit_register: add<Reg, C> needs -2^k < C < 2^k for a k-qubit register");

  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto bits = resolve<L, Reg>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    sink.apply_add(Constant, std::span<const qubit_index>(bits), std::span<const control>(controls));
  }
  add<Reg, -Constant, Ctrls...> adjoint() const { return {}; }
};
template <class Reg, class... Ctrls>
using increment = add<Reg, 1, Ctrls...>;
template <class Reg, class... Ctrls>
using decrement = add<Reg, -1, Ctrls...>;

// add_value<Reg, Ctrls...>{c}: add<> with a constant known only at run time.
template <class Reg, class... Ctrls>
struct add_value : detail::block_gate_base<true, 1, detail::type_list<Reg>, Ctrls...> {
  static constexpr std::size_t k = detail::selector_traits<Reg>::count;
  std::int64_t constant = 0;
  add_value() = default;
  explicit add_value(std::int64_t c) : constant(c) {
    if (k < 63 && (c >= (std::int64_t{1} << k) || c <= -(std::int64_t{1} << k)))
      detail::throw_formatted<std::invalid_argument>("add_value: constant %lld does not fit a %zu-qubit register",
                                                     static_cast<long long>(c), k);
  }
  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto bits = resolve<L, Reg>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    sink.apply_add(constant, std::span<const qubit_index>(bits), std::span<const control>(controls));
  }
  add_value adjoint() const { return add_value{-constant}; }
};

// ---- multiplexed (uniformly controlled) gates ------------------------------------------------

namespace detail {
template <int = 0>
inline void check_select(std::uint64_t select, std::size_t m, const char* what) {
  if (m < 64 && select > max_value_of_width(m))
    throw_formatted<std::invalid_argument>("%s: select value %llu does not fit %zu select qubits", what,
                                           static_cast<unsigned long long>(select), m);
}
}  // namespace detail

// mux_ry<Target, Select, Ctrls...>{{value, theta}...}: Ry(theta) on Target where the Select qubits
// read `value`; values without an entry get the identity. (The walk's Sample layer, walk_sample
// in walk/gates.hpp, lowers to the same op with a voxel-index select whose width a scene decides.)
template <class Target, class Select, class... Ctrls>
struct mux_ry : detail::block_gate_base<true, detail::pow2_saturated(detail::selector_traits<Select>::count),
                                        detail::type_list<Target, Select>, Ctrls...> {
  static constexpr std::size_t m = detail::selector_traits<Select>::count;
  static constexpr bool mux_target_must_be_one_qubit = detail::selector_traits<Target>::count == 1;
  static_assert(mux_target_must_be_one_qubit, "mux_target_must_be_one_qubit: mux_ry rotates a single qubit");

  std::vector<mux1_entry> entries;
  mux_ry() = default;
  explicit mux_ry(std::span<const std::pair<std::uint64_t, double>> angles) : entries(angles.size()) {
    for (std::size_t i = 0; i < angles.size(); ++i) {
      detail::check_select(angles[i].first, m, "mux_ry");
      entries[i] = {angles[i].first, gate::ry(detail::checked_angle("mux_ry", angles[i].second))};
    }
  }
  mux_ry(std::initializer_list<std::pair<std::uint64_t, double>> angles)
      : mux_ry(std::span<const std::pair<std::uint64_t, double>>(angles.begin(), angles.size())) {}

  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto target = resolve<L, Target>();
    static constexpr auto select = resolve<L, Select>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    if (entries.empty()) return;
    sink.apply_mux1(std::span<const mux1_entry>(entries), target[0], std::span<const qubit_index>(select),
                    std::span<const control>(controls));
  }
  mux_ry adjoint() const {
    mux_ry r;
    r.entries = entries;
    for (auto& e : r.entries) e.gate = qrm::adjoint(e.gate);
    return r;
  }
};

// basic_mux_unitary<Real, Targets, Select, Ctrls...>: where Select reads `value`, apply
// matrices[entry.matrix] to Targets; the matrices may be shared between values. (The walk's Coin
// layer, walk_coin in walk/gates.hpp, lowers to the same op, selected by the voxel index.)
template <bool Real, class Targets, class Select, class... Ctrls>
struct basic_mux_unitary
    : detail::block_gate_base<Real, detail::pow2_saturated(detail::selector_traits<Select>::count),
                              detail::type_list<Targets, Select>, Ctrls...> {
  static constexpr std::size_t k = detail::selector_traits<Targets>::count;
  static constexpr std::size_t m = detail::selector_traits<Select>::count;

  std::vector<dense_matrix> matrices;
  std::vector<mux_unitary_entry> entries;
  basic_mux_unitary() = default;
  basic_mux_unitary(std::vector<dense_matrix> ms, std::vector<mux_unitary_entry> es) : entries(std::move(es)) {
    const char* what = Real ? "mux_real_unitary" : "mux_unitary";
    matrices.reserve(ms.size());
    for (auto& mat : ms) matrices.push_back(detail::checked_unitary(std::move(mat), k, Real, what));
    for (const auto& e : entries) {
      detail::check_select(e.select, m, what);
      if (e.matrix >= matrices.size())
        detail::throw_formatted<std::invalid_argument>("%s: entry names matrix %u of %zu", what,
                                                       static_cast<unsigned>(e.matrix), matrices.size());
    }
  }

  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto targets = resolve<L, Targets>();
    static constexpr auto select = resolve<L, Select>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    if (entries.empty()) return;
    sink.apply_mux_unitary(std::span<const dense_matrix>(matrices), std::span<const mux_unitary_entry>(entries),
                           std::span<const qubit_index>(targets), std::span<const qubit_index>(select),
                           std::span<const control>(controls));
  }
  basic_mux_unitary adjoint() const {
    basic_mux_unitary r;
    r.entries = entries;
    for (const auto& mat : matrices) r.matrices.push_back(qrm::adjoint(mat));
    return r;
  }
};
template <class Targets, class Select, class... Ctrls>
using mux_unitary = basic_mux_unitary<false, Targets, Select, Ctrls...>;
template <class Targets, class Select, class... Ctrls>
using mux_real_unitary = basic_mux_unitary<true, Targets, Select, Ctrls...>;

// ---- uniform state preparation ---------------------------------------------------------------

namespace detail {
// The Ry cascade that maps |0> to sum_{j<count} |j>/sqrt(count) on `bits` qubits: qubit i (most
// significant first) is rotated by an angle selected by the qubits above it. Emitted as one
// gate1 (top qubit) then one mux1 per lower qubit.
template <gate_sink S>
void emit_uniform_preparation(S& sink, std::span<const qubit_index> bits, std::uint64_t count, bool inverse,
                              std::span<const control> controls) {
  const std::size_t k = bits.size();
  auto angle_for = [&](std::size_t i, std::uint64_t prefix, double& theta) {
    const std::uint64_t block = std::uint64_t{1} << (i + 1), half = std::uint64_t{1} << i;
    const std::uint64_t start = prefix * block;
    if (start >= count) return false;
    const std::uint64_t c = std::min<std::uint64_t>(count - start, block);
    const std::uint64_t c1 = c > half ? c - half : 0;
    if (c1 == 0) return false;
    theta = 2.0 * std::asin(std::sqrt(static_cast<double>(c1) / static_cast<double>(c)));
    return true;
  };
  auto emit_bit = [&](std::size_t i) {
    const double sign = inverse ? -1.0 : 1.0;
    if (i + 1 == k) {
      double theta = 0;
      if (angle_for(i, 0, theta)) sink.apply_gate1(gate::ry(sign * theta), bits[i], controls);
      return;
    }
    detail::deferred_by<std::vector<mux1_entry>, S> entries;
    const std::uint64_t prefixes = std::uint64_t{1} << (k - 1 - i);
    for (std::uint64_t p = 0; p < prefixes; ++p) {
      double theta = 0;
      if (angle_for(i, p, theta)) entries.push_back({p, gate::ry(sign * theta)});
    }
    if (!entries.empty()) sink.apply_mux1(entries, bits[i], bits.subspan(i + 1), controls);
  };
  if (!inverse)
    for (std::size_t i = k; i-- > 0;) emit_bit(i);
  else
    for (std::size_t i = 0; i < k; ++i) emit_bit(i);
}
}  // namespace detail

// prepare_uniform<Reg, Count, Ctrls...>: |0> -> (|0> + ... + |Count-1>)/sqrt(Count) on Reg (the
// Path gate's steps register); a real unitary (an Ry cascade), inverse via adjoint().
template <class Reg, std::uint64_t Count, bool Inverse = false, class... Ctrls>
struct prepare_uniform
    : detail::block_gate_base<true, detail::selector_traits<Reg>::count, detail::type_list<Reg>, Ctrls...> {
  static constexpr std::size_t k = detail::selector_traits<Reg>::count;
  static constexpr bool prepared_count_must_fit_register = Count >= 1 && (k >= 64 || Count <= (std::uint64_t{1} << k));
  static_assert(prepared_count_must_fit_register,
                "prepared_count_must_fit_register: prepare_uniform<Reg, M> needs 1 <= M <= 2^k for a k-qubit register");

  template <class L, gate_sink S>
  void emit(S& sink) const {
    static constexpr auto bits = resolve<L, Reg>();
    static constexpr auto controls = detail::resolve_controls<L, Ctrls...>();
    detail::emit_uniform_preparation(sink, std::span<const qubit_index>(bits), Count, Inverse,
                                     std::span<const control>(controls));
  }
  prepare_uniform<Reg, Count, !Inverse, Ctrls...> adjoint() const { return {}; }
};

}  // namespace qrm
