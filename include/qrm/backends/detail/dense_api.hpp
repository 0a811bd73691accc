// qrm/backends/detail/dense_api.hpp: what state_vector (backends/dense.hpp) calls in the dense
// kernels: their options and the declarations of their entry points. The definitions are in
// dense_kernels.hpp and dense_blocked.hpp, which dense.hpp includes (through detail/dense_members.hpp) unless QRM_COMPILED_BACKENDS
// says they are compiled in another file (compiled_backends.hpp): then a source file that runs a
// state_vector parses none of the kernels.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "../../circuit/detail/runs.hpp"
#include "../../circuit/ops.hpp"
#include "../../circuit/program.hpp"
#include "bits.hpp"

namespace qrm {
// Which vector instructions the matrix kernels use: the best this CPU has (automatic), or a
// given level (to compare them, or to test each path on one machine); a level the CPU lacks
// falls back to the best one below it.
enum class simd_level : unsigned char { automatic, generic, avx2, avx512 };

// What the matrix kernels (fused blocks, and complex<float> gates above target 0 on states of 12
// or more free qubits) and the low-target pair kernel (dense_pairs.hpp) compute complex<float>
// amplitudes in. double_precision, the default: each
// output is a sum of double products rounded to float once, so one gate repeated 2 x 10^4 times
// keeps the norm to 2e-7. single_precision: float products and sums, as Google qsim computes;
// twice the amplitudes per register and no conversions (the decomposed walk fused runs about
// 2x faster), at the price of float rounding inside every sum (the repeated gate drifts the
// norm by 1.4e-4 for an Ry on 12 qubits, against 8e-8). It needs AVX2; without it the kernels compute in double.
enum class float_math : unsigned char { double_precision, single_precision };

constexpr const char* simd_level_name(simd_level l) {
  switch (l) {
    case simd_level::automatic: return "automatic";
    case simd_level::generic: return "generic";
    case simd_level::avx2: return "avx2";
    case simd_level::avx512: return "avx512";
  }
  return "?";
}

// How a multiplexed gate visits the state: each entry's subspace, or one sweep with a lookup.
enum class mux_strategy : unsigned char { automatic, per_entry, sweep };
}  // namespace qrm

namespace qrm::detail {

// How kernels may use threads: at most `threads`, and only when a kernel touches at least
// `min_parallel` amplitudes (below that, waking workers costs more than the loop).
struct exec_policy {
  unsigned threads = 1;
  std::uint64_t min_parallel = std::uint64_t{1} << 16;
  mux_strategy mux = mux_strategy::automatic;
  simd_level simd = simd_level::automatic;
  float_math math = float_math::double_precision;
};

// The lowest qubits every chunk keeps: 128 contiguous bytes, whole cache lines per copied run.
template <class S>
constexpr unsigned chunk_low_qubits() {
  return static_cast<unsigned>(std::countr_zero(128 / sizeof(S)));
}

// Qubits of a chunk of `chunk_bytes` bytes of S amplitudes (0: no chunks; run_ops chunks from 4).
template <class S>
constexpr unsigned chunk_qubits(std::uint64_t chunk_bytes) {
  const std::uint64_t amplitudes = chunk_bytes / sizeof(S);
  return amplitudes ? static_cast<unsigned>(std::bit_width(amplitudes)) - 1 : 0;
}

// A run is chunked when its ops would make at least this many passes over memory on their own.
// Copying every chunk of a 2^24-amplitude complex<float> state in and out costs 2.1-3.3 in-place
// passes (runs of 128 bytes to 4 KiB, chunks of 2^15 to 2^17 amplitudes; AMD EPYC VM,
// 2026-12-05; a prefetch distance of 8 KiB instead of 16 runs, or non-temporal stores, did not
// change the random suite's time), and the ops then run from cache, so a run breaks even at 2 to
// 3 passes. Same measurements as memory_bound_dim (dense_blocked.hpp): at 4 passes the fused
// programs ran within the noise of 2, and the unfused ones within the noise of 6 at both.
inline constexpr double min_chunked_passes = 2;

// ---- entry points (dense_kernels.hpp) ----------------------------------------------------

template <class S>
void kernel_gate1(S* a, unsigned n, const gate1& g, unsigned t, std::uint64_t cmask, std::uint64_t cvalue,
                  const exec_policy& ex);
template <class S>
void kernel_unitary(S* a, unsigned n, const dense_matrix& m, std::span<const qubit_index> targets,
                    std::uint64_t tmask, std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex);
template <class S>
void kernel_add(S* a, unsigned n, std::int64_t constant, std::span<const qubit_index> bits, std::uint64_t rmask,
                std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex);
template <class S>
void kernel_mux1(S* a, unsigned n, std::span<const mux1_entry> entries, unsigned t, std::span<const qubit_index> select,
                 std::uint64_t smask, std::uint64_t cmask, std::uint64_t cvalue, const exec_policy& ex);
template <class S>
void kernel_mux_unitary(S* a, unsigned n, std::span<const dense_matrix> matrices,
                        std::span<const mux_unitary_entry> entries, std::span<const qubit_index> targets,
                        std::uint64_t tmask, std::span<const qubit_index> select, std::uint64_t smask, std::uint64_t cmask,
                        std::uint64_t cvalue, const exec_policy& ex);
// Sum over s of g(first_index, length), summed per chunk then in chunk order (deterministic).
template <class G>
double reduce_runs(const subspace& s, const exec_policy& ex, G&& g);
template <class S>
double norm_of_run(const S* a, std::uint64_t first, std::uint64_t len);

// ---- runs of ops applied chunk by chunk (dense_blocked.hpp) ---------------------------------

template <class S>
constexpr std::size_t memory_bound_dim(const exec_policy& ex);
template <int = 0>
run_plan plan_runs(std::span<const op::any> ops, unsigned n, unsigned m, unsigned low = 0,
                   double min_passes = min_chunked_passes, std::size_t widest_memory_bound = 4);
template <class Checks>
struct validating_sink;
template <class S>
void run_in_chunks(S* a, unsigned n, std::span<const op::any> ops, std::span<const std::size_t> which,
                   std::uint64_t local, const exec_policy& ex);

}  // namespace qrm::detail
