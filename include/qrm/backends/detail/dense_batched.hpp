// qrm/backends/detail/dense_batched.hpp: k-qubit matrices on complex amplitudes, in vector
// registers.
//
// A fused block (circuit/fuse.hpp) is a 2^k x 2^k matrix (k <= 6) on arbitrary targets. Here the
// 2^k amplitudes of one base are loaded as they lie in memory (real and imaginary part side by
// side), each multiplied by the matrix entries of its column with the complex product written
// as two fused multiply-adds (z * m = re(m) z + im(m) (-im z, re z)), and stored back; where the
// bases come in runs of at least two (no target or control on qubit 0), two neighbouring bases
// share each 256-bit vector. Dense matrices of 4, 8 and 16 rows run with every loop unrolled;
// sparse ones (a fused permutation: one product per amplitude) and wider ones by lists of each
// row's non-zero entries.
//
// Arithmetic is in double for both storage types (see dense_kernels.hpp). The code is GNU
// vector extensions (g++ and clang); on x86-64 the same body is also compiled for AVX2 + FMA
// and chosen at run time when the CPU has it, so the build needs no -march flag.
#pragma once

#include <algorithm>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "bits.hpp"
#include "scalar.hpp"

namespace qrm::detail {

// The widest matrix these kernels take (fuse() makes at most 2^6).
inline constexpr std::size_t vector_kernel_max_dim = 64;

// A matrix as rows of non-zero entries (real and imaginary parts apart, in double).
struct csr_matrix {
  std::size_t dim = 0;
  bool real = true;
  std::vector<std::uint32_t> row_start, col;
  std::vector<double> re, im;
};

// One application: the matrix, each row's offset from a base, the amplitudes.
template <class S>
struct csr_job {
  const csr_matrix* m;
  const std::uint64_t* offsets;
  S* a;
  const double* dense_re = nullptr;  // the matrix row-major, when it is applied as dense
  const double* dense_im = nullptr;
};

// W complex numbers of type R as one GNU vector (2W lanes). Spelled out per size: g++ ignores a
// vector_size that depends on a template parameter.
template <class R, unsigned W>
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
struct lanes<float, 1> {
  typedef float type __attribute__((vector_size(8)));
};
template <>
struct lanes<float, 2> {
  typedef float type __attribute__((vector_size(16)));
};

// Applies the job at the bases that are members [k0, k1) of s, two bases per 256-bit vector:
// b and b + step. With Contiguous, step is 1 and s comes in runs of at least two (each pair is
// one load); otherwise s has the step bit fixed to 0 and the pair is two 128-bit loads. A
// complex product is two sums, A = sum re(m) x and B = sum im(m) x, and out = A + i B, where
// i B swaps each (re, im) pair and negates the new real part: one vector per column instead of
// two. Everything it calls is inlined, so each ISA's copy below is self-contained (a helper
// lambda would be compiled without the caller's ISA).
template <class S, bool Contiguous, bool RealMatrix, std::size_t Dim>
[[gnu::always_inline]] inline void csr_range_body(const csr_job<S>& job, const subspace& s, std::uint64_t step,
                                                  std::uint64_t k0, std::uint64_t k1) {
  using R = typename scalar_traits<S>::real;
  static_assert(scalar_traits<S>::is_complex);
  using vec = typename lanes<double, 2>::type;
  using stored = typename lanes<R, 2>::type;
  using stored_half = typename lanes<R, 1>::type;
  const csr_matrix& m = *job.m;
  const std::size_t dim = Dim ? Dim : m.dim;
  const std::uint64_t* off = job.offsets;
  const double* dense_re = job.dense_re;
  const double* dense_im = job.dense_im;
  R* p = reinterpret_cast<R*>(job.a);
  vec x[vector_kernel_max_dim];
  const vec sign = {-1.0, 1.0, -1.0, 1.0};

  const std::uint64_t run = s.npos ? (std::uint64_t{1} << s.pos[0]) : s.count();
  const std::uint64_t fixed = s.fixed_mask;
  std::uint64_t free = s.index(k0) & ~fixed;
  for (std::uint64_t k = k0; k < k1;) {
    const std::uint64_t first = free | s.fixed_value;
    const std::uint64_t len = std::min(run, k1 - k);
    for (std::uint64_t b = first; b < first + len; b += Contiguous ? 2 : 1) {
      for (std::size_t c = 0; c < dim; ++c) {
        stored v;
        if constexpr (Contiguous) {
          std::memcpy(&v, p + 2 * (b + off[c]), sizeof v);
        } else {
          stored_half lo, hi;
          std::memcpy(&lo, p + 2 * (b + off[c]), sizeof lo);
          std::memcpy(&hi, p + 2 * (b + step + off[c]), sizeof hi);
          v = __builtin_shufflevector(lo, hi, 0, 1, 2, 3);
        }
        if constexpr (std::is_same_v<R, double>)
          x[c] = v;
        else
          x[c] = __builtin_convertvector(v, vec);
      }
      for (std::size_t r = 0; r < dim; ++r) {
        vec acc = {}, acc_im = {};
        if constexpr (Dim != 0) {  // dense: fixed trip counts the compiler unrolls
          for (std::size_t c = 0; c < Dim; ++c) {
            acc += dense_re[r * Dim + c] * x[c];
            if constexpr (!RealMatrix) acc_im += dense_im[r * Dim + c] * x[c];
          }
        } else {
          for (std::uint32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e) {
            acc += m.re[e] * x[m.col[e]];
            if constexpr (!RealMatrix) acc_im += m.im[e] * x[m.col[e]];
          }
        }
        if constexpr (!RealMatrix) acc += __builtin_shufflevector(acc_im, acc_im, 1, 0, 3, 2) * sign;
        stored out;
        if constexpr (std::is_same_v<R, double>)
          out = acc;
        else
          out = __builtin_convertvector(acc, stored);
        if constexpr (Contiguous) {
          std::memcpy(p + 2 * (b + off[r]), &out, sizeof out);
        } else {
          const stored_half lo = __builtin_shufflevector(out, out, 0, 1), hi = __builtin_shufflevector(out, out, 2, 3);
          std::memcpy(p + 2 * (b + off[r]), &lo, sizeof lo);
          std::memcpy(p + 2 * (b + step + off[r]), &hi, sizeof hi);
        }
      }
    }
    k += len;
    free = ((free | fixed) + len) & ~fixed;
  }
}

template <class S, bool Contiguous, bool RealMatrix, std::size_t Dim>
void csr_range_generic(const csr_job<S>& job, const subspace& s, std::uint64_t step, std::uint64_t k0,
                       std::uint64_t k1) {
  csr_range_body<S, Contiguous, RealMatrix, Dim>(job, s, step, k0, k1);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
template <class S, bool Contiguous, bool RealMatrix, std::size_t Dim>
__attribute__((target("avx2,fma"))) void csr_range_avx2(const csr_job<S>& job, const subspace& s, std::uint64_t step,
                                                        std::uint64_t k0, std::uint64_t k1) {
  csr_range_body<S, Contiguous, RealMatrix, Dim>(job, s, step, k0, k1);
}
inline bool cpu_has_avx2_fma() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return yes;
}
#endif

template <class S, bool Contiguous, std::size_t Dim>
void csr_range_dim(const csr_job<S>& job, const subspace& s, std::uint64_t step, std::uint64_t k0, std::uint64_t k1) {
  const bool real = job.m->real;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (cpu_has_avx2_fma()) {
    if (real)
      csr_range_avx2<S, Contiguous, true, Dim>(job, s, step, k0, k1);
    else
      csr_range_avx2<S, Contiguous, false, Dim>(job, s, step, k0, k1);
    return;
  }
#endif
  if (real)
    csr_range_generic<S, Contiguous, true, Dim>(job, s, step, k0, k1);
  else
    csr_range_generic<S, Contiguous, false, Dim>(job, s, step, k0, k1);
}

// Dense matrices of 4, 8 or 16 rows run with unrolled loops; sparse ones (and 32, 64 rows) by
// row lists. `s` is the subspace of bases as csr_pairs describes it.
template <class S, bool Contiguous>
void csr_range(const csr_job<S>& job, const subspace& s, std::uint64_t step, std::uint64_t k0, std::uint64_t k1) {
  if (job.dense_re) {
    switch (job.m->dim) {
      case 4: return csr_range_dim<S, Contiguous, 4>(job, s, step, k0, k1);
      case 8: return csr_range_dim<S, Contiguous, 8>(job, s, step, k0, k1);
      case 16: return csr_range_dim<S, Contiguous, 16>(job, s, step, k0, k1);
      default: break;
    }
  }
  csr_range_dim<S, Contiguous, 0>(job, s, step, k0, k1);
}

// How the bases of s pair up: neighbours when s comes in runs of two or more (step 1), else
// b and b + 2^f for the lowest free qubit f, enumerated as the subspace with f also fixed to 0.
// No pair when s has a single base (every qubit a target or control): step 0.
struct csr_pairs {
  subspace bases;
  std::uint64_t step;
  bool contiguous;
};
inline csr_pairs pair_bases(const subspace& s) {
  if (s.run_log2() >= 1) return {s, 1, true};
  for (unsigned f = 0; f < s.n; ++f)
    if (!((s.fixed_mask >> f) & 1u)) {
      const std::uint64_t step = std::uint64_t{1} << f;
      return {subspace(s.n, s.fixed_mask | step, s.fixed_value), step, false};
    }
  return {s, 0, false};
}

}  // namespace qrm::detail
