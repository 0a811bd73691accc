// qrm/backends/detail/dense_batched.hpp: k-qubit matrices on complex amplitudes, in vector
// registers.
//
// A fused block (circuit/fuse.hpp) is a 2^k x 2^k matrix (k <= 6) on arbitrary targets. Here the
// 2^k amplitudes of one base are loaded as they lie in memory (real and imaginary part side by
// side), each multiplied by the matrix entries of its column with the complex product written
// as two fused multiply-adds (z * m = re(m) z + im(m) (-im z, re z)), and stored back; where the
// bases come in runs of at least two (no target or control on qubit 0), two neighbouring bases
// share each 256-bit vector. Dense matrices of 4, 8 and 16 rows run with every loop unrolled;
// sparse ones of 8 to 64 rows (a fused permutation times rotations: 2 to 8 products per
// amplitude) with a fixed count of entries per row, and the rest by lists of each row's
// non-zero entries.
//
// Arithmetic is in double for both storage types (see dense_kernels.hpp), unless a complex<float>
// state asks for float arithmetic (qrm::float_math): then eight (AVX-512) or four (AVX2)
// neighbouring bases share a register of floats, with no conversions. The code is GNU
// vector extensions (g++ and clang); on x86-64 the same body is also compiled for AVX2 + FMA
// and chosen at run time when the CPU has it, so the build needs no -march flag.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "bits.hpp"
#include "dense_api.hpp"
#include "scalar.hpp"

namespace qrm::detail {

// The widest matrix these kernels take (fuse() makes at most 2^6).
inline constexpr std::size_t vector_kernel_max_dim = 64;

// A matrix as rows of non-zero entries (real and imaginary parts apart, in double: arithmetic
// is in double even when amplitudes are stored in float).
struct csr_matrix {
  std::size_t dim = 0;
  bool real = true;
  std::vector<std::uint32_t> row_start, col;
  std::vector<double> re, im;

