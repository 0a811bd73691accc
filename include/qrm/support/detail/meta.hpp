// qrm/support/detail/meta.hpp: small compile-time helpers (fixed strings, type lists).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace qrm::detail {

// fixed_string<N>: a string literal usable as a template argument (register names).
template <std::size_t N>
struct fixed_string {
  char data[N]{};
  constexpr fixed_string(const char (&s)[N]) { std::copy_n(s, N, data); }
  constexpr std::string_view view() const { return {data, N - 1}; }
  constexpr bool operator==(const fixed_string&) const = default;
};

// type_list<T...>: a pack of types.
template <class... T>
struct type_list {
  static constexpr std::size_t size = sizeof...(T);
};

template <class T, class List>
inline constexpr bool list_contains = false;
template <class T, class... U>
inline constexpr bool list_contains<T, type_list<U...>> = (std::is_same_v<T, U> || ...);

template <class A, class B>
struct list_concat;
template <class... A, class... B>
struct list_concat<type_list<A...>, type_list<B...>> {
  using type = type_list<A..., B...>;
};
template <class... Lists>
struct list_join {
  using type = type_list<>;
};
template <class L, class... Rest>
struct list_join<L, Rest...> {
  using type = typename list_concat<L, typename list_join<Rest...>::type>::type;
};
template <class... Lists>
using list_join_t = typename list_join<Lists...>::type;

// list_unique_t<L>: L without repeated types, first occurrence kept.
template <class Seen, class Rest>
struct list_unique_impl {
  using type = Seen;
};
template <class... Seen, class T, class... Rest>
struct list_unique_impl<type_list<Seen...>, type_list<T, Rest...>> {
  using type = typename list_unique_impl<
      std::conditional_t<(std::is_same_v<T, Seen> || ...), type_list<Seen...>, type_list<Seen..., T>>,
      type_list<Rest...>>::type;
};
template <class L>
using list_unique_t = typename list_unique_impl<type_list<>, L>::type;

// every_in<A, B>: every type of list A is in list B.
template <class A, class B>
inline constexpr bool every_in = false;
template <class... A, class B>
inline constexpr bool every_in<type_list<A...>, B> = (list_contains<A, B> && ...);

// all_distinct(array): no value repeats.
template <class T, std::size_t N>
constexpr bool all_distinct(const std::array<T, N>& a) {
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j)
      if (a[i] == a[j]) return false;
  return true;
}

template <class T, std::size_t N, std::size_t M>
constexpr std::array<T, N + M> concat(const std::array<T, N>& a, const std::array<T, M>& b) {
  std::array<T, N + M> r{};
  for (std::size_t i = 0; i < N; ++i) r[i] = a[i];
  for (std::size_t i = 0; i < M; ++i) r[N + i] = b[i];
  return r;
}

// deferred<T, Tag>: T, spelled as a type that depends on a template parameter of the code that
// names it (see qrm.hpp: clang instantiates what non-dependent code in a template calls).
template <class T, auto>
struct deferred_type {
  using type = T;
};
template <class T, auto Tag>
using deferred = typename deferred_type<T, Tag>::type;
// deferred_by<T, Tag>: the same, tagged by a type parameter.
template <class T, class Tag>
using deferred_by = deferred<T, sizeof(Tag*)>;

// Always-false helper for static_assert in discarded branches.
template <class...>
inline constexpr bool always_false = false;

}  // namespace qrm::detail
