// qrm/backends/detail/dense_kernels.hpp: in-place kernels on a dense array of 2^n amplitudes.
//
// Every kernel visits only the subspace where its controls hold (cost ~ 2^(n - controls)),
// computes in double whatever the storage type (a float-rounded unitary is not unitary, and
// reusing it 10^5 times drifts the norm by ~1e-3; double arithmetic keeps float states within
// the unbiased rounding of storage; the matrix kernels offer float arithmetic on request, see
// qrm::float_math),
// works in place (permutations included), multiplies complex numbers by hand on (re, im) pairs
// (std::complex's operator* carries NaN-recovery branches), and hands chunks of a fixed size to
// the thread pool, so results never depend on the number of threads.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include "../../circuit/ops.hpp"
#include "bits.hpp"
#include "dense_api.hpp"
#include "dense_batched.hpp"
#include "dense_lanes.hpp"
#include "dense_pairs.hpp"
#include "dense_swap.hpp"
#include "scalar.hpp"
#include "../../support/detail/thread_pool.hpp"

namespace qrm::detail {

// Two doubles as one SSE2 register (GNU vector extension, supported by g++ >= 12 and clang).
typedef double v2d __attribute__((vector_size(16)));

// Members per chunk: fixed, so chunk boundaries (and per-chunk partial sums) do not depend on
// the thread count.
inline constexpr std::uint64_t chunk_members = std::uint64_t{1} << 13;

// Calls f(first_index, length) for contiguous runs covering the members [k0, k1) of s
// (k0 aligned to chunk_members, or 0).
template <class F>
inline void runs_in_range(const subspace& s, std::uint64_t k0, std::uint64_t k1, F& f) {
  for (run_cursor r(s, k0, k1); !r.done(); r.next()) f(r.first(), r.length());
}

// Calls g(k0, k1) for ranges of members covering all of s, in parallel chunks when worth it;
// `work` is the number of amplitudes touched per member.
template <class G>
void for_each_chunk(const subspace& s, const exec_policy& ex, std::uint64_t work, G&& g) {
  const std::uint64_t count = s.count();
  if (ex.threads <= 1 || count <= chunk_members || count * work < ex.min_parallel) {
    g(std::uint64_t{0}, count);
    return;
  }
  const std::uint64_t chunks = count / chunk_members;
  shared_pool().parallel_for(static_cast<std::size_t>(chunks), ex.threads,
                             [&](std::size_t i) { g(i * chunk_members, (i + 1) * chunk_members); });
}

// Calls f(first_index, length) for contiguous runs covering all of s (for_each_chunk's chunks).
template <class F>
void for_each_run(const subspace& s, const exec_policy& ex, std::uint64_t work, F&& f) {
  for_each_chunk(s, ex, work, [&](std::uint64_t k0, std::uint64_t k1) { runs_in_range(s, k0, k1, f); });
}

// Calls body(i) for every index i where the controls hold and the target bit is 0 (its partner
// is i + 2^t). When the target lies below every control, the controls' runs are split into
// blocks of 2^(t+1) and walked with plain nested loops, which the compiler turns into straight
// (vectorisable) code even for target 0, instead of one call per pair.
template <class S, class Body>
void for_each_pair(const S* a, unsigned n, unsigned t, std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex,
                   std::uint64_t work, Body&& body) {
  const std::uint64_t st = std::uint64_t{1} << t;
  const subspace sc(n, cmask, cvalue);
  const std::uint64_t run_c = sc.npos ? (std::uint64_t{1} << sc.pos[0]) : sc.count();
  // Each run works on a local copy of `body`: the copy's captures cannot alias the amplitudes,
  // so they stay in registers instead of being reloaded after every store.
  // Chunks of the controls' subspace start at multiples of chunk_members, so blocks of 2^(t+1)
  // never straddle two chunks as long as 2^(t+1) <= chunk_members.
  if (run_c >= 2 * st && 2 * st <= chunk_members) {
    constexpr std::uint64_t line = std::max<std::uint64_t>(1, 64 / sizeof(S));
    if (st == 1) {  // pairs of neighbours: one flat loop the compiler vectorises
      for_each_run(sc, ex, work / 2, [&](std::uint64_t i0, std::uint64_t len) {
        auto local = body;
        for (std::uint64_t j = i0; j < i0 + len; j += 2) local(j);
      });
    } else if (st < 4 * line) {
      for_each_run(sc, ex, work / 2, [&](std::uint64_t i0, std::uint64_t len) {
        auto local = body;
        for (std::uint64_t b = i0; b < i0 + len; b += 2 * st)
          for (std::uint64_t j = b; j < b + st; ++j) local(j);
      });
    } else {
      // Two streams st apart that jump every st elements defeat the hardware prefetcher on
      // this kind of machine (a 2^24-amplitude Ry ran at 19-24 GB/s for st = 64..1024 against
      // 50-60 GB/s for other targets); prefetching both streams of the next block, 8 KiB
      // further on, restores it.
      constexpr std::uint64_t ahead = 8192 / sizeof(S);
      for_each_run(sc, ex, work / 2, [&](std::uint64_t i0, std::uint64_t len) {
        auto local = body;
        for (std::uint64_t b = i0; b < i0 + len; b += 2 * st)
          for (std::uint64_t j0 = b; j0 < b + st; j0 += line) {
            prefetch_for_write(a, j0 + 2 * st + ahead);
            prefetch_for_write(a, j0 + 3 * st + ahead);
            for (std::uint64_t j = j0; j < j0 + line; ++j) local(j);
          }
      });
    }
  } else {
    const subspace s(n, cmask | st, cvalue);
    for_each_run(s, ex, work, [&](std::uint64_t i0, std::uint64_t len) {
      auto local = body;
      for (std::uint64_t j = i0; j < i0 + len; ++j) local(j);
    });
  }
}

template <class G>
double reduce_runs(const subspace& s, const exec_policy& ex, G&& g) {
  const std::uint64_t count = s.count();
  const std::uint64_t chunks = count <= chunk_members ? 1 : count / chunk_members;
  const std::uint64_t per = count / chunks;
  std::vector<double> partial(static_cast<std::size_t>(chunks), 0.0);
  auto body = [&](std::size_t i) {
    double acc = 0;
    auto f = [&](std::uint64_t first, std::uint64_t len) { acc += g(first, len); };
    runs_in_range(s, i * per, (i + 1) * per, f);
    partial[i] = acc;
  };
  if (ex.threads <= 1 || chunks == 1 || count < ex.min_parallel) {
    for (std::size_t i = 0; i < chunks; ++i) body(i);
  } else {
    shared_pool().parallel_for(static_cast<std::size_t>(chunks), ex.threads, body);
  }
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

// Eight partial sums: one accumulator made every add wait on the last (4 cycles each), and the
// compiler may not reorder a floating-point sum itself.
template <class S>
double norm_of_run(const S* a, std::uint64_t first, std::uint64_t len) {
  using R = typename scalar_traits<S>::real;
  const R* p = reinterpret_cast<const R*>(a + first);
  const std::uint64_t count = scalar_traits<S>::is_complex ? 2 * len : len;
  double acc[8] = {};
  std::uint64_t j = 0;
  for (; j + 8 <= count; j += 8)
    for (unsigned k = 0; k < 8; ++k) acc[k] += static_cast<double>(p[j + k]) * static_cast<double>(p[j + k]);
  for (; j < count; ++j) acc[0] += static_cast<double>(p[j]) * static_cast<double>(p[j]);
  return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
}

// ---- single-qubit gates ------------------------------------------------------------------

// Exchanges *x and *y as 64-bit words (32-bit for float): std::swap of a complex moved each
// part as a floating-point value, one element per load, and ran a C^k X on complex<float> at
// 1.9x the time of real double over the same bytes.
template <class S>
[[gnu::always_inline]] inline void swap_as_words(S* x, S* y) {
  typedef std::uint64_t two_words __attribute__((vector_size(16)));
  using word = std::conditional_t<sizeof(S) == 16, two_words, std::conditional_t<sizeof(S) == 8, std::uint64_t, std::uint32_t>>;
  static_assert(sizeof(S) == sizeof(word));
  word u, v;
  std::memcpy(&u, static_cast<void*>(x), sizeof(S));
  std::memcpy(&v, static_cast<void*>(y), sizeof(S));
  std::memcpy(static_cast<void*>(x), &v, sizeof(S));
  std::memcpy(static_cast<void*>(y), &u, sizeof(S));
}

template <class S>
void kernel_gate1(S* a, unsigned n, const gate1& g, unsigned t, std::uint64_t cmask, std::uint64_t cvalue,
                  const exec_policy& ex) {
  using R = typename scalar_traits<S>::real;
  const std::uint64_t st = std::uint64_t{1} << t;
  const bool is_x = g.m[0][0] == complex{} && g.m[1][1] == complex{} && g.m[0][1] == complex{1.0} &&
                    g.m[1][0] == complex{1.0};
  if (is_x) {
    const std::uint64_t block_bytes = st * sizeof(S);
    const subspace sc(n, cmask, cvalue);
    const std::uint64_t run_c = sc.npos ? (std::uint64_t{1} << sc.pos[0]) : sc.count();
    const simd_level level = resolve_simd(ex.simd);
    // Target below every control, blocks narrower than for_each_pair's prefetched case, and runs
    // of whole vectors (chunks of chunk_members amplitudes never split a block pair).
    if (run_c >= 2 * st && 2 * st <= chunk_members && block_bytes < 256 &&
        std::min(run_c, chunk_members) * sizeof(S) >= swap_vector_bytes(level)) {
      for_each_run(sc, ex, 1, [=](std::uint64_t i0, std::uint64_t len) {
        swap_adjacent_blocks(a + i0, len * sizeof(S), block_bytes, level);
      });
      return;
    }
    // Otherwise pairs of runs st apart, whole vectors at a time, with the controls on the qubits
    // inside a cache line as a lane mask (so no line is read that the element loop would skip).
    constexpr std::uint64_t masked_control_bytes = 64;
    const unsigned mask_bits = std::min(t, static_cast<unsigned>(std::countr_zero(masked_control_bytes / sizeof(S))));
    const std::uint64_t low = cmask & ((std::uint64_t{1} << mask_bits) - 1);
    const subspace s(n, (cmask & ~low) | st, cvalue & ~low);
    const std::uint64_t run = std::uint64_t{1} << s.run_log2();
    if (run * sizeof(S) >= swap_vector_bytes(level)) {
      std::array<std::uint32_t, masked_control_bytes / 4> pattern{};
      const std::uint64_t pattern_elements = masked_control_bytes / sizeof(S);
      for (std::uint64_t e = 0; e < pattern_elements; ++e)
        for (std::uint64_t w = 0; w < sizeof(S) / 4; ++w)
          pattern[e * sizeof(S) / 4 + w] = (e & low) == (cvalue & low) ? ~std::uint32_t{0} : 0;
      for_each_chunk(s, ex, 2, [&](std::uint64_t k0, std::uint64_t k1) {
        swap_runs_masked({reinterpret_cast<char*>(a), run_cursor(s, k0, k1), sizeof(S), st * sizeof(S), pattern.data(),
                          pattern.size(), (sizeof(S) << n) > streaming_state_bytes},
                         level);
      });
      return;
    }
    for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) { swap_as_words(a + i, a + i + st); });
    return;
  }
  if (g.is_diagonal()) {
    const complex d0 = g.m[0][0], d1 = g.m[1][1];
    if constexpr (scalar_traits<S>::is_complex) {
      R* p = reinterpret_cast<R*>(a);
      const double d0r = d0.real(), d0i = d0.imag(), d1r = d1.real(), d1i = d1.imag();
      auto scale = [p](std::uint64_t j, double cr, double ci) {
        const double xr = p[2 * j], xi = p[2 * j + 1];
        p[2 * j] = static_cast<R>(cr * xr - ci * xi);
        p[2 * j + 1] = static_cast<R>(cr * xi + ci * xr);
      };
      if (d0 == complex{1.0})  // controlled-Z, phase: only the |1> half moves
        for_each_pair(a, n, t, cmask, cvalue, ex, 1, [=](std::uint64_t i) { scale(i + st, d1r, d1i); });
      else
        for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
          scale(i, d0r, d0i);
          scale(i + st, d1r, d1i);
        });
    } else {
      const double d0r = d0.real(), d1r = d1.real();
      if (d0 == complex{1.0})
        for_each_pair(a, n, t, cmask, cvalue, ex, 1, [=](std::uint64_t i) { a[i + st] = static_cast<S>(d1r * a[i + st]); });
      else
        for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
          a[i] = static_cast<S>(d0r * a[i]);
          a[i + st] = static_cast<S>(d1r * a[i + st]);
        });
    }
    return;
  }
  if constexpr (std::is_same_v<S, std::complex<float>>) {
#ifdef QRM_HAS_CPU_DISPATCH
    // Targets 0..1 (AVX2) or 0..2 (AVX-512) in float arithmetic, where the controls leave runs
    // of whole vectors (no control below qubit 2 or 3): see dense_pairs.hpp.
    if (ex.math == float_math::single_precision) {
      const simd_level level = resolve_simd(ex.simd);
      const subspace sc(n, cmask, cvalue);
      const std::uint64_t run_c = sc.npos ? (std::uint64_t{1} << sc.pos[0]) : sc.count();
      const std::uint64_t per_vector = level == simd_level::avx512 ? 8 : 4;  // amplitudes
      if (level != simd_level::generic && 2 * st <= per_vector && std::min(run_c, chunk_members) >= per_vector) {
        const pair_coefficients c = pair_coefficients::of(g, t);
        float* p = reinterpret_cast<float*>(a);
        for_each_run(sc, ex, 2, [&](std::uint64_t i0, std::uint64_t len) {
          if constexpr (avx512_kernels)
            if (level == simd_level::avx512) return low_target_pairs_avx512(p + 2 * i0, len, t, c);
          low_target_pairs_avx2(p + 2 * i0, len, t, c);
        });
        return;
      }
    } else if (const subspace sc(n, cmask, cvalue);
               resolve_simd(ex.simd) == simd_level::avx2 && t < 2 &&
               std::min(sc.npos ? (std::uint64_t{1} << sc.pos[0]) : sc.count(), chunk_members) >= 4) {
      // Double arithmetic at AVX2, target 0 or 1, runs of 4 amplitudes or more: see dense_pairs.hpp.
      const widened_pair_coefficients c = widened_pair_coefficients::of(g);
      float* p = reinterpret_cast<float*>(a);
      for_each_run(sc, ex, 2, [&](std::uint64_t i0, std::uint64_t len) { low_target_pairs_widened_avx2(p + 2 * i0, len, t, c); });
      return;
    }
#endif
  }