  // A template only so that it is compiled where used (see circuit/program.hpp).
  template <int = 0>
  static csr_matrix of(const dense_matrix& m) {
    csr_matrix r;
    r.dim = m.dim;
    r.real = m.is_real();
    r.row_start.push_back(0);
    for (std::size_t row = 0; row < m.dim; ++row) {
      for (std::size_t c = 0; c < m.dim; ++c) {
        const complex v = m(row, c);
        if (v == complex{}) continue;
        r.col.push_back(static_cast<std::uint32_t>(c));
        r.re.push_back(v.real());
        r.im.push_back(v.imag());
      }
      r.row_start.push_back(static_cast<std::uint32_t>(r.col.size()));
    }
    return r;
  }
};

// Entries per row of the fixed-width form csr_range_body runs a matrix of 8 to 64 rows in (2, 4,
// or 8 above 8 rows: rows padded with zeros), or 0 when a row has more. Fused blocks of 4 to 6
// qubits are mostly this sparse (the decomposed walk fused at 5: 102 of its 126 blocks of 32
// rows have at most 4 entries per row, 123 at most 8; at 6: 73 of 75 blocks of 64 rows at most 8).
template <int = 0>
inline unsigned ell_width(const csr_matrix& m) {
  if (m.dim != 8 && m.dim != 16 && m.dim != 32 && m.dim != 64) return 0;
  std::uint32_t widest = 0;
  for (std::size_t r = 0; r < m.dim; ++r) widest = std::max(widest, m.row_start[r + 1] - m.row_start[r]);
  return widest <= 2 ? 2 : widest <= 4 ? 4 : widest <= 8 && m.dim > 8 ? 8 : 0;
}

// The set D of offsets d = row ^ column of an 8x8 matrix's non-zeros, when it lies within one of
// the sets compiled for (pairs on one bit: {0, 1}, {0, 2}, {0, 4}; quadruples {0, 1, 4, 5}), else
// 0. Row r then reads only x[r ^ d], indices known at compile time, so the eight inputs stay in
// registers: the fused decomposed walk's blocks are mostly of this kind (208 of its 351 ops are
// pairs, 48 quadruples).
inline constexpr unsigned xor_offset_sets[] = {0x03u, 0x05u, 0x11u, 0x33u};
template <int = 0>
inline unsigned xor_offset_set(const csr_matrix& m) {
  if (m.dim != 8) return 0;
  unsigned used = 0;
  for (std::uint32_t r = 0; r < 8; ++r)
    for (std::uint32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e) used |= 1u << (r ^ m.col[e]);
  for (unsigned set : xor_offset_sets)
    if ((used & ~set) == 0) return set;
  return 0;
}

// The n-th (from 0) set bit of `set`.
constexpr unsigned nth_bit(unsigned set, std::size_t n) {
  for (unsigned b = 0; b < 32; ++b)
    if ((set >> b) & 1u) {
      if (n == 0) return b;
      --n;
    }
  return 0;
}

template <unsigned Set>
constexpr std::array<unsigned, std::popcount(Set)> offsets_of() {
  std::array<unsigned, std::popcount(Set)> d{};
  for (std::size_t e = 0; e < d.size(); ++e) d[e] = nth_bit(Set, e);
  return d;
}

// Rows and columns of an 8x8 matrix put in an order where its non-zeros fall in an offset set:
// possible when the matrix is, up to the order of its rows and of its columns, a direct sum of
// blocks of at most 2 (set {0, 1}) or 4 rows (set {0, 1, 4, 5}), as a fused block of a
// permutation and rotations is (CX then Ry on one of its qubits: rows read columns 2 apart in no
// fixed pattern). Placed row i is original row row[i], placed column j original column col[j];
// each block takes the same positions among the rows as among the columns, so row i reads only
// columns i ^ d. The kernel then loads column j from offset[col[j]] and stores row i to
// offset[row[i]]: a real 8x8 block of 2x2 rotations ran at 0.23 ns per amplitude with its
// columns listed, 0.12 in the offset-set form (2^17 complex<float>, float arithmetic, AMD EPYC VM,
// 2026-12-04).
struct block_order {
  unsigned set = 0;  // 0: no such order
  std::array<std::uint8_t, 8> row{}, col{};
};
template <int = 0>
inline block_order order_blocks(const csr_matrix& m) {
  block_order out;
  if (m.dim != 8) return out;
  // Connected components of the bipartite graph rows - columns (nodes 0-7 rows, 8-15 columns).
  std::array<std::uint8_t, 16> parent;
  for (std::uint8_t i = 0; i < 16; ++i) parent[i] = i;
  const auto root = [&](std::uint8_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::uint32_t r = 0; r < 8; ++r)
    for (std::uint32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e)
      parent[root(static_cast<std::uint8_t>(r))] = root(static_cast<std::uint8_t>(8 + m.col[e]));
  std::array<std::uint8_t, 16> rows_in{}, cols_in{};
  for (std::uint8_t i = 0; i < 8; ++i) {
    ++rows_in[root(i)];
    ++cols_in[root(static_cast<std::uint8_t>(8 + i))];
  }
  unsigned widest = 0;
  for (std::uint8_t c = 0; c < 16; ++c) {
    if (rows_in[c] != cols_in[c]) return out;  // not square: no such order
    widest = std::max<unsigned>(widest, rows_in[c]);
  }
  if (widest > 4) return out;
  // Positions of each group (pairs, or the two quadruples of {0, 1, 4, 5}), filled largest
  // block first so that no block is split.
  static constexpr std::uint8_t pairs[4][4] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}};
  static constexpr std::uint8_t quads[2][4] = {{0, 1, 4, 5}, {2, 3, 6, 7}};
  const unsigned group_size = widest <= 2 ? 2 : 4, groups = 8 / group_size;
  std::array<unsigned, 4> used{};
  std::array<std::uint8_t, 16> order;
  for (std::uint8_t i = 0; i < 16; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::uint8_t x, std::uint8_t y) { return rows_in[x] > rows_in[y]; });
  for (std::uint8_t c : order) {
    if (rows_in[c] == 0) continue;
    unsigned g = 0;
    while (g < groups && used[g] + rows_in[c] > group_size) ++g;
    if (g == groups) return out;
    const std::uint8_t* slots = group_size == 2 ? pairs[g] : quads[g];
    unsigned r_at = used[g], c_at = used[g];
    for (std::uint8_t i = 0; i < 8; ++i) {
      if (root(i) == c) out.row[slots[r_at++]] = i;
      if (root(static_cast<std::uint8_t>(8 + i)) == c) out.col[slots[c_at++]] = i;
    }
    used[g] += rows_in[c];
  }
  out.set = group_size == 2 ? 0x03u : 0x33u;
  return out;
}

// How an 8x8 matrix runs in the fixed-width form, decided once per gate: entries per row (0: not
// that form), the offset set (0: columns listed), and the row and column order that puts it in a
// smaller set than its own order does (`reordered`; see block_order). Reordering keeps each row's
// number of non-zeros, so the width holds in either order.
struct fixed_width_form {
  unsigned width = 0, set = 0;
  bool reordered = false;
  std::array<std::uint8_t, 8> row{}, col{};
};
template <int = 0>
inline fixed_width_form choose_fixed_width_form(const csr_matrix& m) {
  fixed_width_form f;
  f.width = ell_width(m);
  if (f.width == 0) return f;
  f.set = xor_offset_set(m);
  if (f.set != 0 && std::popcount(f.set) <= 2) return f;  // already pairs: nothing smaller
  const block_order order = order_blocks(m);
  if (order.set && (f.set == 0 || std::popcount(order.set) < std::popcount(f.set))) {
    f.set = order.set;
    f.reordered = true;
    f.row = order.row;
    f.col = order.col;
  }
  return f;
}

