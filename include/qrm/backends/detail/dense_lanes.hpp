// qrm/backends/detail/dense_lanes.hpp: small matrices with a target inside the vector.
//
// dense_batched.hpp puts N neighbouring bases in one register, which needs the lowest log2(N)
// qubits free; a fused 8x8 block with a target there (qubits 0-2 for complex<float> in float
// arithmetic at AVX-512, 0-1 in double arithmetic) gathered its bases four at a time and ran at
// 2-3x the time of the same block higher up (random 24-qubit suite: 13 such blocks, 0.17 s of
// 0.66 s; complex<double> on targets 0, 2, 6 at n = 24: 52 ms against 15-18 ms). Here the register
// holds the amplitudes as they lie in memory, the low targets included: a matrix on targets T
// splits into its high targets H (vector columns, as in dense_batched) and low targets L (lanes).
// Output lane l of vector row h gets, for every vector column c and every subset P of L's bits,
// coefficient(h, c, P)[l] times lane l ^ P of column c: the 2^|L| lane permutations of each
// column are fixed shuffles, and the coefficients are vectors, one value per lane (the matrix
// entry that lane's row and column select). The products per amplitude are those of the dense
// form: a 2^k-entry row for every output. Real amplitudes (double) are lanes of one value each:
// eight per register, qubits 0-2.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <utility>

#include "dense_batched.hpp"

