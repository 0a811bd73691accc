// qrm/backends/detail/labels.hpp: basis-state labels for the compact backend.
//
// A label is the basis index |b_{n-1} ... b_1 b_0> as a number (qubit q = bit q). The compact
// backend takes std::uint64_t (up to 64 qubits) or qrm::wide_label<Words> (64 * Words qubits);
// detail::label_traits gives both the same small set of bit operations, so the kernels are
// written once.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>

namespace qrm {

// wide_label<Words>: an unsigned number of 64 * Words bits (word[0] holds qubits 0..63), for
// compact states wider than 64 qubits. Converts implicitly from std::uint64_t.
template <std::size_t Words>
struct wide_label {
  static_assert(Words >= 1, "wide_label_needs_at_least_one_word: wide_label<Words> needs Words >= 1");
  std::array<std::uint64_t, Words> word{};

  constexpr wide_label() = default;
  constexpr wide_label(std::uint64_t low) { word[0] = low; }  // NOLINT: implicit, so small labels read naturally

  // Qubit q of the label.
  constexpr bool test(std::size_t q) const { return ((word[q / 64] >> (q % 64)) & 1u) != 0; }
  constexpr wide_label& set(std::size_t q, bool value = true) {
    const std::uint64_t b = std::uint64_t{1} << (q % 64);
    word[q / 64] = value ? (word[q / 64] | b) : (word[q / 64] & ~b);
    return *this;
  }

