// qrm/circuit/layout.hpp: layouts (registers placed at compile-time qubit offsets), qubit selectors
// (a register, one bit, a slice, a concatenation) and controls (`when`, `on`, `off`).
#pragma once

#include <array>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "../support/detail/meta.hpp"
#include "detail/diagnostics.hpp"
#include "ops.hpp"
#include "registers.hpp"

namespace qrm {

// Run-time description of one register of a layout (for printing, export and pruning).
struct register_info {
  std::string_view name;
  role kind;
  qubit_index offset;
  std::size_t width;
};

namespace detail {
template <class R, class... Regs>
constexpr std::size_t index_in_pack() {
  std::size_t i = 0;
  bool found = false;
  ((found = found || std::is_same_v<R, Regs>, i += found ? 0 : 1), ...);
  return i;
}

// The storage of a layout whose widths are all constants: everything is a constant expression.
template <bool AllStatic, class... Regs>
struct layout_storage {
  static constexpr bool is_static = true;
  static constexpr std::size_t width = (Regs::width + ... + 0);

 private:
  static constexpr std::array<register_info, sizeof...(Regs)> infos() {
    std::array<register_info, sizeof...(Regs)> r{};
    qubit_index off = 0;
    std::size_t i = 0;
    ((r[i++] = register_info{Regs::name, Regs::kind, off, Regs::width}, off += static_cast<qubit_index>(Regs::width)),
     ...);
    return r;
  }

 public:
  static constexpr std::array<register_info, sizeof...(Regs)> register_table = infos();

  // offset<R>: the qubit index of R's least significant qubit.
  template <class R>
  static constexpr qubit_index offset = [] {
    constexpr bool found = (std::is_same_v<R, Regs> || ...);
    static_assert(require<found, find_foreign_register<type_list<R>, type_list<Regs...>>>::checked,
                  "register_must_belong_to_layout: the register is not part of this layout");
    if constexpr (found)
      return register_table[index_in_pack<R, Regs...>()].offset;
    else
      return qubit_index{0};  // already reported: no second error for the out-of-range index
  }();

  static constexpr std::size_t num_qubits() { return width; }
  static constexpr std::span<const register_info> registers_info() { return register_table; }
};

// The storage of a layout with dynamic widths: widths given at construction, checked there by
// the rules a static register states at compile time (same rule names in the message).
template <class... Regs>
struct layout_storage<false, Regs...> {
  static constexpr bool is_static = false;
  static constexpr std::size_t dynamic_count = ((Regs::is_dynamic ? 1 : 0) + ... + 0);

  // layout<R...>(w...): one width per dynamic register, in layout order. A dynamic register may
  // be empty (width 0): present in the type, absent at this size (the walk's rho register at s = 1).
  template <class... W>
    requires(sizeof...(W) == dynamic_count && (std::is_convertible_v<W, std::size_t> && ...))
  explicit layout_storage(W... dynamic_widths)
      : layout_storage(std::array<std::size_t, dynamic_count>{static_cast<std::size_t>(dynamic_widths)...}) {}

  explicit layout_storage(const std::array<std::size_t, dynamic_count>& given) {
    std::size_t next = 0, i = 0;
    qubit_index off = 0;
    (
        [&] {
          std::size_t w = 0;
          if constexpr (Regs::is_dynamic) {
            w = given[next++];
          } else {
            w = Regs::width;
          }
          if (w > 64)
            throw std::invalid_argument("register_width_must_fit_64_bits: register '" + std::string(Regs::name) +
                                        "' is " + std::to_string(w) + " qubits wide; register values are 64-bit numbers");
          table_[i++] = register_info{Regs::name, Regs::kind, off, w};
          off += static_cast<qubit_index>(w);
        }(),
        ...);
    width_ = off;
  }

  std::size_t num_qubits() const { return width_; }
  std::span<const register_info> registers_info() const { return table_; }

