// qrm/circuit/compose.hpp: composing gates (seq, repeat, unroll), binding them to a layout (circuit),
// compile-time metrics (width, qubits touched, a depth bound) and running them on a backend.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "../support/detail/formatted_error.hpp"
#include "../support/detail/meta.hpp"
#include "gates.hpp"
#include "layout.hpp"
#include "ops.hpp"

namespace qrm {

// static_gate: a type that follows the gate protocol of gates.hpp.
template <class G>
concept static_gate = requires(const G& g) {
  typename G::registers;
  { G::is_real } -> std::convertible_to<bool>;
  { G::gate_count_bound } -> std::convertible_to<std::size_t>;
  g.adjoint();
};

template <class G>
using adjoint_t = decltype(std::declval<const G&>().adjoint());

namespace detail {
// A sequence's gates, each in a base of its own: std::tuple's constructors and std::apply cost a
// typed circuit's file more to compile than the gates do.
template <std::size_t I, class G>
struct seq_slot {
  G gate;
};
template <class Indices, class... G>
struct seq_slots;
template <std::size_t... I, class... G>
struct seq_slots<std::index_sequence<I...>, G...> : seq_slot<I, G>... {
  seq_slots() = default;
  explicit seq_slots(G... g) : seq_slot<I, G>{std::move(g)}... {}
  template <class L, class S>
  void emit(S& sink) const {
    (static_cast<const seq_slot<I, G>&>(*this).gate.template emit<L>(sink), ...);
  }
};
// seq_gate<I>(slots): the I-th gate (the base seq_slot<I, G> is found by deduction).
template <std::size_t I, class G>
const G& seq_gate(const seq_slot<I, G>& slot) {
  return slot.gate;
}
}  // namespace detail

// seq<G...>: the gates in order (a gate itself, so sequences nest).
template <static_gate... G>
struct seq {
  detail::seq_slots<std::index_sequence_for<G...>, G...> gates;

  seq() = default;
  explicit seq(G... g) : gates(std::move(g)...) {}

  using registers = detail::list_unique_t<detail::list_join_t<typename G::registers...>>;
  static constexpr bool is_real = (G::is_real && ...);
  static constexpr std::size_t gate_count_bound = (std::size_t{0} + ... + G::gate_count_bound);

  template <class L, std::size_t W>
  static constexpr void schedule(std::array<std::size_t, W>& level) {
    (G::template schedule<L>(level), ...);
  }
  template <class L, std::size_t W>
  static constexpr void touch(std::array<bool, W>& used) {
    (G::template touch<L>(used), ...);
  }
  template <class L, gate_sink S>
  void emit(S& sink) const {
    gates.template emit<L>(sink);
  }
  auto adjoint() const { return reversed_adjoint(std::index_sequence_for<G...>{}); }

 private:
  template <std::size_t... I>
  auto reversed_adjoint(std::index_sequence<I...>) const {
    constexpr std::size_t n = sizeof...(G);
    return seq<decltype(detail::seq_gate<n - 1 - I>(gates).adjoint())...>(detail::seq_gate<n - 1 - I>(gates).adjoint()...);
  }
};

template <static_gate... G>
seq(G...) -> seq<G...>;

// repeat<N, G>: G applied N times (Grover iterations, identical walk steps).
template <std::size_t N, static_gate G>
struct repeat {
  G gate;

  using registers = typename G::registers;
  static constexpr bool is_real = G::is_real;
  static constexpr std::size_t gate_count_bound = N * G::gate_count_bound;

  template <class L, std::size_t W>
  static constexpr void schedule(std::array<std::size_t, W>& level) {
    for (std::size_t i = 0; i < N; ++i) G::template schedule<L>(level);
  }
  template <class L, std::size_t W>
  static constexpr void touch(std::array<bool, W>& used) {
    G::template touch<L>(used);
  }
  template <class L, gate_sink S>
  void emit(S& sink) const {
    for (std::size_t i = 0; i < N; ++i) gate.template emit<L>(sink);
  }
  repeat<N, adjoint_t<G>> adjoint() const { return {gate.adjoint()}; }
};

// unroll<N>(f): seq(f(integral_constant<0>), ..., f(integral_constant<N-1>)), for steps that
// differ by a compile-time index (step i writes Le_i and rho_i).
template <std::size_t N, class F>
auto unroll(F&& f) {
  return [&]<std::size_t... I>(std::index_sequence<I...>) {
    return seq{f(std::integral_constant<std::size_t, I>{})...};
  }(std::make_index_sequence<N>{});
}

// gate_in_layout<G, L>: every register G touches is part of L.
template <class G, class L>
concept gate_in_layout = static_gate<G> && static_layout<L> && detail::every_in<typename G::registers, typename L::registers>;

// circuit<L, G...>: gates bound to a layout, with compile-time metrics.
template <static_layout L, static_gate... G>
struct circuit {
  using layout_type = L;
  using body_type = seq<G...>;
  body_type body;