// One application: the matrix, each row's offset from a base (where row r is stored, and
// where column r is loaded from: the same unless block_order reordered them), the amplitudes.
template <class S>
struct csr_job {
  const csr_matrix* m;
  const std::uint64_t* offsets;
  S* a;
  const std::uint64_t* load_offsets = nullptr;  // nullptr: `offsets`
  const double* dense_re = nullptr;  // the matrix row-major, when it is applied as dense
  const double* dense_im = nullptr;
  // The same numbers rounded to float, for float arithmetic: the dense matrix (when dense_re is
  // set) and the row lists' entries.
  const float* dense_re_f = nullptr;
  const float* dense_im_f = nullptr;
  const float* rows_re_f = nullptr;
  const float* rows_im_f = nullptr;
  // Rows of exactly ell_k entries (padded with zeros), when every row has at most that many
  // non-zeros (see ell_width): fixed trip counts without the dense form's zero products.
  unsigned ell_k = 0;
  // Or, with ell_xor set (see xor_offset_set), entry e of row r is the one at column r ^ d_e, d_e
  // the e-th offset of the set (ell_col unused).
  unsigned ell_xor = 0;
  const std::uint8_t* ell_col = nullptr;
  const double* ell_re = nullptr;
  const double* ell_im = nullptr;
  const float* ell_re_f = nullptr;
  const float* ell_im_f = nullptr;
  simd_level level = simd_level::generic;  // resolved (never automatic)
  bool streams = false;                    // the state exceeds streaming_state_bytes (see csr_range_body)
};

// A state larger than this streams from memory on every pass: a typical last-level cache
// (32 MiB; chunked runs and the 21-qubit walk in complex<float> stay below it).
inline constexpr std::uint64_t streaming_state_bytes = std::uint64_t{32} << 20;

// N complex numbers of type R as one GNU vector (2N lanes). Spelled out per size: g++ ignores a
// vector_size that depends on a template parameter.
template <class R, unsigned N>
struct lanes;
template <>
struct lanes<double, 1> {
  typedef double type __attribute__((vector_size(16)));
};
template <>
struct lanes<double, 2> {
  typedef double type __attribute__((vector_size(32)));
};
template <>
struct lanes<double, 4> {
  typedef double type __attribute__((vector_size(64)));
};
template <>
struct lanes<float, 1> {
  typedef float type __attribute__((vector_size(8)));
};
template <>
struct lanes<float, 2> {
  typedef float type __attribute__((vector_size(16)));
};
template <>
struct lanes<float, 4> {
  typedef float type __attribute__((vector_size(32)));
};
template <>
struct lanes<float, 8> {
  typedef float type __attribute__((vector_size(64)));
};

// How N bases share a vector: b + g[j] for j < N. With `contiguous` they are neighbours (the
// subspace comes in runs of at least N: one load); otherwise g = {0, 2^f1} or
// {0, 2^f1, 2^f2, 2^f1 + 2^f2} for the lowest free qubits f1 < f2, and `bases` is the subspace
// with those fixed to 0 (one 128-bit load per base). ok is false when too few qubits are free.
struct base_groups {
  subspace bases;
  std::uint64_t g[4] = {0, 1, 2, 3};
  bool contiguous = true;
  bool ok = true;
};
template <int = 0>
inline base_groups group_bases(const subspace& s, unsigned per_vector) {
  const unsigned need = per_vector == 4 ? 2 : 1;
  if (s.run_log2() >= need) return {s, {0, 1, 2, 3}, true, true};
  std::uint64_t bits[2] = {0, 0}, mask = s.fixed_mask;
  unsigned found = 0;
  for (unsigned f = 0; f < s.n && found < need; ++f)
    if (!((s.fixed_mask >> f) & 1u)) {
      bits[found++] = std::uint64_t{1} << f;
      mask |= std::uint64_t{1} << f;
    }
  if (found < need) return {s, {0, 0, 0, 0}, false, false};
  return {subspace(s.n, mask, s.fixed_value), {0, bits[0], bits[1], bits[0] | bits[1]}, false, true};
}

// Hint that a[i] will be written soon. The address is formed as an integer because it may lie
// past the end of the vector near the last block (a prefetch never faults; pointer arithmetic
// out of bounds would be undefined).
template <class S>
[[gnu::always_inline]] inline void prefetch_for_write(const S* a, std::uint64_t i) {
  __builtin_prefetch(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(a) + i * sizeof(S)), 1);
}