#ifdef QRM_HAS_CPU_DISPATCH
  if constexpr (scalar_traits<S>::is_complex && avx512_kernels && specialized_kernels) {
    // Double arithmetic at AVX-512, target 0 or 1: four amplitudes per register, the target a
    // lane (dense_lanes.hpp), where the pair loop below takes one amplitude at a time
    // (complex<float>: each scalar widened on its own; complex<double>: 0.78-0.81 ns per
    // amplitude in a cache-sized state, the lanes 0.20-0.26, as the matrix kernel from target 4).
    if (!float_arithmetic<S>(ex) && resolve_simd(ex.simd) == simd_level::avx512 && t < 2 && (cmask & 3) == 0 &&
        n >= 2) {
      const dense_matrix m = dense_matrix::of(g);
      const qubit_index target[] = {static_cast<qubit_index>(t)};
      const subspace bases(n, cmask, cvalue);
      const auto chunks = [&](auto&& f) { for_each_chunk(bases, ex, 2, f); };
      return lane_mix<S, double, 4, 2>(a, m, target, bases, chunks);
    }
  }
#endif
  // Where the matrix kernel's vectors beat the scalar pair loop below. complex<float>: above
  // target 0, 1.5-3x (floats widened to double, two or four bases per register; 2^22
  // amplitudes, one thread); at target 0 (generic level) the loop is already one vectorised
  // stream. complex<double> with AVX2 or AVX-512: from target 1 (at AVX-512, targets 0 and 1
  // take the lanes above unless a control lies there; at AVX2 target 0 stays in the loop): in a
  // cache-sized state (2^16, as in a chunked run) 0.23-0.29 ns per amplitude at AVX-512 and 0.37
  // at AVX2 on targets 2-3 against the loop's 0.72-0.75, under a control on qubit 0 or 1
  // 0.26-0.41 against 0.54-0.84, from memory level or better (AMD EPYC VM, 2026-12-07). At the
  // generic level (128-bit vectors, one complex<double> each) from target 4, where the loop takes
  // its prefetching form. Small states keep the loop: the matrix kernel's setup would dominate.
  const unsigned matrix_kernel_from = std::is_same_v<S, std::complex<float>> ? 1
                                      : std::is_same_v<S, std::complex<double>>
                                          ? (resolve_simd(ex.simd) != simd_level::generic ? 1 : 4)
                                          : 64;
  if (t >= matrix_kernel_from && n - static_cast<unsigned>(std::popcount(cmask)) >= 12) {
    const dense_matrix m = dense_matrix::of(g);
    const qubit_index target[] = {static_cast<qubit_index>(t)};
    kernel_unitary(a, n, m, target, st, cmask, cvalue, ex);
    return;
  }
  if (g.is_real()) {
    const double m00 = g.m[0][0].real(), m01 = g.m[0][1].real();
    const double m10 = g.m[1][0].real(), m11 = g.m[1][1].real();
    if constexpr (scalar_traits<S>::is_complex) {
      R* p = reinterpret_cast<R*>(a);
      for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
        R* lo = p + 2 * i;
        R* hi = p + 2 * (i + st);
        const double xr = lo[0], xi = lo[1], yr = hi[0], yi = hi[1];
        lo[0] = static_cast<R>(m00 * xr + m01 * yr);
        lo[1] = static_cast<R>(m00 * xi + m01 * yi);
        hi[0] = static_cast<R>(m10 * xr + m11 * yr);
        hi[1] = static_cast<R>(m10 * xi + m11 * yi);
      });
    } else {
      for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
        const double x = a[i], y = a[i + st];
        a[i] = static_cast<S>(m00 * x + m01 * y);
        a[i + st] = static_cast<S>(m10 * x + m11 * y);
      });
    }
    return;
  }
  if constexpr (std::is_same_v<S, std::complex<double>>) {
    // One complex<double> is one 2-lane vector (re, im): z * w = w.re * (zr, zi) + w.im * (-zi, zr).
    using v2 = v2d;
    double* p = reinterpret_cast<double*>(a);
    auto re_part = [](complex w) { return v2{w.real(), w.real()}; };
    auto im_part = [](complex w) { return v2{-w.imag(), w.imag()}; };
    const v2 ar = re_part(g.m[0][0]), ai = im_part(g.m[0][0]), br = re_part(g.m[0][1]), bi = im_part(g.m[0][1]);
    const v2 cr = re_part(g.m[1][0]), ci = im_part(g.m[1][0]), dr = re_part(g.m[1][1]), di = im_part(g.m[1][1]);
    for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
      v2 x, y;
      std::memcpy(&x, p + 2 * i, sizeof x);
      std::memcpy(&y, p + 2 * (i + st), sizeof y);
      const v2 xs = __builtin_shufflevector(x, x, 1, 0), ys = __builtin_shufflevector(y, y, 1, 0);
      const v2 lo = ar * x + ai * xs + br * y + bi * ys;
      const v2 hi = cr * x + ci * xs + dr * y + di * ys;
      std::memcpy(p + 2 * i, &lo, sizeof lo);
      std::memcpy(p + 2 * (i + st), &hi, sizeof hi);
    });
  } else if constexpr (scalar_traits<S>::is_complex) {
    R* p = reinterpret_cast<R*>(a);
    const double ar = g.m[0][0].real(), ai = g.m[0][0].imag(), br = g.m[0][1].real(), bi = g.m[0][1].imag();
    const double cr = g.m[1][0].real(), ci = g.m[1][0].imag(), dr = g.m[1][1].real(), di = g.m[1][1].imag();
    for_each_pair(a, n, t, cmask, cvalue, ex, 2, [=](std::uint64_t i) {
      R* lo = p + 2 * i;
      R* hi = p + 2 * (i + st);
      const double xr = lo[0], xi = lo[1], yr = hi[0], yi = hi[1];
      lo[0] = static_cast<R>(ar * xr - ai * xi + br * yr - bi * yi);
      lo[1] = static_cast<R>(ar * xi + ai * xr + br * yi + bi * yr);
      hi[0] = static_cast<R>(cr * xr - ci * xi + dr * yr - di * yi);
      hi[1] = static_cast<R>(cr * xi + ci * xr + dr * yi + di * yr);
    });
  }
}

