// qrm/backends/detail/bits.hpp: bit manipulation for basis-state indices.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

#include "../../circuit/ops.hpp"

namespace qrm::detail {

// Insert a zero bit at position p (bits at p and above move up by one).
constexpr std::uint64_t insert_zero(std::uint64_t k, unsigned p) {
  const std::uint64_t low = k & ((std::uint64_t{1} << p) - 1);
  return ((k >> p) << (p + 1)) | low;
}

// Spread the low bits of v onto the given positions (bit i of v -> bit positions[i]).
template <int = 0>
inline std::uint64_t deposit(std::uint64_t v, std::span<const qubit_index> positions) {
  std::uint64_t r = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) r |= ((v >> i) & 1u) << positions[i];
  return r;
}

// Gather the bits at the given positions into a number (inverse of deposit).
template <int = 0>
inline std::uint64_t gather(std::uint64_t index, std::span<const qubit_index> positions) {
  std::uint64_t r = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) r |= ((index >> positions[i]) & 1u) << i;
  return r;
}

// True when positions are consecutive and increasing (a register in a layout).
template <int = 0>
inline bool contiguous(std::span<const qubit_index> positions) {
  for (std::size_t i = 1; i < positions.size(); ++i)
    if (positions[i] != positions[0] + i) return false;
  return true;
}

// subspace: the indices i < 2^n whose bits at some fixed positions hold fixed values,
// enumerated in increasing order as member 0, 1, ...; members come in contiguous runs of
// 2^(lowest fixed position) indices.
struct subspace {
  unsigned n = 0;
  std::uint64_t fixed_mask = 0, fixed_value = 0;
  std::array<unsigned char, 64> pos{};  // fixed positions, increasing
  unsigned npos = 0;

  subspace(unsigned num_qubits, std::uint64_t mask, std::uint64_t value) : n(num_qubits), fixed_mask(mask), fixed_value(value & mask) {
    for (unsigned b = 0; b < num_qubits; ++b)
      if ((mask >> b) & 1u) pos[npos++] = static_cast<unsigned char>(b);
  }
  std::uint64_t count() const { return std::uint64_t{1} << (n - npos); }
  unsigned run_log2() const { return npos == 0 ? n : pos[0]; }
  template <int = 0>
  std::uint64_t index(std::uint64_t k) const {
    for (unsigned i = 0; i < npos; ++i) k = insert_zero(k, pos[i]);
    return k | fixed_value;
  }
};

// The runs of the members [k0, k1) of a subspace, in order (k0 aligned to a run or to
// chunk_members): first() is a run's first index, length() its length. next() steps to the
// following run by adding to the free bits only (the fixed bits set to 1 so the carry passes
// over them): three operations instead of index()'s loop over every fixed bit, which dominated
// scattered walks (C^12 X with low controls at n = 26 on an Intel Xeon VM: 330 -> 131 us).
// Inlined into the kernels of every instruction set (it holds no vector code).
struct run_cursor {
  std::uint64_t fixed, value, run, free, left;
  [[gnu::always_inline]] run_cursor(const subspace& s, std::uint64_t k0, std::uint64_t k1)
      : fixed(s.fixed_mask), value(s.fixed_value), run(std::uint64_t{1} << s.run_log2()),
        free(s.index(k0) & ~s.fixed_mask), left(k1 - k0) {}
  [[gnu::always_inline]] bool done() const { return left == 0; }
  [[gnu::always_inline]] std::uint64_t first() const { return free | value; }
  [[gnu::always_inline]] std::uint64_t length() const { return run < left ? run : left; }
  [[gnu::always_inline]] void next() {
    const std::uint64_t len = length();
    free = ((free | fixed) + len) & ~fixed;
    left -= len;
  }
};

}  // namespace qrm::detail