// How many bytes ahead a kernel prefetches that walks a run and its partner run as two streams
// (a 2x2 matrix's two columns, an X swap's two halves): 8 KiB of addresses, or the same place in
// the next block where the runs are 8 to 128 KiB long. There, 8 KiB on is the other stream (or,
// near a run's end, a skipped gap), so the first 8 KiB of every run went unfetched: a
// complex<float> 2x2 gate at n = 25 took 20-29 ms on targets 10-11 against 11-13 ms on target
// 24; a block ahead, 14-19 ms (AMD EPYC VM, 2026-12-05, bench/RESULTS.md). Chosen once per call:
// an address computed per line or per run cost the in-cache gate on target 2 (runs of 4) 20-40%.
[[gnu::always_inline]] inline std::uint64_t paired_prefetch_bytes(std::uint64_t run_bytes) {
  return run_bytes >= 8192 && run_bytes <= 128 * 1024 ? 2 * run_bytes : 8192;
}

// Two lines whose addresses differ by a multiple of 2^28 bytes share their set and their
// linear-address hash (bits 12-27) in the L1 data cache of AMD Zen cores, which holds only one
// line per hash and set: a kernel that alternates between them misses L1 on every access. A
// complex<float> 2x2 gate on target 25 of 26 qubits (partners 256 MiB apart) ran at 10 GB/s
// against 31-47 GB/s on targets 0-24; a plain loop over two float streams 256 or 512 MiB apart
// the same, 192, 320 or 384 MiB apart 37-41 GB/s. Loading 4 or more vectors of one stream before
// the other's: 29-35 GB/s (AMD EPYC VM, AVX2, 2026-12-06).
inline constexpr std::uint64_t aliasing_stride_bytes = std::uint64_t{1} << 28;

// x86-64 under g++ or clang: kernels compiled per ISA (target attributes), chosen at run time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define QRM_HAS_CPU_DISPATCH 1
#endif

// Defining QRM_NO_AVX512 (CMake: -DQRM_AVX512=OFF) leaves the AVX-512 kernels out and runs AVX2 at
// most, for machines without AVX-512: test_fuse.cpp compiled in 85 s instead of 113 s (clang 14 with
// sanitizers, bench/RESULTS.md).
#if defined(QRM_HAS_CPU_DISPATCH) && !defined(QRM_NO_AVX512)
inline constexpr bool avx512_kernels = true;
#else
inline constexpr bool avx512_kernels = false;
#endif

// The matrix kernels' specialised forms (fixed sizes and offset sets, grouped columns, register
// lanes) are each a function per matrix shape, ISA and scalar: an unoptimised build (-O0, where
// __OPTIMIZE__ is undefined) compiles only the general forms they specialise, which compute the
// same sums (over the same non-zero entries; the specialised forms add exact zeros, and sum an
// offset set's entries in another order: results may differ by rounding). The README tour's
// circuit at -O0 with g++ 12: 4.7 s -> 3.0 s (bench/RESULTS.md). QRM_ALL_KERNELS keeps every form
// at -O0; QRM_FEWER_KERNELS drops them at any level (the test of this path). A program that links
// optimised and unoptimised units runs one of the two forms; both are correct.
#if defined(QRM_FEWER_KERNELS) || (!defined(__OPTIMIZE__) && !defined(QRM_ALL_KERNELS))
inline constexpr bool specialized_kernels = false;
#else
inline constexpr bool specialized_kernels = true;
#endif

#ifdef QRM_HAS_CPU_DISPATCH
// Eight floats to eight doubles in one instruction, where g++ 12 lowers __builtin_convertvector
// at this width to two 4-wide conversions, an extract and an insert. A target function, not an
// always_inline one (that could not be inlined into the ISA-neutral bodies below); the AVX-512
// copies, the only callers, inline it.
template <class Vec, class Stored>
__attribute__((target("avx512f"))) inline void widen_eight_floats(const Stored& v, Vec& out) {
  out = __builtin_ia32_cvtps2pd512_mask(v, Vec{}, -1, 4);  // every lane, the current rounding mode
}

// Four floats to four doubles in one instruction, where g++ 12 lowers __builtin_convertvector at
// this width to two 2-wide conversions and an insert (narrowing compiles to one instruction); the
// AVX2 copies inline it. The fused 2-qubit blocks of the random suite (24 qubits, complex<float>,
// double arithmetic) took 1.35-1.39 s with the split form, 1.14-1.25 s with this (bench/RESULTS.md).
template <class Vec, class Stored>
__attribute__((target("avx2,fma"))) inline void widen_four_floats(const Stored& v, Vec& out) {
#ifdef __clang__
  out = __builtin_convertvector(v, Vec);  // clang already emits one instruction
#else
  out = __builtin_ia32_cvtps2pd256(v);
#endif
}
#endif

