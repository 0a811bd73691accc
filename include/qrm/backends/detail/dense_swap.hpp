// qrm/backends/detail/dense_swap.hpp: X (and C^k X) as a move of bytes, the same for every scalar.
//
// An X on target t exchanges the blocks of 2^t amplitudes at i and i + 2^t. Where the target lies
// below every control, each run of the controls' subspace is a row of such block pairs, and the
// exchange is a byte permutation that does not depend on the element type: blocks narrower than a
// vector are swapped inside the register by one shuffle of 32-bit lanes (lane j takes lane
// j ^ block_lanes), wider ones by exchanging whole vectors. Element-wise std::swap moved one
// complex<double> per 16-byte load and store and ran a contiguous C^12 X at 2.1x the time of real
// double (bench_kernels BM_mcx, n = 26).
#pragma once

#include <cstdint>
#include <cstring>
#include <utility>

#include "dense_batched.hpp"

namespace qrm::detail {

typedef std::uint32_t v4u32 __attribute__((vector_size(16)));
typedef std::uint32_t v8u32 __attribute__((vector_size(32)));
typedef std::uint32_t v16u32 __attribute__((vector_size(64)));

template <class V, unsigned BlockLanes, std::size_t... I>
[[gnu::always_inline]] inline void shuffle_lane_blocks(V& v, std::index_sequence<I...>) {
  v = __builtin_shufflevector(v, v, static_cast<int>(I ^ BlockLanes)...);
}

// Swaps adjacent blocks of `block` 32-bit lanes throughout p[0, lanes); lanes is a multiple of
// 2 * block and of the vector's lane count.
template <class V, unsigned BlockLanes>
[[gnu::always_inline]] inline void swap_blocks_in_vectors(std::uint32_t* p, std::uint64_t lanes) {
  constexpr unsigned per = sizeof(V) / 4;
  for (std::uint64_t i = 0; i < lanes; i += per) {
    V v;
    std::memcpy(&v, p + i, sizeof(V));
    shuffle_lane_blocks<V, BlockLanes>(v, std::make_index_sequence<per>{});
    std::memcpy(p + i, &v, sizeof(V));
  }
}

template <class V>
[[gnu::always_inline]] inline void swap_blocks_of_vectors(std::uint32_t* p, std::uint64_t lanes, std::uint64_t block) {
  constexpr unsigned per = sizeof(V) / 4;
  for (std::uint64_t b = 0; b < lanes; b += 2 * block)
    for (std::uint64_t j = b; j < b + block; j += per) {
      V x, y;
      std::memcpy(&x, p + j, sizeof(V));
      std::memcpy(&y, p + j + block, sizeof(V));
      std::memcpy(p + j, &y, sizeof(V));
      std::memcpy(p + j + block, &x, sizeof(V));
    }
}

template <class V>
[[gnu::always_inline]] inline void swap_blocks(std::uint32_t* p, std::uint64_t lanes, std::uint64_t block) {
  constexpr unsigned per = sizeof(V) / 4;
  if (block >= per) return swap_blocks_of_vectors<V>(p, lanes, block);
  if constexpr (per > 1) {
    if (block == 1) return swap_blocks_in_vectors<V, 1>(p, lanes);
  }
  if constexpr (per > 2) {
    if (block == 2) return swap_blocks_in_vectors<V, 2>(p, lanes);
  }
  if constexpr (per > 4) {
    if (block == 4) return swap_blocks_in_vectors<V, 4>(p, lanes);
  }
  if constexpr (per > 8) {
    if (block == 8) return swap_blocks_in_vectors<V, 8>(p, lanes);
  }
}

template <int = 0>
inline void swap_blocks_generic(std::uint32_t* p, std::uint64_t lanes, std::uint64_t block) {
  swap_blocks<v4u32>(p, lanes, block);
}
#ifdef QRM_HAS_CPU_DISPATCH
__attribute__((target("avx2"))) inline void swap_blocks_avx2(std::uint32_t* p, std::uint64_t lanes, std::uint64_t block) {
  swap_blocks<v8u32>(p, lanes, block);
}
__attribute__((target("avx512f"))) inline void swap_blocks_avx512(std::uint32_t* p, std::uint64_t lanes,
                                                                  std::uint64_t block) {
  swap_blocks<v16u32>(p, lanes, block);
}
#endif

// X on blocks wider than a vector: each run of `runs` (a subspace's members, see run_cursor)
// exchanged with the run `dist` bytes above it where `pattern` is all ones (32-bit lanes,
// repeating every pattern_lanes, a power of two >= the vector's lanes): controls on the lowest
// qubits become a lane mask instead of splitting the runs into pieces as short as one amplitude
// (a complex<float> C^2 X on qubits 1, 2 -> 6 at n = 24 took 2.6x a full pass that way).
struct masked_swap_job {
  char* base;
  run_cursor runs;
  std::uint64_t element_bytes, dist;
  const std::uint32_t* pattern;
  std::uint64_t pattern_lanes;
  // The state exceeds streaming_state_bytes: both streams are prefetched. In cache a prefetch
  // only takes load slots: a CX on a 2^16-amplitude complex<double> chunk with runs of 64 bytes
  // took 10.7 us with it and 6.3 us without.
  bool streams;
};

// The loop of swap_runs_masked. Masked: blend under the pattern (else every lane moves);
// OneVector: the pattern fits one vector and stays in a register. The job's fields are copied
// to locals first: the stores through p may alias the job, and the loop reloaded them after each
// one. With these, X and C^k X on a cached 2^16-amplitude complex<double> state (bench_kernels
// BM_mcx placement 3, k = 0..3) take 8.9 / 5.6 / 1.8 / 0.9 us instead of 14.3 / 9.1 / 5.1 / 2.7 us
// (AMD EPYC VM, 2026-12-07).
//
// G > 1 (runs aliasing_stride_bytes apart or more): G vectors (512 bytes) of one run read and
// written before the other's. X on target 25 of 26 complex<float> qubits took 107 ms against
// 28-31 ms on targets 13 and 24; 128 bytes at a time 64 ms, 256 bytes 44 ms, 512 bytes 36 ms.
template <class V, unsigned G, bool Masked, bool OneVector, bool Streams>
[[gnu::always_inline]] inline void swap_runs_loop(const masked_swap_job& job) {
  constexpr unsigned per = sizeof(V) / 4;
  static_assert(G == 1 || (Masked && Streams), "grouped runs are 256 MiB apart: a streamed state");
  char* const base = job.base;
  const std::uint64_t element_bytes = job.element_bytes;
  const std::uint64_t dist = job.dist / 4, wrap = job.pattern_lanes - 1;
  const std::uint32_t* const pattern = job.pattern;
  const std::uint64_t ahead = paired_prefetch_bytes(job.runs.run * element_bytes) / 4;
  V held{};
  if constexpr (OneVector) std::memcpy(&held, pattern, sizeof(V));
  for (run_cursor runs = job.runs; !runs.done(); runs.next()) {
    auto* p = reinterpret_cast<std::uint32_t*>(base + runs.first() * element_bytes);
    const std::uint64_t lanes = runs.length() * element_bytes / 4;
    std::uint64_t j = 0;
    if constexpr (G > 1)
      for (; j + G * per <= lanes; j += G * per) {
        V x[G], y[G];
        for (unsigned u = 0; u < G; ++u) std::memcpy(&x[u], p + j + u * per, sizeof(V));
        for (unsigned u = 0; u < G; ++u) std::memcpy(&y[u], p + j + dist + u * per, sizeof(V));
        for (unsigned u = 0; u < G; ++u) {
          V m = held;
          if constexpr (!OneVector) std::memcpy(&m, pattern + ((j + u * per) & wrap), sizeof(V));
          const V d = (x[u] ^ y[u]) & m;
          x[u] ^= d;
          y[u] ^= d;
        }
        for (unsigned u = 0; u < G; ++u) std::memcpy(p + j + u * per, &x[u], sizeof(V));
        for (unsigned u = 0; u < G; ++u) std::memcpy(p + j + dist + u * per, &y[u], sizeof(V));
      }
    for (; j < lanes; j += per) {
      if constexpr (Streams)
        if (j % 16 == 0) {  // both streams, one line at a time
          prefetch_for_write(p, j + ahead);
          prefetch_for_write(p, j + dist + ahead);
        }
      V x, y;
      std::memcpy(&x, p + j, sizeof(V));
      std::memcpy(&y, p + j + dist, sizeof(V));
      if constexpr (Masked) {
        V m = held;
        if constexpr (!OneVector) std::memcpy(&m, pattern + (j & wrap), sizeof(V));
        const V d = (x ^ y) & m;
        std::memcpy(p + j, &(x ^= d), sizeof(V));
        std::memcpy(p + j + dist, &(y ^= d), sizeof(V));
      } else {
        std::memcpy(p + j, &y, sizeof(V));
        std::memcpy(p + j + dist, &x, sizeof(V));
      }
    }
  }
}

// A state streamed from memory keeps the blend even under an all-ones pattern: the plain
// exchange ran X on target 12 of 25 complex<double> qubits at 21 ms against 19.3 ms.
template <class V, unsigned G = 1>
[[gnu::always_inline]] inline void swap_runs_masked(const masked_swap_job& job) {
  constexpr unsigned per = sizeof(V) / 4;
  const bool one_vector = job.pattern_lanes <= per;
  if constexpr (G == 1)
    if (!job.streams) {
      bool masked = false;
      for (std::uint64_t l = 0; l < job.pattern_lanes; ++l) masked |= job.pattern[l] != ~std::uint32_t{0};
      if (!masked) return swap_runs_loop<V, 1, false, false, false>(job);
      if (one_vector) return swap_runs_loop<V, 1, true, true, false>(job);
      return swap_runs_loop<V, 1, true, false, false>(job);
    }
  if (one_vector) return swap_runs_loop<V, G, true, true, true>(job);
  swap_runs_loop<V, G, true, false, true>(job);
}

template <int = 0>
inline void swap_runs_masked_generic(const masked_swap_job& job) {
  swap_runs_masked<v4u32>(job);
}
template <int = 0>
inline void swap_runs_grouped_generic(const masked_swap_job& job) {
  swap_runs_masked<v4u32, 32>(job);
}
#ifdef QRM_HAS_CPU_DISPATCH
__attribute__((target("avx2"))) inline void swap_runs_masked_avx2(const masked_swap_job& job) {
  swap_runs_masked<v8u32>(job);
}
__attribute__((target("avx512f"))) inline void swap_runs_masked_avx512(const masked_swap_job& job) {
  swap_runs_masked<v16u32>(job);
}
__attribute__((target("avx2"))) inline void swap_runs_grouped_avx2(const masked_swap_job& job) {
  swap_runs_masked<v8u32, 16>(job);
}
__attribute__((target("avx512f"))) inline void swap_runs_grouped_avx512(const masked_swap_job& job) {
  swap_runs_masked<v16u32, 8>(job);
}
#endif

// The widest vector (in bytes) swap_blocks runs with at `level` (resolved, never automatic).
template <int = 0>
inline unsigned swap_vector_bytes(simd_level level) {
  return level == simd_level::avx512 ? 64 : level == simd_level::avx2 ? 32 : 16;
}

// Swaps adjacent blocks of `block_bytes` throughout `bytes` bytes at p (bytes a multiple of
// swap_vector_bytes(level) and of 2 * block_bytes; block_bytes a power of two >= 4).
template <int = 0>
inline void swap_adjacent_blocks(void* p, std::uint64_t bytes, std::uint64_t block_bytes, simd_level level) {
  auto* w = static_cast<std::uint32_t*>(p);
#ifdef QRM_HAS_CPU_DISPATCH
  if constexpr (avx512_kernels)
    if (level == simd_level::avx512) return swap_blocks_avx512(w, bytes / 4, block_bytes / 4);
  if (level == simd_level::avx2) return swap_blocks_avx2(w, bytes / 4, block_bytes / 4);
#else
  (void)level;
#endif
  swap_blocks_generic(w, bytes / 4, block_bytes / 4);
}

template <int = 0>
inline void swap_runs_masked(const masked_swap_job& job, simd_level level) {
  const bool aliased = job.dist >= aliasing_stride_bytes;
#ifdef QRM_HAS_CPU_DISPATCH
  if constexpr (avx512_kernels)
    if (level == simd_level::avx512) return aliased ? swap_runs_grouped_avx512(job) : swap_runs_masked_avx512(job);
  if (level == simd_level::avx2) return aliased ? swap_runs_grouped_avx2(job) : swap_runs_masked_avx2(job);
#else
  (void)level;
#endif
  if (aliased) return swap_runs_grouped_generic(job);
  swap_runs_masked_generic(job);
}

}  // namespace qrm::detail
