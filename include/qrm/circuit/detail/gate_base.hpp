// qrm/circuit/detail/gate_base.hpp: what every static gate template shares: the named rules on its
// qubit arguments, their resolution in a layout, and ASAP scheduling for depth bounds.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

#include "../layout.hpp"
#include "../../support/detail/meta.hpp"
#include "diagnostics.hpp"

namespace qrm::detail {

template <class L>
struct layout_from_list;
template <class... R>
struct layout_from_list<type_list<R...>> {
  using type = layout<R...>;
};

// checked_qubits<type_list<Sel...>, Ctrls...>: the selectors a gate acts on (targets, select
// registers) and its controls, with the rules every gate states.
template <class Sels, class... Ctrls>
struct checked_qubits;

template <class... Sels, class... Ctrls>
struct checked_qubits<type_list<Sels...>, Ctrls...> {
  static constexpr bool operands_must_select_qubits = (selector<Sels> && ...);
  static constexpr bool controls_must_select_qubits = (control_traits<Ctrls>::valid && ...);
  static constexpr bool control_value_must_fit_register = (control_traits<Ctrls>::fits && ...);
  static constexpr bool well_formed =
      operands_must_select_qubits && controls_must_select_qubits && control_value_must_fit_register;

  using registers = std::conditional_t<well_formed,
                                       list_unique_t<list_join_t<typename selector_traits<Sels>::registers...,
                                                                 control_registers_t<Ctrls...>>>,
                                       type_list<>>;

  template <class L>
  static constexpr auto all_qubits() {
    std::array<qubit_index, (std::size_t{0} + ... + selector_traits<Sels>::count)> ops{};
    std::size_t i = 0;
    (void)i;
    (
        [&] {
          for (qubit_index q : selector_traits<Sels>::template resolve<L>()) ops[i++] = q;
        }(),
        ...);
    const auto cs = resolve_controls<L, Ctrls...>();
    std::array<qubit_index, cs.size()> cq{};
    for (std::size_t k = 0; k < cs.size(); ++k) cq[k] = cs[k].qubit;
    return concat(ops, cq);
  }

  static constexpr bool disjoint() {
    if constexpr (!well_formed) {
      return true;  // the earlier rule already failed; do not pile on
    } else {
      using local = typename layout_from_list<registers>::type;
      return all_distinct(all_qubits<local>());
    }
  }
  static constexpr bool qubits_must_be_disjoint = disjoint();

  // The culprits of the last two rules (see diagnostics.hpp), instantiated only when one fails.
  using oversized_control = find_oversized_control<Ctrls...>;
  struct find_clash {  // the first qubit used twice: its register and bit
    using local = typename layout_from_list<registers>::type;
    static constexpr auto qs = all_qubits<local>();
    static constexpr qubit_index q = [] {
      for (std::size_t i = 0; i < qs.size(); ++i)
        for (std::size_t j = i + 1; j < qs.size(); ++j)
          if (qs[i] == qs[j]) return qs[i];
      return qs[0];
    }();
    static constexpr std::size_t r = [] {
      std::size_t i = 0;
      while (q >= local::register_table[i].offset + local::register_table[i].width) ++i;
      return i;
    }();
    using type = qubit_used_twice<name_of<list_at_t<r, registers>>, bit_index<q - local::register_table[r].offset>>;
  };
};

// Every qubit of `qs` waits for the latest of them, then all advance by `layers`.
template <std::size_t W, std::size_t N>
constexpr void schedule_block(std::array<std::size_t, W>& level, const std::array<qubit_index, N>& qs,
                              std::size_t layers) {
  std::size_t start = 0;
  for (qubit_index q : qs) start = std::max(start, level[q]);
  for (qubit_index q : qs) level[q] = start + layers;
}

}  // namespace qrm::detail

// The three rules every gate template asserts, with their one-line messages.
#define QRM_DETAIL_ASSERT_GATE_ARGS(checked)                                                                       \
  static_assert(checked::operands_must_select_qubits,                                                              \
                "operands_must_select_qubits: targets and select registers must be a register, bit<>, slice<> or " \
                "qubits<>");                                                                                       \
  static_assert(checked::controls_must_select_qubits,                                                              \
                "controls_must_select_qubits: each control must be when<S, V>, on<S>, off<S> or a selector");      \
  static_assert(::qrm::detail::require<checked::control_value_must_fit_register,                                   \
                                       typename checked::oversized_control>::checked,                              \
                "control_value_must_fit_register: when<S, V> needs V < 2^(number of qubits of S)");                \
  static_assert(::qrm::detail::require<checked::qubits_must_be_disjoint,                                           \
                                       typename checked::find_clash>::checked,                                     \
                "qubits_must_be_disjoint: a qubit is used twice among the gate's targets, select and controls")