// The amplitudes loaded as stored (R) in the arithmetic type (A) of the kernels below, in a
// kernel compiled for `Isa` (the 4-float form needs to know it is inside an AVX2 copy).
template <simd_level Isa, class Vec, class Stored>
[[gnu::always_inline]] inline void widen(const Stored& v, Vec& out) {
  if constexpr (std::is_same_v<Vec, Stored>)
    out = v;
#ifdef QRM_HAS_CPU_DISPATCH
  else if constexpr (sizeof(Vec) == 64 && sizeof(Stored) == 32)
    widen_eight_floats(v, out);
  else if constexpr (Isa == simd_level::avx2 && sizeof(Vec) == 32 && sizeof(Stored) == 16)
    widen_four_floats(v, out);
#endif
  else
    out = __builtin_convertvector(v, Vec);
}

// acc += i acc_im for N complex numbers as (re, im) lanes: i z swaps each pair and negates the
// new real part (sign: -1, 1, -1, 1, ...).
template <unsigned N, class Vec>
[[gnu::always_inline]] inline void add_i_times(Vec& acc, const Vec& acc_im, const Vec& sign) {
  if constexpr (N == 2)
    acc += __builtin_shufflevector(acc_im, acc_im, 1, 0, 3, 2) * sign;
  else if constexpr (N == 4)
    acc += __builtin_shufflevector(acc_im, acc_im, 1, 0, 3, 2, 5, 4, 7, 6) * sign;
  else
    acc += __builtin_shufflevector(acc_im, acc_im, 1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14) * sign;
}

// Applies the job at the bases that are members [k0, k1) of s, N bases per vector (see
// base_groups), in the instructions of Isa, in arithmetic type A (double, or float for
// complex<float>). A complex product is two sums, A = sum re(m) x and B = sum im(m) x, and
// out = A + i B, where i B swaps each (re, im) pair and negates the new real part: one vector
// per column instead of two. Everything it calls is inlined, so each ISA's copy below is
// self-contained (a helper lambda would be compiled without the caller's ISA).
template <simd_level Isa, class S, class A, unsigned N, bool Contiguous, bool RealMatrix, std::size_t Dim, unsigned K = 0,
          unsigned XorSet = 0, unsigned G = 1>