  static constexpr bool register_must_belong_to_layout =
      detail::every_in<typename body_type::registers, typename L::registers>;
  static_assert(
      detail::require<register_must_belong_to_layout,
                      detail::find_foreign_register<typename body_type::registers, typename L::registers>>::checked,
      "register_must_belong_to_layout: a gate of the circuit uses a register the layout does not have");

  circuit() = default;
  explicit circuit(G... g) : body(std::move(g)...) {}
  explicit circuit(body_type b) : body(std::move(b)) {}

  // Width: the layout's qubits.
  static constexpr std::size_t width = L::width;
  // Every emitted op (a multiplexed gate: every possible entry) counted once.
  static constexpr std::size_t gate_count_bound = body_type::gate_count_bound;
  static constexpr bool is_real = body_type::is_real;

  // Depth bound: ASAP layering of the gates as the structure gives them (a multiplexed gate
  // occupies one layer per possible select value; a run-time table may prune that).
  // (Neither these metrics nor emit() look a foreign register up: the rule above reported it.)
  static constexpr std::size_t depth_bound = [] {
    if constexpr (L::width == 0 || !register_must_belong_to_layout) {
      return std::size_t{0};
    } else {
      std::array<std::size_t, L::width> level{};
      body_type::template schedule<L>(level);
      return *std::max_element(level.begin(), level.end());
    }
  }();
  // Qubits some gate touches.
  static constexpr std::size_t qubits_touched = [] {
    std::array<bool, L::width> used{};
    if constexpr (register_must_belong_to_layout) body_type::template touch<L>(used);
    return static_cast<std::size_t>(std::count(used.begin(), used.end(), true));
  }();

  template <gate_sink S>
  void emit(S& sink) const {
    if constexpr (register_must_belong_to_layout) body.template emit<L>(sink);
  }

  auto adjoint() const {
    auto b = body.adjoint();
    return [&]<class... A>(seq<A...> s) { return circuit<L, A...>(std::move(s)); }(std::move(b));
  }
};

// make_circuit<L>(g...): bind gates to layout L.
template <static_layout L, static_gate... G>
circuit<L, G...> make_circuit(G... g) {
  return circuit<L, G...>(std::move(g)...);
}

template <class T>
inline constexpr bool is_circuit_v = false;
template <class L, class... G>
inline constexpr bool is_circuit_v<circuit<L, G...>> = true;

// real_valued_backend<B>: B stores real amplitudes (declares `is_complex = false`).
template <class B>
concept real_valued_backend = requires { B::is_complex; } && !B::is_complex;

// can_run<C, B>: C may run on backend B (a complex gate needs a complex backend).
template <class C, class B>
concept can_run = gate_sink<B> && (C::is_real || !real_valued_backend<B>);

// run(backend, c): apply circuit (or program) c to the backend's state.
template <class B, class C>
void run(B& backend, const C& c) {
  constexpr bool complex_gate_needs_complex_backend = C::is_real || !real_valued_backend<B>;
  static_assert(complex_gate_needs_complex_backend,
                "complex_gate_needs_complex_backend: the circuit has a complex gate but the backend stores real "
                "amplitudes; use std::complex<double> or std::complex<float>");
  std::size_t needed = 0;
  if constexpr (is_circuit_v<C>) {
    needed = C::width;
  } else if constexpr (requires { c.num_qubits(); }) {
    needed = c.num_qubits();  // a typed circuit on a layout with dynamic widths
  }
  if (backend.num_qubits() < needed)
    detail::throw_formatted<std::invalid_argument>("run: the circuit needs %zu qubits but the backend has %zu", needed,
                                                   static_cast<std::size_t>(backend.num_qubits()));
  c.emit(backend);
}

}  // namespace qrm
