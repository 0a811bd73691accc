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

// Applies the job at the bases that are members [k0, k1) of s; W amplitudes per vector (W = 2
// needs runs of at least two bases). Everything it calls is inlined, so each ISA's copy below
// is self-contained (a helper lambda would be compiled without the caller's ISA).
template <class S, unsigned W, bool RealMatrix, std::size_t Dim>
[[gnu::always_inline]] inline void csr_range_body(const csr_job<S>& job, const subspace& s, std::uint64_t k0,
                                                  std::uint64_t k1) {
  using R = typename scalar_traits<S>::real;
  static_assert(scalar_traits<S>::is_complex && (W == 1 || W == 2));
  using vec = typename lanes<double, W>::type;
  using stored = typename lanes<R, W>::type;
  const csr_matrix& m = *job.m;
  const std::size_t dim = Dim ? Dim : m.dim;
  const std::uint64_t* off = job.offsets;
  const double* dense_re = job.dense_re;
  const double* dense_im = job.dense_im;
  R* p = reinterpret_cast<R*>(job.a);
  vec x[vector_kernel_max_dim], xs[vector_kernel_max_dim];
  vec sign;
  for (unsigned l = 0; l < 2 * W; ++l) sign[l] = (l % 2 == 0) ? -1.0 : 1.0;

  const std::uint64_t run = s.npos ? (std::uint64_t{1} << s.pos[0]) : s.count();
  const std::uint64_t fixed = s.fixed_mask;
  std::uint64_t free = s.index(k0) & ~fixed;
  for (std::uint64_t k = k0; k < k1;) {
    const std::uint64_t first = free | s.fixed_value;
    const std::uint64_t len = std::min(run, k1 - k);
    for (std::uint64_t b = first; b < first + len; b += W) {
      for (std::size_t c = 0; c < dim; ++c) {
        stored v;
        std::memcpy(&v, p + 2 * (b + off[c]), sizeof v);
        if constexpr (std::is_same_v<R, double>)
          x[c] = v;
        else
          x[c] = __builtin_convertvector(v, vec);
        if constexpr (W == 1)
          xs[c] = __builtin_shufflevector(x[c], x[c], 1, 0) * sign;
        else
          xs[c] = __builtin_shufflevector(x[c], x[c], 1, 0, 3, 2) * sign;
      }
      for (std::size_t r = 0; r < dim; ++r) {
        vec acc = {};
        if constexpr (Dim != 0) {  // dense: fixed trip counts the compiler unrolls
          for (std::size_t c = 0; c < Dim; ++c) {
            acc += dense_re[r * Dim + c] * x[c];
            if constexpr (!RealMatrix) acc += dense_im[r * Dim + c] * xs[c];
          }
        } else {
          for (std::uint32_t e = m.row_start[r]; e < m.row_start[r + 1]; ++e) {
            acc += m.re[e] * x[m.col[e]];
            if constexpr (!RealMatrix) acc += m.im[e] * xs[m.col[e]];
          }
        }
        if constexpr (std::is_same_v<R, double>) {
          std::memcpy(p + 2 * (b + off[r]), &acc, sizeof acc);
        } else {
          const stored out = __builtin_convertvector(acc, stored);
          std::memcpy(p + 2 * (b + off[r]), &out, sizeof out);
        }
      }
    }
    k += len;
    free = ((free | fixed) + len) & ~fixed;
  }
}

template <class S, unsigned W, bool RealMatrix, std::size_t Dim>
void csr_range_generic(const csr_job<S>& job, const subspace& s, std::uint64_t k0, std::uint64_t k1) {
  csr_range_body<S, W, RealMatrix, Dim>(job, s, k0, k1);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
template <class S, unsigned W, bool RealMatrix, std::size_t Dim>
__attribute__((target("avx2,fma"))) void csr_range_avx2(const csr_job<S>& job, const subspace& s, std::uint64_t k0,
                                                        std::uint64_t k1) {
  csr_range_body<S, W, RealMatrix, Dim>(job, s, k0, k1);
}
inline bool cpu_has_avx2_fma() {
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return yes;
}
#endif

template <class S, unsigned W, std::size_t Dim>
void csr_range_dim(const csr_job<S>& job, const subspace& s, std::uint64_t k0, std::uint64_t k1) {
  const bool real = job.m->real;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (cpu_has_avx2_fma()) {
    if (real)
      csr_range_avx2<S, W, true, Dim>(job, s, k0, k1);
    else
      csr_range_avx2<S, W, false, Dim>(job, s, k0, k1);
    return;
  }
#endif
  if (real)
    csr_range_generic<S, W, true, Dim>(job, s, k0, k1);
  else
    csr_range_generic<S, W, false, Dim>(job, s, k0, k1);
}

// Dense matrices of 4, 8 or 16 rows run with unrolled loops; sparse ones (and 32, 64 rows) by rows.
template <class S, unsigned W>
void csr_range_width(const csr_job<S>& job, const subspace& s, std::uint64_t k0, std::uint64_t k1) {
  if (job.dense_re) {
    switch (job.m->dim) {
      case 4: return csr_range_dim<S, W, 4>(job, s, k0, k1);
      case 8: return csr_range_dim<S, W, 8>(job, s, k0, k1);
      case 16: return csr_range_dim<S, W, 16>(job, s, k0, k1);
      default: break;
    }
  }
  csr_range_dim<S, W, 0>(job, s, k0, k1);
}

// The range loop for this CPU and these bases: two bases per vector when they come in pairs.
template <class S>
void csr_range(const csr_job<S>& job, const subspace& s, std::uint64_t k0, std::uint64_t k1) {
  if (s.run_log2() >= 1)
    csr_range_width<S, 2>(job, s, k0, k1);
  else
    csr_range_width<S, 1>(job, s, k0, k1);
}

}  // namespace qrm::detail