[[gnu::always_inline]] inline void csr_range_body(const csr_job<S>& job, const subspace& s, const std::uint64_t* g,
                                                  std::uint64_t k0, std::uint64_t k1) {
  using R = typename scalar_traits<S>::real;
  static_assert(scalar_traits<S>::is_complex && (N == 2 || N == 4 || N == 8));
  static_assert(std::is_same_v<A, double> || (std::is_same_v<A, R> && (Contiguous || N <= 4)));
  using vec = typename lanes<A, N>::type;
  using stored = typename lanes<R, N>::type;
  using one = typename lanes<R, 1>::type;
  const csr_matrix& m = *job.m;
  const std::size_t dim = Dim ? Dim : m.dim;
  const std::uint64_t* off = job.offsets;
  const std::uint64_t* load_off = job.load_offsets ? job.load_offsets : job.offsets;
  const A* dense_re;
  const A* dense_im;
  const A* rows_re;
  const A* rows_im;
  const A* ell_re;
  const A* ell_im;
  if constexpr (std::is_same_v<A, double>) {
    dense_re = job.dense_re, dense_im = job.dense_im, rows_re = m.re.data(), rows_im = m.im.data();
    ell_re = job.ell_re, ell_im = job.ell_im;
  } else {
    dense_re = job.dense_re_f, dense_im = job.dense_im_f, rows_re = job.rows_re_f, rows_im = job.rows_im_f;
    ell_re = job.ell_re_f, ell_im = job.ell_im_f;
  }
  const std::uint8_t* ell_col = job.ell_col;
  R* p = reinterpret_cast<R*>(job.a);
  // The offsets in locals where their count is fixed, and the coefficients of dense matrices up to
  // 4x4: stores through p (memcpy) may alias the job's arrays, so the compiler reloaded every offset
  // and broadcast every coefficient on every iteration (a 1-qubit gate on target 13, n = 26,
  // complex<float> in double arithmetic: 45-49 -> 40 ms).
  std::uint64_t store_local[Dim ? Dim : 1], load_local[Dim ? Dim : 1];
  constexpr bool dense_small = Dim != 0 && Dim <= 4 && K == 0 && XorSet == 0;
  constexpr std::size_t local_coefficients = dense_small ? Dim * Dim : 1;
  A dense_re_local[local_coefficients], dense_im_local[local_coefficients];
  if constexpr (Dim != 0) {
    for (std::size_t i = 0; i < Dim; ++i) store_local[i] = off[i], load_local[i] = load_off[i];
    off = store_local;
    load_off = load_local;
  }
  if constexpr (dense_small) {
    for (std::size_t i = 0; i < Dim * Dim; ++i) dense_re_local[i] = dense_re[i], dense_im_local[i] = dense_im[i];
    dense_re = dense_re_local;
    dense_im = dense_im_local;
  }
  vec x[vector_kernel_max_dim];
  vec sign;
  for (unsigned l = 0; l < 2 * N; ++l) sign[l] = (l % 2 == 0) ? -1.0 : 1.0;

  // How far ahead each column is prefetched, in R values (see below): a 2x2 matrix's columns are
  // paired streams (paired_prefetch_bytes); wider matrices keep 8 KiB.
  const std::uint64_t paired = dim <= 2 && s.npos != 0 ? paired_prefetch_bytes(sizeof(S) << s.run_log2()) : 8192;
  const std::uint64_t ahead = paired / sizeof(R);
  for (run_cursor runs(s, k0, k1); !runs.done(); runs.next()) {
    const std::uint64_t first = runs.first(), len = runs.length();
    if constexpr (G > 1) {
      // G vectors of each column loaded before any other column's, each row's G stored together
      // (see aliased_streams): runs of G N neighbours, a dense matrix.
      static_assert(Contiguous && Dim != 0 && K == 0 && XorSet == 0 && Dim * G <= vector_kernel_max_dim);
      for (std::uint64_t b = first; b < first + len; b += N * G) {
        for (std::size_t c = 0; c < Dim; ++c) {
          for (unsigned u = 0; u < G; ++u) {
            stored v;
            std::memcpy(&v, p + 2 * (b + u * N + load_off[c]), sizeof v);
            widen<Isa>(v, x[c * G + u]);
          }
        }
        for (std::size_t r = 0; r < Dim; ++r) {
          stored out[G];
          for (unsigned u = 0; u < G; ++u) {
            vec acc = {}, acc_im = {};
            for (std::size_t c = 0; c < Dim; ++c) {
              acc += dense_re[r * Dim + c] * x[c * G + u];
              if constexpr (!RealMatrix) acc_im += dense_im[r * Dim + c] * x[c * G + u];
            }
            if constexpr (!RealMatrix) add_i_times<N>(acc, acc_im, sign);
            if constexpr (std::is_same_v<R, A>)
              out[u] = acc;
            else
              out[u] = __builtin_convertvector(acc, stored);
          }
          for (unsigned u = 0; u < G; ++u) std::memcpy(p + 2 * (b + u * N + off[r]), &out[u], sizeof out[u]);
        }
      }
      continue;
    }
    for (std::uint64_t b = first; b < first + len; b += Contiguous ? N : 1) {
      // Each column is its own stream, and streams 2^t apart that jump every 2^t amplitudes
      // defeat the hardware prefetcher (see for_each_pair): fetch each one's line ahead
      // (an 8x8 real matrix on targets 4, 8, 9, n = 24: 7.0 -> 5.1 ms). The offset-set and
      // fixed-width forms in float arithmetic have too few products to hide it where the state
      // sits in a cache (the fused 21-qubit walk: 0.155 -> 0.170 s with it at width 3; 0.096-0.099
      // -> 0.100-0.126 s at width 6), but need it where it streams from memory (offsets
      // {0, 1, 4, 5} on targets 4, 8, 9, n = 24: 13 ms without, 5.5 ms with).
      if constexpr (Contiguous)
        if (((XorSet == 0 && K == 0) || std::is_same_v<A, double> || job.streams) && (b & (64 / sizeof(S) - 1)) == 0)
          for (std::size_t c = 0; c < dim; ++c)
            prefetch_for_write(p, 2 * (b + load_off[c]) + ahead);
      for (std::size_t c = 0; c < dim; ++c) {
        stored v;
        if constexpr (Contiguous) {
          std::memcpy(&v, p + 2 * (b + load_off[c]), sizeof v);
        } else {
          one l[N];
          for (unsigned j = 0; j < N; ++j) std::memcpy(&l[j], p + 2 * (b + g[j] + load_off[c]), sizeof l[j]);
          if constexpr (N == 2) {
            v = __builtin_shufflevector(l[0], l[1], 0, 1, 2, 3);
          } else if constexpr (N == 4) {
            const auto lo = __builtin_shufflevector(l[0], l[1], 0, 1, 2, 3);
            const auto hi = __builtin_shufflevector(l[2], l[3], 0, 1, 2, 3);
            v = __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
          }
        }
        widen<Isa>(v, x[c]);
      }
      for (std::size_t r = 0; r < dim; ++r) {
        vec acc = {}, acc_im = {};
        if constexpr (XorSet != 0) {  // row r's entries at columns r ^ d, d in XorSet: all indices fixed
          constexpr unsigned width = std::popcount(XorSet);
          constexpr auto d = offsets_of<XorSet>();
          for (unsigned e = 0; e < width; ++e) {
            acc += ell_re[r * width + e] * x[r ^ d[e]];
            if constexpr (!RealMatrix) acc_im += ell_im[r * width + e] * x[r ^ d[e]];
          }
        } else if constexpr (K != 0) {  // fixed-width rows
          for (unsigned e = 0; e < K; ++e) {
            const std::size_t at = r * K + e;
            acc += ell_re[at] * x[ell_col[at]];
            if constexpr (!RealMatrix) acc_im += ell_im[at] * x[ell_col[at]];
          }
        } else if constexpr (Dim != 0) {  // dense: fixed trip counts the compiler unrolls
          for (std::size_t c = 0; c < Dim; ++c) {
            acc += dense_re[r * Dim + c] * x[c];
            if constexpr (!RealMatrix) acc_im += dense_im[r * Dim + c] * x[c];
          }
        } else {
          for (std::uint32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e) {
            acc += rows_re[e] * x[m.col[e]];
            if constexpr (!RealMatrix) acc_im += rows_im[e] * x[m.col[e]];
          }
        }
        if constexpr (!RealMatrix) add_i_times<N>(acc, acc_im, sign);
        stored out;
        if constexpr (std::is_same_v<R, A>)
          out = acc;
        else
          out = __builtin_convertvector(acc, stored);
        if constexpr (Contiguous) {
          std::memcpy(p + 2 * (b + off[r]), &out, sizeof out);
        } else {
          one l[N];
          if constexpr (N == 2) {
            l[0] = __builtin_shufflevector(out, out, 0, 1);
            l[1] = __builtin_shufflevector(out, out, 2, 3);
          } else if constexpr (N == 4) {
            l[0] = __builtin_shufflevector(out, out, 0, 1);
            l[1] = __builtin_shufflevector(out, out, 2, 3);
            l[2] = __builtin_shufflevector(out, out, 4, 5);
            l[3] = __builtin_shufflevector(out, out, 6, 7);
          }
          for (unsigned j = 0; j < N; ++j) std::memcpy(p + 2 * (b + g[j] + off[r]), &l[j], sizeof l[j]);
        }
      }
    }
  }
}