 protected:
  std::array<register_info, sizeof...(Regs)> table_{};
  std::size_t width_ = 0;
};
}  // namespace detail

// layout<R...>: registers placed one after another from qubit 0 (the first register holds the
// least significant qubits of a basis-state index). With static widths every offset is a
// constant (layout<...>::offset<R>); with dynamic widths (reg<Name, dynamic_width, Role>) a
// layout object is built from the run-time widths. Both answer offset_of<R>() and width_of<R>().
template <register_type... Regs>
struct layout : detail::layout_storage<(static_register<Regs> && ...), Regs...> {
  using storage = detail::layout_storage<(static_register<Regs> && ...), Regs...>;
  using storage::storage;
  layout() requires(storage::is_static) = default;

  using registers = detail::type_list<Regs...>;
  static constexpr std::size_t register_count = sizeof...(Regs);

  static constexpr bool registers_must_be_distinct =
      std::is_same_v<detail::list_unique_t<registers>, registers>;
  static_assert(registers_must_be_distinct, "registers_must_be_distinct: a register appears twice in the layout");
  static constexpr bool register_names_must_be_distinct =
      detail::all_distinct(std::array<std::string_view, sizeof...(Regs)>{Regs::name...});
  static_assert(register_names_must_be_distinct,
                "register_names_must_be_distinct: two registers of the layout share a name");

  template <class R>
  static constexpr bool contains = detail::list_contains<R, registers>;

  // offset_of<R>() / width_of<R>(): where R starts and how many qubits it has (constant
  // expressions when the layout is static).
  template <class R>
  constexpr qubit_index offset_of() const {
    static_assert(detail::require<contains<R>, detail::find_foreign_register<detail::type_list<R>, registers>>::checked,
                  "register_must_belong_to_layout: the register is not part of this layout");
    if constexpr (contains<R>)
      return this->registers_info()[detail::index_in_pack<R, Regs...>()].offset;
    else
      return 0;  // already reported: no second error for the out-of-range index
  }
  template <class R>
  constexpr std::size_t width_of() const {
    static_assert(detail::require<contains<R>, detail::find_foreign_register<detail::type_list<R>, registers>>::checked,
                  "register_must_belong_to_layout: the register is not part of this layout");
    if constexpr (contains<R>)
      return this->registers_info()[detail::index_in_pack<R, Regs...>()].width;
    else
      return 0;
  }
  // qubit_of<R>(i): qubit i of R (i counted from R's least significant qubit), checked.
  template <class R>
  constexpr qubit_index qubit_of(std::size_t i) const {
    if (i >= width_of<R>())
      throw std::out_of_range("bit_index_must_be_within_register: bit " + std::to_string(i) + " of register '" +
                              std::string(R::name) + "', which has " + std::to_string(width_of<R>()) + " qubits");
    return offset_of<R>() + static_cast<qubit_index>(i);
  }
  // with_widths(w): the layout whose i-th register has w[i] qubits. A static register must have
  // exactly its declared width: the error names it (a scene that does not fit a typed circuit).
  static layout with_widths(const std::array<std::size_t, sizeof...(Regs)>& w) {
    std::size_t i = 0;
    (
        [&] {
          if constexpr (!Regs::is_dynamic)
            if (w[i] != Regs::width)
              throw std::invalid_argument("register '" + std::string(Regs::name) + "' has " +
                                          std::to_string(Regs::width) + " qubits in the layout type, but " +
                                          std::to_string(w[i]) + " are needed");
          ++i;
        }(),
        ...);
    if constexpr (storage::is_static) {
      return layout{};
    } else {
      std::array<std::size_t, storage::dynamic_count> dynamic{};
      std::size_t next = 0;
      i = 0;
      ((Regs::is_dynamic ? void(dynamic[next++] = w[i++]) : void(i++)), ...);
      return layout(dynamic);
    }
  }