// ---- dense k-qubit matrices -------------------------------------------------------------------

// A matrix stored by rows of non-zero entries, in the backend's precision.
template <class S>
struct sparse_rows : csr_matrix {
  using R = typename scalar_traits<S>::real;

  explicit sparse_rows(const dense_matrix& m) : csr_matrix(csr_matrix::of(m)) {}

  // out = M * in, for `in` gathered from the state.
  void multiply(const S* in, S* out) const {
    for (std::size_t r = 0; r < dim; ++r) {
      if constexpr (scalar_traits<S>::is_complex) {
        double accr = 0, acci = 0;
        for (std::uint32_t e = row_start[r]; e < row_start[r + 1]; ++e) {
          const double xr = in[col[e]].real(), xi = in[col[e]].imag();
          accr += re[e] * xr - im[e] * xi;
          acci += re[e] * xi + im[e] * xr;
        }
        out[r] = S(static_cast<R>(accr), static_cast<R>(acci));
      } else {
        double acc = 0;
        for (std::uint32_t e = row_start[r]; e < row_start[r + 1]; ++e) acc += re[e] * in[col[e]];
        out[r] = static_cast<S>(acc);
      }
    }
  }
};

// Applies `m` at every base index (all targets 0) of the runs handed to it.
template <class S>
struct unitary_applier {
  const sparse_rows<S>& m;
  const std::vector<std::uint64_t>& offsets;
  S* a;
  void operator()(std::uint64_t i0, std::uint64_t len) const {
    constexpr std::size_t stack_dim = 64;
    std::array<S, stack_dim> in_s, out_s;
    S* in = in_s.data();
    S* out = out_s.data();
    if (m.dim > stack_dim) {
      thread_local std::vector<S> heap;  // reused: runs can be one base long
      if (heap.size() < 2 * m.dim) heap.resize(2 * m.dim);
      in = heap.data();
      out = heap.data() + m.dim;
    }
    for (std::uint64_t b = i0; b < i0 + len; ++b) {
      for (std::size_t r = 0; r < m.dim; ++r) in[r] = a[b + offsets[r]];
      m.multiply(in, out);
      for (std::size_t r = 0; r < m.dim; ++r) a[b + offsets[r]] = out[r];
    }
  }
};