template <class S, class A, unsigned N, bool Contiguous, bool RealMatrix, std::size_t Dim, unsigned K, unsigned XorSet,
          unsigned G = 1>
void csr_range_generic(const csr_job<S>& job, const subspace& s, const std::uint64_t* g, std::uint64_t k0,
                       std::uint64_t k1) {
  csr_range_body<simd_level::generic, S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
}

#ifdef QRM_HAS_CPU_DISPATCH
template <class S, class A, unsigned N, bool Contiguous, bool RealMatrix, std::size_t Dim, unsigned K, unsigned XorSet,
          unsigned G = 1>
__attribute__((target("avx2,fma"))) void csr_range_avx2(const csr_job<S>& job, const subspace& s,
                                                        const std::uint64_t* g, std::uint64_t k0, std::uint64_t k1) {
  csr_range_body<simd_level::avx2, S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
}
template <class S, class A, unsigned N, bool Contiguous, bool RealMatrix, std::size_t Dim, unsigned K, unsigned XorSet,
          unsigned G = 1>
__attribute__((target("avx512f"))) void csr_range_avx512(const csr_job<S>& job, const subspace& s,
                                                         const std::uint64_t* g, std::uint64_t k0, std::uint64_t k1) {
  csr_range_body<simd_level::avx512, S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
}
template <int = 0>
inline bool cpu_has_avx2_fma() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return yes;
}
template <int = 0>
inline bool cpu_has_avx512f() {
  static const bool yes = __builtin_cpu_supports("avx512f");
  return yes;
}
#endif

// The level the kernels run at: the one asked for, or the best below it this CPU has.
template <int = 0>
inline simd_level resolve_simd(simd_level asked) {
#ifdef QRM_HAS_CPU_DISPATCH
  if (avx512_kernels && (asked == simd_level::automatic || asked == simd_level::avx512) && cpu_has_avx512f())
    return simd_level::avx512;
  if (asked != simd_level::generic && cpu_has_avx2_fma()) return simd_level::avx2;
#else
  (void)asked;
#endif
  return simd_level::generic;
}

// Registers of 512 bits (four bases in double, eight in float) run only at avx512, float
// arithmetic only at avx2 and above (resolve_simd and the caller see to it).
template <class S, class A, unsigned N, bool Contiguous, bool RealMatrix, std::size_t Dim, unsigned K, unsigned XorSet,
          unsigned G = 1>