namespace qrm::detail {

// What lane_mix_body needs: columns' offsets and coefficient vectors
// coef_re/coef_im[(row * dim + t) * 2N + lane] for term t = column * patterns + pattern (the
// columns and lane patterns are compile-time constants of the body).
template <class A>
struct lane_mix_job {
  std::array<std::uint64_t, 8> offset{};  // vector column c at base + offset[c]
  bool real = false;                      // coef_im all zero
  const A* coef_re = nullptr;
  const A* coef_im = nullptr;
  void* amplitudes = nullptr;
};

// out = v with amplitude lane l taken from lane l ^ X (each amplitude is C neighbouring values:
// 2 for a complex number, 1 for a real one). Vectors by reference: a vector returned by value
// would be passed in registers its caller's ISA may lack (-Wpsabi).
template <unsigned X, unsigned C, class V, std::size_t... I>
[[gnu::always_inline]] inline void xor_lanes(const V& v, V& out, std::index_sequence<I...>) {
  out = __builtin_shufflevector(v, v, static_cast<int>((((I / C) ^ X) * C) + I % C)...);
}

// Values per amplitude of S: 2 for complex types, 1 for real ones.
template <class S>
inline constexpr unsigned values_per_amplitude = scalar_traits<S>::is_complex ? 2 : 1;

template <class V, std::size_t... I>
[[gnu::always_inline]] inline void swap_real_imaginary(const V& v, V& out, std::index_sequence<I...>) {
  out = __builtin_shufflevector(v, v, static_cast<int>(I ^ 1)...);
}

// The bases that are members [k0, k1) of s (runs of at least N: the low targets are not in s).
// The subsets of `mask`'s bits, in increasing order of the subset's index.
template <unsigned Mask>
constexpr std::array<unsigned, (1u << std::popcount(Mask))> subsets_of() {
  std::array<unsigned, (1u << std::popcount(Mask))> r{};
  for (unsigned q = 0; q < r.size(); ++q)
    for (unsigned i = 0; i < std::popcount(Mask); ++i)
      if ((q >> i) & 1u) r[q] |= 1u << nth_bit(Mask, i);
  return r;
}

// N amplitudes of S in one register of A values (N complex numbers are 2N values).
template <class S, class A, unsigned N>
using amplitude_lanes = typename lanes<A, values_per_amplitude<S> * N / 2>::type;

template <class S, class A, unsigned N, unsigned LowMask, std::size_t... Q>
[[gnu::always_inline]] inline void permute_all(const amplitude_lanes<S, A, N>& w, amplitude_lanes<S, A, N>* x,
                                               std::index_sequence<Q...>) {
  constexpr auto patterns = subsets_of<LowMask>();
  constexpr unsigned C = values_per_amplitude<S>;
  (xor_lanes<patterns[Q], C>(w, x[Q], std::make_index_sequence<C * N>{}), ...);
}

template <class S, class A, unsigned N, unsigned Dim, unsigned LowMask, bool RealMatrix>
[[gnu::always_inline]] inline void lane_mix_body(const lane_mix_job<A>& job, const subspace& s, std::uint64_t k0,
                                                 std::uint64_t k1) {
  using R = typename scalar_traits<S>::real;
  using vec = amplitude_lanes<S, A, N>;
  using stored = amplitude_lanes<S, R, N>;
  constexpr unsigned C = values_per_amplitude<S>;
  static_assert(C == 2 || RealMatrix, "real amplitudes take real matrices only");
  R* p = static_cast<R*>(job.amplitudes);
  constexpr unsigned Patterns = 1u << std::popcount(LowMask), Columns = Dim / Patterns, dim = Dim;
  // The job's fields in locals: stores through p (memcpy) may alias the job, so the compiler
  // reloaded them on every iteration (see csr_range_body).
  std::uint64_t offset[Columns];
  for (unsigned c = 0; c < Columns; ++c) offset[c] = job.offset[c];
  const A* coef_re = job.coef_re;
  const A* coef_im = job.coef_im;
  // Matrices up to 4x4: the coefficient vectors in locals too (at most 16 registers), which the
  // stores cannot alias, instead of four to sixteen loads per iteration.
  constexpr bool local_coefficients = Dim <= 4;
  constexpr std::size_t held = local_coefficients ? std::size_t{Columns} * dim * C * N : 1;
  alignas(64) A re_local[held], im_local[held];
  if constexpr (local_coefficients) {
    std::memcpy(re_local, coef_re, sizeof re_local);
    if constexpr (!RealMatrix) std::memcpy(im_local, coef_im, sizeof im_local);
    coef_re = re_local;
    coef_im = im_local;
  }
  vec x[dim];
  vec sign;
  for (unsigned l = 0; l < C * N; ++l) sign[l] = (l % 2 == 0) ? -1.0 : 1.0;
  for (run_cursor runs(s, k0, k1); !runs.done(); runs.next()) {
    const std::uint64_t first = runs.first(), len = runs.length();
    for (std::uint64_t b = first; b < first + len; b += N) {
      for (unsigned c = 0; c < Columns; ++c) {
        if ((b & (64 / sizeof(S) - 1)) == 0) prefetch_for_write(p, C * (b + offset[c]) + 8192 / sizeof(R));
        stored v;
        std::memcpy(&v, p + C * (b + offset[c]), sizeof v);
        vec w;
        widen<simd_level::avx512>(v, w);
        permute_all<S, A, N, LowMask>(w, x + c * Patterns, std::make_index_sequence<Patterns>{});
      }
      for (unsigned r = 0; r < Columns; ++r) {
        vec acc = {}, acc_im = {};
        const A* cr = coef_re + std::size_t{r} * dim * C * N;
        const A* ci = coef_im + std::size_t{r} * dim * C * N;
        for (unsigned t = 0; t < dim; ++t) {
          vec cre, cim;
          std::memcpy(&cre, cr + t * C * N, sizeof cre);
          acc += cre * x[t];
          if constexpr (!RealMatrix) {
            std::memcpy(&cim, ci + t * C * N, sizeof cim);
            acc_im += cim * x[t];
          }
        }
        if constexpr (!RealMatrix) {
          vec swapped;
          swap_real_imaginary(acc_im, swapped, std::make_index_sequence<C * N>{});
          acc += swapped * sign;  // + i * acc_im
        }
        stored out;
        if constexpr (std::is_same_v<R, A>)
          out = acc;
        else
          out = __builtin_convertvector(acc, stored);
        std::memcpy(p + C * (b + offset[r]), &out, sizeof out);
      }
    }
  }
}

#ifdef QRM_HAS_CPU_DISPATCH
template <class S, class A, unsigned N, unsigned Dim, unsigned LowMask>
__attribute__((target("avx512f"))) void lane_mix_avx512(const lane_mix_job<A>& job, const subspace& s,
                                                        std::uint64_t k0, std::uint64_t k1) {
  if constexpr (!scalar_traits<S>::is_complex)
    lane_mix_body<S, A, N, Dim, LowMask, true>(job, s, k0, k1);
  else if (job.real)
    lane_mix_body<S, A, N, Dim, LowMask, true>(job, s, k0, k1);
  else
    lane_mix_body<S, A, N, Dim, LowMask, false>(job, s, k0, k1);
}

// Applies a Dim x Dim m on `targets` to the bases of `s` (controls and the targets at or above
// log2(N) fixed; no control below log2(N)), N amplitudes in values of type A per 512-bit register,
// the targets below log2(N) as lanes; `chunks(g)` calls g(k0, k1) over s. Compiled for Dim x Dim
// matrices, Dim 8 (fused blocks are 8x8 unless a circuit has fewer qubits to fuse; real double
// states: N 8), 4 (2-qubit blocks: gathered, a 4x4 with a target on qubit 1 took 3.4x its time on
// high targets) or 2 (a 1-qubit gate on qubit 0 or 1 of complex<float> in double arithmetic), with
// fixed trip counts and permutations: with run-time ones the inputs stayed in memory and the form
// lost to the gathered bases.
template <class S, class A, unsigned N, unsigned Dim = 8, class Chunks>
void lane_mix(S* a, const dense_matrix& m, std::span<const qubit_index> targets, const subspace& s, Chunks&& chunks) {
  constexpr unsigned C = values_per_amplitude<S>;
  static_assert(C * N * sizeof(A) == 64 && (Dim == 2 || Dim == 4 || Dim == 8));
  constexpr unsigned lane_bits = std::countr_zero(N);
  std::array<qubit_index, 8> low{}, high{};
  std::array<unsigned, 8> low_at{}, high_at{};  // the matrix index bit of each
  unsigned nl = 0, nh = 0;
  for (unsigned j = 0; j < targets.size(); ++j) {
    if (targets[j] < lane_bits) low[nl] = targets[j], low_at[nl++] = j;
    else high[nh] = targets[j], high_at[nh++] = j;
  }
  for (unsigned i = 1; i < nl; ++i)  // increasing qubits, the order subsets_of enumerates
    for (unsigned j = i; j > 0 && low[j - 1] > low[j]; --j) {
      std::swap(low[j - 1], low[j]);
      std::swap(low_at[j - 1], low_at[j]);
    }
  const unsigned columns = 1u << nh, patterns = 1u << nl;
  std::array<unsigned, 8> lane_xor{};  // pattern q: lane l reads lane l ^ lane_xor[q]
  lane_mix_job<A> job;
  job.amplitudes = a;
  job.real = m.is_real();
  for (unsigned c = 0; c < columns; ++c)
    for (unsigned i = 0; i < nh; ++i)
      if ((c >> i) & 1u) job.offset[c] |= std::uint64_t{1} << high[i];
  for (unsigned q = 0; q < patterns; ++q)
    for (unsigned i = 0; i < nl; ++i)
      if ((q >> i) & 1u) lane_xor[q] |= 1u << low[i];
  auto matrix_index = [&](unsigned column, unsigned lane) {
    std::size_t at = 0;
    for (unsigned i = 0; i < nh; ++i) at |= std::size_t{(column >> i) & 1u} << high_at[i];
    for (unsigned i = 0; i < nl; ++i) at |= std::size_t{(lane >> low[i]) & 1u} << low_at[i];
    return at;
  };
  // Aligned: a coefficient vector split across two cache lines doubled the kernel's time.
  alignas(64) std::array<A, 8 * 8 * C * N> re{}, im{};
  for (unsigned r = 0; r < columns; ++r)
    for (unsigned t = 0; t < Dim; ++t)
      for (unsigned l = 0; l < N; ++l) {
        const unsigned c = t / patterns, q = t % patterns;
        const complex z = m(matrix_index(r, l), matrix_index(c, l ^ lane_xor[q]));
        const std::size_t at = (std::size_t{r} * Dim + t) * C * N + C * l;
        for (unsigned v = 0; v < C; ++v) {
          re[at + v] = static_cast<A>(z.real());
          im[at + v] = static_cast<A>(z.imag());
        }
      }
  job.coef_re = re.data();
  job.coef_im = im.data();
  unsigned low_mask = 0;
  for (unsigned i = 0; i < nl; ++i) low_mask |= 1u << low[i];
  chunks([&](std::uint64_t k0, std::uint64_t k1) {
    switch (low_mask) {
      case 1: return lane_mix_avx512<S, A, N, Dim, 1>(job, s, k0, k1);
      case 2: return lane_mix_avx512<S, A, N, Dim, 2>(job, s, k0, k1);
      default: break;
    }
    if constexpr (Dim >= 4)
      if (low_mask == 3) return lane_mix_avx512<S, A, N, Dim, 3>(job, s, k0, k1);
    if constexpr (N == 8 && Dim >= 4) {
      switch (low_mask) {
        case 4: return lane_mix_avx512<S, A, N, Dim, 4>(job, s, k0, k1);
        case 5: return lane_mix_avx512<S, A, N, Dim, 5>(job, s, k0, k1);
        case 6: return lane_mix_avx512<S, A, N, Dim, 6>(job, s, k0, k1);
        default: break;
      }
    }
    if constexpr (N == 8 && Dim == 8)
      if (low_mask == 7) return lane_mix_avx512<S, A, N, Dim, 7>(job, s, k0, k1);
    throw std::logic_error("lane_mix: no target among the lanes");
  });
}
#endif

}  // namespace qrm::detail