  friend constexpr wide_label operator&(wide_label a, const wide_label& b) {
    for (std::size_t i = 0; i < Words; ++i) a.word[i] &= b.word[i];
    return a;
  }
  friend constexpr wide_label operator|(wide_label a, const wide_label& b) {
    for (std::size_t i = 0; i < Words; ++i) a.word[i] |= b.word[i];
    return a;
  }
  friend constexpr wide_label operator^(wide_label a, const wide_label& b) {
    for (std::size_t i = 0; i < Words; ++i) a.word[i] ^= b.word[i];
    return a;
  }
  friend constexpr wide_label operator~(wide_label a) {
    for (std::size_t i = 0; i < Words; ++i) a.word[i] = ~a.word[i];
    return a;
  }
  friend constexpr bool operator==(const wide_label& a, const wide_label& b) = default;
  // Numeric order (most significant word first).
  friend constexpr bool operator<(const wide_label& a, const wide_label& b) {
    for (std::size_t i = Words; i-- > 0;)
      if (a.word[i] != b.word[i]) return a.word[i] < b.word[i];
    return false;
  }
  friend constexpr bool operator>(const wide_label& a, const wide_label& b) { return b < a; }
  friend constexpr bool operator<=(const wide_label& a, const wide_label& b) { return !(b < a); }
  friend constexpr bool operator>=(const wide_label& a, const wide_label& b) { return !(a < b); }
};

namespace detail {

template <class L>
struct label_traits {
  static constexpr bool supported = false;
};

template <>
struct label_traits<std::uint64_t> {
  using L = std::uint64_t;
  static constexpr bool supported = true;
  static constexpr std::size_t bits = 64;
  static constexpr const char* name = "std::uint64_t";
  static constexpr L bit(std::size_t q) { return L{1} << q; }
  // Bits 0 .. p-1.
  static constexpr L low_mask(std::size_t p) { return p >= 64 ? ~L{0} : (L{1} << p) - 1; }
  static constexpr bool test(L x, std::size_t q) { return ((x >> q) & 1u) != 0; }
  static constexpr bool is_zero(L x) { return x == 0; }
  static constexpr bool is_all_ones(L x) { return x == ~L{0}; }
  // Index of the highest set bit (x != 0).
  static constexpr std::size_t highest(L x) { return 63 - static_cast<std::size_t>(std::countl_zero(x)); }
  // Index of the lowest set bit (x != 0).
  static constexpr std::size_t lowest(L x) { return static_cast<std::size_t>(std::countr_zero(x)); }
  static constexpr L increment(L x) { return x + 1; }
  // Bits p .. p+k-1 as a number (k <= 64, p + k <= 64).
  static constexpr std::uint64_t extract(L x, std::size_t p, std::size_t k) {
    x >>= p;
    return k >= 64 ? x : x & ((std::uint64_t{1} << k) - 1);
  }
  // v (< 2^k) placed at bit p.
  static constexpr L place(std::uint64_t v, std::size_t p) { return v << p; }
  // The field at bits [p, p + k) (mask `field`) plus s, modulo 2^k; other bits unchanged.
  static constexpr L add_field(L x, L field, std::size_t p, std::size_t, std::uint64_t s) {
    return (x & ~field) | ((x + (s << p)) & field);
  }
  static constexpr L from_u64(std::uint64_t v) { return v; }
  // The low 64 bits (the whole label).
  static constexpr std::uint64_t low_u64(L x) { return x; }
  static std::string to_string(L x) { return std::to_string(x); }
};

template <std::size_t W>
struct label_traits<wide_label<W>> {
  using L = wide_label<W>;
  static constexpr bool supported = true;
  static constexpr std::size_t bits = 64 * W;
  static constexpr const char* name = "qrm::wide_label";
  static constexpr L bit(std::size_t q) {
    L r;
    r.set(q);
    return r;
  }
  static constexpr L low_mask(std::size_t p) {
    L r;
    for (std::size_t i = 0; i < W; ++i) {
      const std::size_t lo = 64 * i;
      r.word[i] = p >= lo + 64 ? ~std::uint64_t{0} : p <= lo ? 0 : (std::uint64_t{1} << (p - lo)) - 1;
    }
    return r;
  }
  static constexpr bool test(const L& x, std::size_t q) { return x.test(q); }
  static constexpr bool is_zero(const L& x) {
    for (std::uint64_t w : x.word)
      if (w != 0) return false;
    return true;
  }
  static constexpr bool is_all_ones(const L& x) {
    for (std::uint64_t w : x.word)
      if (w != ~std::uint64_t{0}) return false;
    return true;
  }
  static constexpr std::size_t highest(const L& x) {
    for (std::size_t i = W; i-- > 0;)
      if (x.word[i] != 0) return 64 * i + 63 - static_cast<std::size_t>(std::countl_zero(x.word[i]));
    return 0;
  }
  static constexpr std::size_t lowest(const L& x) {
    for (std::size_t i = 0; i < W; ++i)
      if (x.word[i] != 0) return 64 * i + static_cast<std::size_t>(std::countr_zero(x.word[i]));
    return 0;
  }
  static constexpr L increment(L x) {
    for (std::size_t i = 0; i < W; ++i)
      if (++x.word[i] != 0) break;
    return x;
  }
  static constexpr std::uint64_t extract(const L& x, std::size_t p, std::size_t k) {
    const std::size_t w = p / 64, off = p % 64;
    std::uint64_t v = x.word[w] >> off;
    if (off != 0 && w + 1 < W) v |= x.word[w + 1] << (64 - off);
    return k >= 64 ? v : v & ((std::uint64_t{1} << k) - 1);
  }
  static constexpr L place(std::uint64_t v, std::size_t p) {
    L r;
    const std::size_t w = p / 64, off = p % 64;
    r.word[w] = v << off;
    if (off != 0 && w + 1 < W) r.word[w + 1] = v >> (64 - off);
    return r;
  }
  static constexpr L add_field(const L& x, const L& field, std::size_t p, std::size_t k, std::uint64_t s) {
    const std::uint64_t mask = k >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << k) - 1;
    return (x & ~field) | place((extract(x, p, k) + s) & mask, p);
  }
  static constexpr L from_u64(std::uint64_t v) { return L(v); }
  static constexpr std::uint64_t low_u64(const L& x) { return x.word[0]; }
  static std::string to_string(const L& x) {
    static constexpr char hex[] = "0123456789abcdef";
    std::string s;
    for (std::size_t i = W; i-- > 0;)
      for (int d = 15; d >= 0; --d) s += hex[(x.word[i] >> (4 * d)) & 15u];
    const auto first = s.find_first_not_of('0');
    return "0x" + (first == std::string::npos ? std::string("0") : s.substr(first));
  }
};

}  // namespace detail
}  // namespace qrm