void csr_range_isa(const csr_job<S>& job, const subspace& s, const std::uint64_t* g, std::uint64_t k0,
                   std::uint64_t k1) {
  constexpr bool wide = N * sizeof(A) * 2 == 64;
#ifdef QRM_HAS_CPU_DISPATCH
  if constexpr (wide) {
    if constexpr (avx512_kernels) csr_range_avx512<S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
    return;
  } else if (job.level == simd_level::avx2 || !std::is_same_v<A, double>) {
    csr_range_avx2<S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
    return;
  }
#endif
  if constexpr (N == 2 && std::is_same_v<A, double>) csr_range_generic<S, A, N, Contiguous, RealMatrix, Dim, K, XorSet, G>(job, s, g, k0, k1);
}

// The fixed-width forms (K, XorSet) are compiled for complex matrices only: a real one runs the
// same code with zero imaginary parts: half the copies (a real form measured 13-18% faster on the
// random suite's real 3-qubit blocks in cache; from memory the difference was within the noise).
template <class S, class A, unsigned N, bool Contiguous, std::size_t Dim, unsigned K = 0, unsigned XorSet = 0, unsigned G = 1>
void csr_range_dim(const csr_job<S>& job, const subspace& s, const std::uint64_t* g, std::uint64_t k0,
                   std::uint64_t k1) {
  if constexpr (K == 0 && XorSet == 0)
    if (job.m->real) return csr_range_isa<S, A, N, Contiguous, true, Dim, 0, 0, G>(job, s, g, k0, k1);
  csr_range_isa<S, A, N, Contiguous, false, Dim, K, XorSet, G>(job, s, g, k0, k1);
}

// Sparse matrices of 8 to 64 rows run at a fixed count of entries per row (see ell_width), dense
// ones of 4, 8 or 16 rows with unrolled loops (these forms only where specialized_kernels), the rest by
// row lists. `s` and `g` are a base_groups' bases and offsets.
template <class S, unsigned N, bool Contiguous, class A = double>
void csr_range(const csr_job<S>& job, const subspace& s, const std::uint64_t* g, std::uint64_t k0, std::uint64_t k1) {
  if constexpr (specialized_kernels) {
    if constexpr (Contiguous) {  // the fixed-width forms only where bases are neighbours (see csr_range_dim)
      switch (job.ell_xor) {
        case 0x03: return csr_range_dim<S, A, N, Contiguous, 8, 0, 0x03>(job, s, g, k0, k1);
        case 0x05: return csr_range_dim<S, A, N, Contiguous, 8, 0, 0x05>(job, s, g, k0, k1);
        case 0x11: return csr_range_dim<S, A, N, Contiguous, 8, 0, 0x11>(job, s, g, k0, k1);
        case 0x33: return csr_range_dim<S, A, N, Contiguous, 8, 0, 0x33>(job, s, g, k0, k1);
        default: break;
      }
      switch (job.m->dim * 16 + job.ell_k) {
        case 8 * 16 + 2: return csr_range_dim<S, A, N, Contiguous, 8, 2>(job, s, g, k0, k1);
        case 8 * 16 + 4: return csr_range_dim<S, A, N, Contiguous, 8, 4>(job, s, g, k0, k1);
        case 16 * 16 + 2: return csr_range_dim<S, A, N, Contiguous, 16, 2>(job, s, g, k0, k1);
        case 16 * 16 + 4: return csr_range_dim<S, A, N, Contiguous, 16, 4>(job, s, g, k0, k1);
        case 16 * 16 + 8: return csr_range_dim<S, A, N, Contiguous, 16, 8>(job, s, g, k0, k1);
        case 32 * 16 + 2: return csr_range_dim<S, A, N, Contiguous, 32, 2>(job, s, g, k0, k1);
        case 32 * 16 + 4: return csr_range_dim<S, A, N, Contiguous, 32, 4>(job, s, g, k0, k1);
        case 32 * 16 + 8: return csr_range_dim<S, A, N, Contiguous, 32, 8>(job, s, g, k0, k1);
        case 64 * 16 + 2: return csr_range_dim<S, A, N, Contiguous, 64, 2>(job, s, g, k0, k1);
        case 64 * 16 + 4: return csr_range_dim<S, A, N, Contiguous, 64, 4>(job, s, g, k0, k1);
        case 64 * 16 + 8: return csr_range_dim<S, A, N, Contiguous, 64, 8>(job, s, g, k0, k1);
        default: break;
      }
    }
    if (job.dense_re) {
      switch (job.m->dim) {
        case 2: return csr_range_dim<S, A, N, Contiguous, 2>(job, s, g, k0, k1);
        case 4: return csr_range_dim<S, A, N, Contiguous, 4>(job, s, g, k0, k1);
        case 8: return csr_range_dim<S, A, N, Contiguous, 8>(job, s, g, k0, k1);
        case 16: return csr_range_dim<S, A, N, Contiguous, 16>(job, s, g, k0, k1);
        default: break;
      }
    }
  }
  csr_range_dim<S, A, N, Contiguous, 0>(job, s, g, k0, k1);
}

}  // namespace qrm::detail