template <int = 0>
inline std::vector<std::uint64_t> target_offsets(std::span<const qubit_index> targets) {
  std::vector<std::uint64_t> off(std::size_t{1} << targets.size());
  for (std::size_t r = 0; r < off.size(); ++r) off[r] = deposit(r, targets);
  return off;
}

// Products and sums in float: complex<float> amplitudes and the caller asked for it.
template <class S>
constexpr bool float_arithmetic(const exec_policy& ex) {
  return std::is_same_v<S, std::complex<float>> && ex.math == float_math::single_precision;
}

// A dense 2x2 or 4x4 matrix with partners aliasing_stride_bytes apart or more is applied 16 bases
// of one column at a time (apply_grouped): an L1 miss per 128-256 bytes of each stream instead of
// per vector. Needs runs of 16 bases (the controls and targets above qubit 3).
template <class S>
bool aliased_streams(std::size_t dim, std::uint64_t tmask, std::uint64_t cmask) {
  const unsigned from = static_cast<unsigned>(std::countr_zero(aliasing_stride_bytes / sizeof(S)));
  return (tmask >> from) != 0 && dim <= 4 && std::countr_zero(tmask | cmask) >= 4;
}

// What kernel_unitary derives from a matrix, its targets and its controls' mask before it touches
// the state (row lists, the fixed-width form and its tables, in double and in float; none of
// these when the op takes the lane path, which builds its own coefficients). A chunked run
// (dense_blocked.hpp) applies an op to every chunk with the same local targets and controls, so
// it builds the plan once per run instead of once per chunk.
template <class S>
struct unitary_plan {
  const dense_matrix* m = nullptr;
  std::vector<qubit_index> targets;
  std::vector<std::uint64_t> offsets;
  bool vector_kernel = false;  // complex, at most vector_kernel_max_dim rows: the tables below are set
  bool lane_path = false;      // applied by lane_mix (no tables)
  simd_level level = simd_level::generic;
  csr_matrix rows;  // of `m`, or of its reordering (form.reordered)
  fixed_width_form form;
  std::array<std::uint64_t, 8> store_at{}, load_from{};
  std::vector<double> dense_re, dense_im;  // row-major, when applied as dense
  std::vector<float> dense_re_f, dense_im_f, rows_re_f, rows_im_f;
  std::vector<std::uint8_t> ell_col;
  std::vector<double> ell_re, ell_im;
  std::vector<float> ell_re_f, ell_im_f;
  // Real amplitudes (S = double) and neither targets nor controls on qubit 0: the plan of the
  // same matrix on the state read as complex numbers (see apply_unitary_plan).
  std::unique_ptr<unitary_plan<std::complex<double>>> on_pairs;
  bool grouped = false;  // see aliased_streams

