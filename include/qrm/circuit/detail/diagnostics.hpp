// qrm/circuit/detail/diagnostics.hpp: compile errors that name the culprit (which register, which
// qubit, which value).
//
// A static_assert message is a fixed string literal, so a rule that fails asserts inside a class
// template whose arguments spell out the culprit, e.g. qubit_used_twice<register_name<'d','i','r'>,
// bit_index<0>>; both compilers print that in the "in instantiation of" line next to the rule's
// message. Names are char packs: clang prints a fixed_string argument as {{100, 105, 114, 0}}.
//
// Use: static_assert(require<rule, culprit_finder>::checked, "rule: ..."). When the rule holds,
// nothing is instantiated beyond no_error. When it fails, only the culprit's own assertion fails:
// `checked` is true and require<> asserts at class scope, so the caller stays valid even inside a
// function body. Otherwise clang drops the caller and reports again wherever it is used ("no
// matching function for call to 'make_circuit'", "must be initialized by a constant expression").
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "../../support/detail/meta.hpp"

namespace qrm::detail {

// The words of a diagnostic.
template <char... C>
struct register_name {};
template <std::size_t I>
struct bit_index {};
template <std::uint64_t V>
struct control_value {};
template <std::size_t N>
struct selected_qubits {};
template <class... Names>
struct layout_registers {};

template <class R, class = std::make_index_sequence<R::name.size()>>
struct name_of_impl;
template <class R, std::size_t... I>
struct name_of_impl<R, std::index_sequence<I...>> {
  using type = register_name<R::name[I]...>;
};
// name_of<R>: register_name<'d','i','r'> for a register named "dir".
template <class R>
using name_of = typename name_of_impl<R>::type;

template <class List>
struct names_of_layout;
template <class... R>
struct names_of_layout<type_list<R...>> {
  using type = layout_registers<name_of<R>...>;
};

// list_at_t<I, type_list<T...>>: the I-th type.
template <std::size_t I, class List>
struct list_at;
template <std::size_t I, class T, class... Rest>
struct list_at<I, type_list<T, Rest...>> : list_at<I - 1, type_list<Rest...>> {};
template <class T, class... Rest>
struct list_at<0, type_list<T, Rest...>> {
  using type = T;
};
template <std::size_t I, class List>
using list_at_t = typename list_at<I, List>::type;

struct no_error {
  static constexpr bool reported = true;
};
template <bool Ok, class Finder>
struct culprit_unless {
  using type = typename Finder::type;
};
template <class Finder>
struct culprit_unless<true, Finder> {
  using type = no_error;
};

// require<Ok, Finder>: when !Ok, instantiates Finder::type, the culprit below, whose assertion fails.
template <bool Ok, class Finder>
struct require {
  static_assert(culprit_unless<Ok, Finder>::type::reported);
  static constexpr bool checked = true;
};

// ---- the culprits ----------------------------------------------------------------------------

template <class Register, class Bit>
struct qubit_used_twice {
  static_assert(always_false<Register, Bit>,
                "qubits_must_be_disjoint: a qubit is used twice among the gate's targets, select and controls "
                "(qubit_used_twice<register_name<...>, bit_index<i>> names it)");
  static constexpr bool reported = true;
};

template <class Value, class Qubits, class... Registers>
struct control_value_too_large {
  static_assert(always_false<Value, Qubits, Registers...>,
                "control_value_must_fit_register: when<S, V> needs V < 2^(number of qubits of S) "
                "(control_value_too_large<control_value<V>, selected_qubits<n>, register_name<...>...> names them)");
  static constexpr bool reported = true;
};

template <class Register, class Layout>
struct register_not_in_layout {
  static_assert(always_false<Register, Layout>,
                "register_must_belong_to_layout: the register is not part of the layout "
                "(register_not_in_layout<register_name<...>, layout_registers<...>> names them)");
  static constexpr bool reported = true;
};

// ---- finders (instantiated only when their rule fails) ---------------------------------------

// The first register of Used that Layout (a type_list) lacks.
template <class Used, class Layout>
struct find_foreign_register;
template <class R, class... Rest, class Layout>
struct find_foreign_register<type_list<R, Rest...>, Layout> {
  using type = typename std::conditional_t<
      list_contains<R, Layout>, find_foreign_register<type_list<Rest...>, Layout>,
      std::type_identity<register_not_in_layout<name_of<R>, typename names_of_layout<Layout>::type>>>::type;
};

}  // namespace qrm::detail