  // qubits_of<R>(): R's qubits, least significant first.
  template <class R>
  std::vector<qubit_index> qubits_of() const {
    std::vector<qubit_index> q(width_of<R>());
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = offset_of<R>() + static_cast<qubit_index>(i);
    return q;
  }
};

template <class T>
inline constexpr bool is_layout_v = false;
template <class... R>
inline constexpr bool is_layout_v<layout<R...>> = true;
// layout_type: any qrm::layout<...>.
template <class T>
concept layout_type = is_layout_v<T>;
// static_layout: a layout whose offsets are all constants (what circuit<> and the selectors need).
template <class T>
concept static_layout = layout_type<T> && T::is_static;

// ---- qubit selectors ------------------------------------------------------------------------

// bit<R, I>: qubit I of register R.
template <register_type R, std::size_t I>
struct bit {
  static constexpr bool bit_index_must_be_within_register = I < R::width;
  static_assert(bit_index_must_be_within_register, "bit_index_must_be_within_register: bit<R, I> needs I < R::width");
};

// slice<R, First, Count>: qubits First .. First+Count-1 of R (First is the least significant).
template <register_type R, std::size_t First, std::size_t Count>
struct slice {
  static constexpr bool slice_must_be_within_register = Count >= 1 && First + Count <= R::width;
  static_assert(slice_must_be_within_register,
                "slice_must_be_within_register: slice<R, First, Count> needs Count >= 1 and First + Count <= R::width");
};

// qubits<S...>: the selectors' qubits concatenated, the first selector least significant.
template <class... S>
struct qubits {};

namespace detail {
template <class S>
struct selector_traits {
  static constexpr bool valid = false;
};
template <fixed_string N, role Ro>
struct selector_traits<reg<N, dynamic_width, Ro>> {
  static constexpr bool valid = false;  // its qubits are known only to a layout object
};
template <fixed_string N, std::size_t W, role Ro>
struct selector_traits<reg<N, W, Ro>> {
  static constexpr bool valid = true;
  using registers = type_list<reg<N, W, Ro>>;
  static constexpr std::size_t count = W;
  template <class L>
  static constexpr std::array<qubit_index, count> resolve() {
    std::array<qubit_index, count> r{};
    for (std::size_t i = 0; i < count; ++i) r[i] = L::template offset<reg<N, W, Ro>> + static_cast<qubit_index>(i);
    return r;
  }
};
template <class R, std::size_t I>
struct selector_traits<bit<R, I>> {
  static constexpr bool valid = I < R::width;
  using registers = type_list<R>;
  static constexpr std::size_t count = 1;
  template <class L>
  static constexpr std::array<qubit_index, 1> resolve() {
    return {L::template offset<R> + static_cast<qubit_index>(I)};
  }
};
template <class R, std::size_t F, std::size_t C>
struct selector_traits<slice<R, F, C>> {
  static constexpr bool valid = C >= 1 && F + C <= R::width;
  using registers = type_list<R>;
  static constexpr std::size_t count = C;
  template <class L>
  static constexpr std::array<qubit_index, count> resolve() {
    std::array<qubit_index, count> r{};
    for (std::size_t i = 0; i < count; ++i) r[i] = L::template offset<R> + static_cast<qubit_index>(F + i);
    return r;
  }
};
template <class... S>
struct selector_traits<qubits<S...>> {
  static constexpr bool valid = sizeof...(S) >= 1 && (selector_traits<S>::valid && ...);
  using registers = list_join_t<typename selector_traits<S>::registers...>;
  static constexpr std::size_t count = (std::size_t{0} + ... + selector_traits<S>::count);
  template <class L>
  static constexpr std::array<qubit_index, count> resolve() {
    std::array<qubit_index, count> r{};
    std::size_t i = 0;
    (void)i;
    (
        [&] {
          for (qubit_index q : selector_traits<S>::template resolve<L>()) r[i++] = q;
        }(),
        ...);
    return r;
  }
};
}  // namespace detail

// selector: a register, bit<>, slice<> or qubits<> naming some qubits.
template <class S>
concept selector = detail::selector_traits<S>::valid;

template <selector S>
inline constexpr std::size_t selector_width = detail::selector_traits<S>::count;

// resolve<L, S>(): the qubit indices S names in layout L, least significant first.
template <static_layout L, selector S>
constexpr std::array<qubit_index, selector_width<S>> resolve() {
  return detail::selector_traits<S>::template resolve<L>();
}

// ---- controls -------------------------------------------------------------------------------

namespace detail {
// control_value_too_large<...> for when<S, V>: the value, the number of qubits, S's registers.
template <class S, std::uint64_t V, class Registers = list_unique_t<typename selector_traits<S>::registers>>
struct find_oversized_value;
template <class S, std::uint64_t V, class... R>
struct find_oversized_value<S, V, type_list<R...>> {
  using type = control_value_too_large<control_value<V>, selected_qubits<selector_traits<S>::count>, name_of<R>...>;
};
}  // namespace detail

// when<S, Value>: control on the qubits of S reading Value (bit i of Value for qubit i of S);
// per-qubit values make negative controls: when<bit<r, 0>, 0> fires on |0>.
template <class S, std::uint64_t Value>
struct when {
  static constexpr bool control_must_select_qubits = selector<S>;
  static_assert(control_must_select_qubits,
                "control_must_select_qubits: when<S, V> needs S to be a register, bit<>, slice<> or qubits<>");
  static constexpr bool control_value_must_fit_register =
      Value <= max_value_of_width(detail::selector_traits<S>::count);
  static_assert(detail::require<control_value_must_fit_register, detail::find_oversized_value<S, Value>>::checked,
                "control_value_must_fit_register: when<S, V> needs V < 2^(number of qubits of S)");
};

// on<S>: every qubit of S is |1>.  off<S>: every qubit of S is |0>.
template <selector S>
using on = when<S, max_value_of_width(selector_width<S>)>;
template <selector S>
using off = when<S, 0>;

namespace detail {
// A control is written when<S, V> or as a bare selector (meaning on<S>).
template <class C>
struct control_traits {
  static constexpr bool valid = selector<C>;
  static constexpr bool fits = true;
  using sel = C;
  static constexpr std::uint64_t value = valid ? max_value_of_width(selector_traits<C>::count) : 0;
};
template <class S, std::uint64_t V>
struct control_traits<when<S, V>> {
  static constexpr bool valid = selector<S>;
  static constexpr bool fits = !valid || V <= max_value_of_width(selector_traits<S>::count);
  using sel = S;
  static constexpr std::uint64_t value = V;
};

template <class L, class C>
constexpr std::array<control, selector_traits<typename control_traits<C>::sel>::count> resolve_control() {
  using T = control_traits<C>;
  constexpr auto qs = selector_traits<typename T::sel>::template resolve<L>();
  std::array<control, qs.size()> r{};
  for (std::size_t i = 0; i < qs.size(); ++i) r[i] = control{qs[i], ((T::value >> i) & 1u) != 0};
  return r;
}

template <class L, class... C>
constexpr auto resolve_controls() {
  constexpr std::size_t n = (std::size_t{0} + ... + selector_traits<typename control_traits<C>::sel>::count);
  std::array<control, n> r{};
  std::size_t i = 0;
  (void)i;  // unused when there are no controls
  (
      [&] {
        for (control c : resolve_control<L, C>()) r[i++] = c;
      }(),
      ...);
  return r;
}

// The first control of C... whose value does not fit its qubits (only when<> can be one).
template <class... C>
struct find_oversized_control;
template <class C, class... Rest>
struct find_oversized_control<C, Rest...> {
  using type = typename std::conditional_t<
      control_traits<C>::fits, find_oversized_control<Rest...>,
      find_oversized_value<typename control_traits<C>::sel, control_traits<C>::value>>::type;
};

template <class... C>
using control_registers_t = list_join_t<typename selector_traits<typename control_traits<C>::sel>::registers...>;
}  // namespace detail

// control_spec: a when<> or a selector.
template <class C>
concept control_spec = detail::control_traits<C>::valid && detail::control_traits<C>::fits;

}  // namespace qrm