  unitary_plan(const dense_matrix& mat, std::span<const qubit_index> ts, [[maybe_unused]] std::uint64_t cmask,
               const exec_policy& ex)
      : m(&mat), targets(ts.begin(), ts.end()), offsets(target_offsets(ts)) {
    [[maybe_unused]] std::uint64_t tmask = 0;  // real float states use neither form below
    for (const qubit_index t : ts) tmask |= std::uint64_t{1} << t;
    if constexpr (std::is_same_v<S, double>) {
      if (mat.dim <= vector_kernel_max_dim && ((tmask | cmask) & 1) == 0) {
        std::vector<qubit_index> above(ts.size());
        for (std::size_t i = 0; i < ts.size(); ++i) above[i] = ts[i] - 1;
        on_pairs = std::make_unique<unitary_plan<std::complex<double>>>(mat, above, cmask >> 1, ex);
      }
#ifdef QRM_HAS_CPU_DISPATCH
      // Else a real 8x8 matrix may take the lanes of eight doubles.
      lane_path = specialized_kernels && !on_pairs && mat.is_real() && takes_lanes(mat, tmask, cmask, 7, resolve_simd(ex.simd));
#endif
    }
    if constexpr (scalar_traits<S>::is_complex) {
      if (mat.dim > vector_kernel_max_dim) return;
      vector_kernel = true;
      level = resolve_simd(ex.simd);
#ifdef QRM_HAS_CPU_DISPATCH
      // Qubits 0-2 are lanes in float arithmetic, 0-1 in double: otherwise bases gathered four at a time.
      lane_path = specialized_kernels && takes_lanes(mat, tmask, cmask, float_arithmetic<S>(ex) ? 7 : 3, level);
      if (lane_path) return;
#endif
      rows = csr_matrix::of(mat);
      // The matrix in the order applied: reordered when that puts it in a smaller offset set
      // (see block_order); rows are then stored to store_at, columns loaded from load_from.
      form = choose_fixed_width_form(rows);
      const dense_matrix* applied = &mat;
      dense_matrix reordered;
      if (form.reordered) {
        reordered = dense_matrix(8);
        for (std::size_t i = 0; i < 8; ++i) {
          for (std::size_t j = 0; j < 8; ++j) reordered(i, j) = mat(form.row[i], form.col[j]);
          store_at[i] = offsets[form.row[i]];
          load_from[i] = offsets[form.col[i]];
        }
        rows = csr_matrix::of(reordered);
        applied = &reordered;
      }
      // Dense enough (a quarter of the entries non-zero): every entry, unrolled, beats the
      // row lists' indirection.
      if (rows.col.size() * 4 >= mat.dim * mat.dim && mat.dim <= 16) {
        for (const complex& z : applied->data) {
          dense_re.push_back(z.real());
          dense_im.push_back(z.imag());
        }
      }
      if (const unsigned k = form.width) {
        // Row r's entries: at columns r ^ d (d from the offset set, fixed at compile time), or
        // at listed columns padded to k.
        const unsigned set = form.set;
        const auto w = set ? static_cast<unsigned>(std::popcount(set)) : k;
        const std::size_t size = mat.dim * w;
        ell_col.assign(size, 0);
        ell_re.assign(size, 0), ell_im.assign(size, 0);
        ell_re_f.assign(size, 0), ell_im_f.assign(size, 0);
        for (std::size_t r = 0; r < mat.dim; ++r)
          for (unsigned e = 0; e < w; ++e) {
            const std::uint32_t at_row = rows.row_start[r] + e;
            const bool listed = at_row < rows.row_start[r + 1];
            const std::size_t c = set ? r ^ nth_bit(set, e) : listed ? rows.col[at_row] : 0;
            const complex z = set || listed ? (*applied)(r, c) : complex{};
            const std::size_t at = r * w + e;
            ell_col[at] = static_cast<std::uint8_t>(c);
            ell_re[at] = z.real(), ell_im[at] = z.imag();
            ell_re_f[at] = static_cast<float>(z.real()), ell_im_f[at] = static_cast<float>(z.imag());
          }
      }
      grouped = specialized_kernels && !dense_re.empty() && aliased_streams<S>(mat.dim, tmask, cmask);
      if (float_arithmetic<S>(ex)) {
        dense_re_f.assign(dense_re.begin(), dense_re.end());
        dense_im_f.assign(dense_im.begin(), dense_im.end());
        rows_re_f.assign(rows.re.begin(), rows.re.end());
        rows_im_f.assign(rows.im.begin(), rows.im.end());
      }
    }
  }
  // At AVX-512, a 4x4 or 8x8 matrix with a target among the amplitudes one register holds (the
  // qubits of `lanes`) and no control there: those targets are lanes (dense_lanes.hpp).
  static bool takes_lanes(const dense_matrix& mat, std::uint64_t tmask, std::uint64_t cmask, std::uint64_t lanes,
                          simd_level level) {
    return level == simd_level::avx512 && (mat.dim == 4 || mat.dim == 8) && (tmask & lanes) != 0 &&
           (cmask & lanes) == 0;
  }
  // A job points into the plan: valid while the plan is neither moved nor destroyed.
  csr_job<S> job(S* a, unsigned n) const {
    csr_job<S> j{&rows, form.reordered ? store_at.data() : offsets.data(), a};
    if (form.reordered) j.load_offsets = load_from.data();
    j.level = level;
    j.streams = (std::uint64_t{sizeof(S)} << n) > streaming_state_bytes;
    if (!dense_re.empty()) j.dense_re = dense_re.data(), j.dense_im = dense_im.data();
    if (form.width) {
      j.ell_k = form.width;
      j.ell_xor = form.set;
      j.ell_col = ell_col.data();
      j.ell_re = ell_re.data(), j.ell_im = ell_im.data();
      j.ell_re_f = ell_re_f.data(), j.ell_im_f = ell_im_f.data();
    }
    j.dense_re_f = dense_re_f.data(), j.dense_im_f = dense_im_f.data();
    j.rows_re_f = rows_re_f.data(), j.rows_im_f = rows_im_f.data();
    return j;
  }
};

// Applies a dense 2x2 or 4x4 job at the members of s, 16 bases of each column at a time.
template <class S, std::size_t Dim>
void apply_grouped(const csr_job<S>& job, const subspace& s, const exec_policy& ex) {
  static constexpr std::uint64_t neighbours[4] = {0, 1, 2, 3};
  const bool wide = avx512_kernels && job.level == simd_level::avx512;
  for_each_chunk(s, ex, Dim, [&](std::uint64_t k0, std::uint64_t k1) {
#ifdef QRM_HAS_CPU_DISPATCH
    if constexpr (std::is_same_v<S, std::complex<float>>)
      if (float_arithmetic<S>(ex) && job.level != simd_level::generic) {
        if constexpr (avx512_kernels)
          if (wide) return csr_range_dim<S, float, 8, true, Dim, 0, 0, 2>(job, s, neighbours, k0, k1);
        return csr_range_dim<S, float, 4, true, Dim, 0, 0, 4>(job, s, neighbours, k0, k1);
      }
#endif
    if constexpr (avx512_kernels)
      if (wide) return csr_range_dim<S, double, 4, true, Dim, 0, 0, 4>(job, s, neighbours, k0, k1);
    csr_range_dim<S, double, 2, true, Dim, 0, 0, 8>(job, s, neighbours, k0, k1);
  });
}

// Applies a planned matrix at the bases of an n-qubit state where the controls hold (tmask: the
// plan's targets as a mask; cmask: the control mask the plan was built with).
template <class S>
void apply_unitary_plan(S* a, unsigned n, const unitary_plan<S>& plan, std::uint64_t tmask, std::uint64_t cmask,
                        std::uint64_t cvalue, const exec_policy& ex) {
  if constexpr (std::is_same_v<S, double>) {
    // Amplitudes 2k and 2k + 1 differ only in qubit 0, which the op neither moves nor tests: a
    // real matrix maps them as it maps the complex number 2k + i (2k + 1), so the complex<double>
    // kernels (vectorised; the row lists below are scalar: a fused 8x8 block took 3.5x the time of
    // its gates unfused) apply it to the state read as 2^(n-1) complex numbers. std::complex
    // guarantees the layout of two doubles ([complex.numbers]).
    if (plan.on_pairs && n >= 2)
      return apply_unitary_plan(reinterpret_cast<std::complex<double>*>(a), n - 1, *plan.on_pairs, tmask >> 1, cmask >> 1,
                                cvalue >> 1, ex);
#ifdef QRM_HAS_CPU_DISPATCH
    if (avx512_kernels && plan.lane_path) {
      const subspace bases(n, cmask | (tmask & ~std::uint64_t{7}), cvalue);
      const auto chunks = [&](auto&& g) { for_each_chunk(bases, ex, 8, g); };
      const std::span<const qubit_index> targets(plan.targets);
      if constexpr (avx512_kernels && specialized_kernels) {
        if (plan.m->dim == 4) return lane_mix<S, double, 8, 4>(a, *plan.m, targets, bases, chunks);
        return lane_mix<S, double, 8>(a, *plan.m, targets, bases, chunks);
      }
    }
#endif
  }
  const dense_matrix& m = *plan.m;
  const subspace s(n, cmask | tmask, cvalue);
  if constexpr (scalar_traits<S>::is_complex) {
    if (plan.vector_kernel) {
#ifdef QRM_HAS_CPU_DISPATCH
      if constexpr (avx512_kernels && specialized_kernels) {
        if (plan.lane_path) {
          const std::uint64_t lanes = float_arithmetic<S>(ex) ? 7 : 3;
          const subspace bases(n, cmask | (tmask & ~lanes), cvalue);
          const auto chunks = [&](auto&& g) { for_each_chunk(bases, ex, m.dim, g); };
          const std::span<const qubit_index> targets(plan.targets);
          if constexpr (std::is_same_v<S, std::complex<float>>)
            if (float_arithmetic<S>(ex))
              return m.dim == 4 ? lane_mix<S, float, 8, 4>(a, m, targets, bases, chunks)
                                : lane_mix<S, float, 8>(a, m, targets, bases, chunks);
          if (m.dim == 4) return lane_mix<S, double, 4, 4>(a, m, targets, bases, chunks);
          return lane_mix<S, double, 4>(a, m, targets, bases, chunks);
        }
      }
#endif
      const csr_job<S> job = plan.job(a, n);
      if constexpr (specialized_kernels)
        if (plan.grouped) return m.dim == 2 ? apply_grouped<S, 2>(job, s, ex) : apply_grouped<S, 4>(job, s, ex);
#ifdef QRM_HAS_CPU_DISPATCH
      // Float arithmetic (asked for, and a CPU with AVX2): eight neighbouring bases per 512-bit
      // register where the lowest 3 qubits are free, else four per 256-bit register (neighbours,
      // or gathered as in base_groups); else double below.
      if constexpr (std::is_same_v<S, std::complex<float>>) {
        const bool wide = job.level == simd_level::avx512 && s.run_log2() >= 3;
        const base_groups gr = group_bases(s, 4);
        if (ex.math == float_math::single_precision && job.level != simd_level::generic && (wide || gr.ok)) {
          if (wide) {
            static constexpr std::uint64_t neighbours[4] = {0, 1, 2, 3};
            if constexpr (avx512_kernels)
              for_each_chunk(s, ex, m.dim, [&](std::uint64_t k0, std::uint64_t k1) {
                csr_range<S, 8, true, float>(job, s, neighbours, k0, k1);
              });
          } else {
            for_each_chunk(gr.bases, ex, m.dim * (gr.contiguous ? 1 : 4), [&](std::uint64_t k0, std::uint64_t k1) {
              if (gr.contiguous)
                csr_range<S, 4, true, float>(job, gr.bases, gr.g, k0, k1);
              else
                csr_range<S, 4, false, float>(job, gr.bases, gr.g, k0, k1);
            });
          }
          return;
        }
      }
#endif
      // Four bases per vector where the CPU has 512-bit registers, else two; a state too
      // small for that many free qubits takes the row-list path below.
      for (unsigned per = job.level == simd_level::avx512 ? 4 : 2; per >= 2; per /= 2) {
        const base_groups gr = group_bases(s, per);
        if (!gr.ok) continue;
        const subspace& bs = gr.bases;
        const std::uint64_t* g = gr.g;
        const std::uint64_t work = m.dim * (gr.contiguous ? 1 : per);
        for_each_chunk(bs, ex, work, [&](std::uint64_t k0, std::uint64_t k1) {
          if (per == 4) {
            if constexpr (avx512_kernels) {
              if (gr.contiguous)
                csr_range<S, 4, true>(job, bs, g, k0, k1);
              else
                csr_range<S, 4, false>(job, bs, g, k0, k1);
            }
          } else {
            if (gr.contiguous)
              csr_range<S, 2, true>(job, bs, g, k0, k1);
            else
              csr_range<S, 2, false>(job, bs, g, k0, k1);
          }
        });
        return;
      }
    }
  }
  const sparse_rows<S> rows(m);
  for_each_run(s, ex, m.dim, unitary_applier<S>{rows, plan.offsets, a});
}

template <class S>
void kernel_unitary(S* a, unsigned n, const dense_matrix& m, std::span<const qubit_index> targets,
                    std::uint64_t tmask, std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex) {
  const unitary_plan<S> plan(m, targets, cmask, ex);
  apply_unitary_plan(a, n, plan, tmask, cmask, cvalue, ex);
}


// ---- add a constant modulo 2^k (a permutation, in place) ------------------------------------

template <class S>
void kernel_add(S* a, unsigned n, std::int64_t constant, std::span<const qubit_index> bits, std::uint64_t rmask,
                std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex) {
  const std::size_t k = bits.size();
  const std::uint64_t dim = std::uint64_t{1} << k, wrap = dim - 1;
  const std::uint64_t shift = static_cast<std::uint64_t>(constant) & wrap;
  if (shift == 0) return;
  const auto offsets = target_offsets(bits);
  const subspace s(n, cmask | rmask, cvalue);
  // Bases are processed `block` at a time: rows of one register value are read contiguously
  // into a small buffer, then written back to the shifted rows.
  const std::uint64_t block = std::max<std::uint64_t>(1, (std::uint64_t{1} << 13) >> k);
  for_each_run(s, ex, dim, [&](std::uint64_t i0, std::uint64_t len) {
    thread_local std::vector<S> buf;  // reused: runs can be one base long
    if (buf.size() < dim * std::min(block, len)) buf.resize(static_cast<std::size_t>(dim * std::min(block, len)));
    for (std::uint64_t b0 = i0; b0 < i0 + len; b0 += block) {
      const std::uint64_t w = std::min(block, i0 + len - b0);
      for (std::uint64_t v = 0; v < dim; ++v) std::copy_n(a + b0 + offsets[v], w, buf.data() + v * w);
      for (std::uint64_t v = 0; v < dim; ++v) std::copy_n(buf.data() + v * w, w, a + b0 + offsets[(v + shift) & wrap]);
    }
  });
}

// ---- multiplexed gates ------------------------------------------------------------------------

// Visiting each entry's subspace costs a pass over its share of the state, but when the select
// qubits sit inside a cache line every entry drags in whole lines; one sweep over everything
// with a table lookup is cheaper then.
template <int = 0>
inline bool mux_prefers_sweep(std::size_t entries, std::span<const qubit_index> select, std::size_t scalar_bytes,
                              mux_strategy forced = mux_strategy::automatic) {
  const std::size_t m = select.size();
  if (m > 20) return false;
  if (forced != mux_strategy::automatic) return forced == mux_strategy::sweep;
  unsigned lowest = 64;
  for (qubit_index q : select) lowest = std::min<unsigned>(lowest, q);
  unsigned line_bits = 0;
  while ((std::size_t{1} << (line_bits + 1)) * scalar_bytes <= 64) ++line_bits;
  // Select qubits above the cache line: each entry's subspace is whole lines, visited with
  // vectorised runs; a sweep would move as many bytes but look up every amplitude.
  if (lowest >= line_bits) return false;
  const double waste = static_cast<double>(std::uint64_t{1} << std::min<unsigned>(line_bits - lowest, static_cast<unsigned>(m)));
  return static_cast<double>(entries) * waste >= static_cast<double>(std::uint64_t{1} << m);
}

// Select value of basis index i.
struct select_reader {
  std::span<const qubit_index> select;
  bool contiguous_bits;
  unsigned shift;
  std::uint64_t mask;
  explicit select_reader(std::span<const qubit_index> sel)
      : select(sel), contiguous_bits(contiguous(sel)), shift(sel.empty() ? 0 : sel[0]),
        mask(sel.size() >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << sel.size()) - 1) {}
  std::uint64_t operator()(std::uint64_t i) const { return contiguous_bits ? (i >> shift) & mask : gather(i, select); }
};

template <class S>
void kernel_mux1(S* a, unsigned n, std::span<const mux1_entry> entries, unsigned t, std::span<const qubit_index> select,
                 std::uint64_t smask, std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex) {
  if (!mux_prefers_sweep(entries.size(), select, sizeof(S), ex.mux)) {
    for (const mux1_entry& e : entries)
      kernel_gate1(a, n, e.gate, t, cmask | smask, cvalue | deposit(e.select, select), ex);
    return;
  }
  using R = typename scalar_traits<S>::real;
  // Per select value: the 2x2 matrix in backend precision, or none.
  std::vector<std::int32_t> slot(std::size_t{1} << select.size(), -1);
  std::vector<std::array<double, 8>> mats;
  for (const mux1_entry& e : entries) {
    std::array<double, 8> mm{};
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) {
        mm[static_cast<std::size_t>(4 * r + 2 * c)] = e.gate.m[r][c].real();
        mm[static_cast<std::size_t>(4 * r + 2 * c + 1)] = e.gate.m[r][c].imag();
      }
    slot[e.select] = static_cast<std::int32_t>(mats.size());
    mats.push_back(mm);
  }
  const select_reader sel(select);
  const std::uint64_t st = std::uint64_t{1} << t;
  const subspace s(n, cmask | st, cvalue);
  for_each_run(s, ex, 2, [&](std::uint64_t i0, std::uint64_t len) {
    for (std::uint64_t i = i0; i < i0 + len; ++i) {
      const std::int32_t id = slot[sel(i)];
      if (id < 0) continue;
      const auto& m = mats[static_cast<std::size_t>(id)];
      if constexpr (scalar_traits<S>::is_complex) {
        const double xr = a[i].real(), xi = a[i].imag(), yr = a[i + st].real(), yi = a[i + st].imag();
        a[i] = S(static_cast<R>(m[0] * xr - m[1] * xi + m[2] * yr - m[3] * yi),
                 static_cast<R>(m[0] * xi + m[1] * xr + m[2] * yi + m[3] * yr));
        a[i + st] = S(static_cast<R>(m[4] * xr - m[5] * xi + m[6] * yr - m[7] * yi),
                      static_cast<R>(m[4] * xi + m[5] * xr + m[6] * yi + m[7] * yr));
      } else {
        const double x = a[i], y = a[i + st];
        a[i] = static_cast<S>(m[0] * x + m[2] * y);
        a[i + st] = static_cast<S>(m[4] * x + m[6] * y);
      }
    }
  });
}

template <class S>
void kernel_mux_unitary(S* a, unsigned n, std::span<const dense_matrix> matrices,
                        std::span<const mux_unitary_entry> entries, std::span<const qubit_index> targets,
                        std::uint64_t tmask, std::span<const qubit_index> select, std::uint64_t smask, std::uint64_t cmask,
                        std::uint64_t cvalue, const exec_policy& ex) {
  const bool per_entry = !mux_prefers_sweep(entries.size(), select, sizeof(S), ex.mux);
  if constexpr (scalar_traits<S>::is_complex) {
    // Each entry is its matrix controlled by the select bits: the vector kernels, one plan per
    // matrix (the logical noisy oracle on the paper's 4x4 walk, 15 qubits, 100 trajectories
    // through Q^16 A: 1.06-1.08 -> 0.72-0.75 s, bench/RESULTS.md). Real states keep the scalar
    // products below, the compact backend's, so that the two agree bit for bit (compact.hpp,
    // "Determinism"); the vector kernels group the same products differently.
    if (per_entry) {
      std::vector<std::optional<unitary_plan<S>>> plans(matrices.size());
      for (const mux_unitary_entry& e : entries) {
        if (!plans[e.matrix]) plans[e.matrix].emplace(matrices[e.matrix], targets, cmask | smask, ex);
        apply_unitary_plan(a, n, *plans[e.matrix], tmask, cmask | smask, cvalue | deposit(e.select, select), ex);
      }
      return;
    }
  }
  std::vector<sparse_rows<S>> rows;
  rows.reserve(matrices.size());
  for (const dense_matrix& m : matrices) rows.emplace_back(m);
  const auto offsets = target_offsets(targets);
  if (per_entry) {
    for (const mux_unitary_entry& e : entries) {
      const subspace s(n, cmask | smask | tmask, cvalue | deposit(e.select, select));
      for_each_run(s, ex, rows[e.matrix].dim, unitary_applier<S>{rows[e.matrix], offsets, a});
    }
    return;
  }
  std::vector<std::int32_t> slot(std::size_t{1} << select.size(), -1);
  for (const mux_unitary_entry& e : entries) slot[e.select] = static_cast<std::int32_t>(e.matrix);
  const select_reader sel(select);
  const subspace s(n, cmask | tmask, cvalue);
  const std::size_t dim = std::size_t{1} << targets.size();
  for_each_run(s, ex, dim, [&](std::uint64_t i0, std::uint64_t len) {
    for (std::uint64_t b = i0; b < i0 + len; ++b) {
      const std::int32_t id = slot[sel(b)];
      if (id >= 0) unitary_applier<S>{rows[static_cast<std::size_t>(id)], offsets, a}(b, 1);
    }
  });
}

}  // namespace qrm::detail
