// qrm/backends/dense.hpp: the dense state-vector backend, templated on its amplitude type.
//
// state_vector<S> holds all 2^n amplitudes. S is std::complex<double> (default),
// std::complex<float>, or real double / float for circuits whose gates are all real (the
// paper's circuits are: X, Ry and the +-1/2 coins), which halves memory and arithmetic.
// dense_backend is the family (backend.hpp) that picks among them.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <type_traits>
#include <vector>

#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

#include "backend.hpp"
#include "detail/aligned_allocator.hpp"
#include "detail/bits.hpp"
#include "detail/dense_api.hpp"
#include "detail/scalar.hpp"
#include "../circuit/fuse.hpp"
#include "../circuit/ops.hpp"
#include "../circuit/program.hpp"

namespace qrm {

namespace detail {
template <class Label, class Scalar>
struct op_checks;  // detail/validate.hpp, which only the members' file (detail/dense_members.hpp) needs
}  // namespace detail

struct dense_options {
  unsigned threads = 0;                               // 0: every hardware thread; 1: never spawn work
  std::uint64_t min_parallel = std::uint64_t{1} << 16;  // amplitudes a kernel touches before it uses threads
  std::uint64_t max_bytes = 0;                        // refuse larger states; 0: the machine's physical memory
  // Multiplexed gates: visit each entry's subspace, or sweep the state once with a table lookup;
  // `automatic` picks by cache-line waste (detail::mux_prefers_sweep).
  mux_strategy mux = mux_strategy::automatic;
  // Vector instructions of the k-qubit matrix kernels (fused gates): see qrm::simd_level.
  simd_level simd = simd_level::automatic;
  // What those kernels compute complex<float> amplitudes in (double unless asked): see qrm::float_math.
  float_math math = float_math::double_precision;
  // Programs (qrm::run) apply runs of ops that fit in chunks of this many bytes chunk by chunk,
  // one trip to memory per run instead of per op (detail/dense_blocked.hpp); 0: op by op. The
  // default is a typical per-core L2 cache (bench/RESULTS.md measures 256 KiB to 4 MiB).
  std::uint64_t chunk_bytes = std::uint64_t{1} << 20;
  // ... when the run's ops would make at least this many passes over memory one by one (see
  // detail::memory_passes; fewer cost less than the chunk's copy).
  double chunk_min_passes = detail::min_chunked_passes;
};

// dense_fusion_options<S>(options, dense): `options` set to fuse within the runs a
// state_vector<S> built with `dense` applies chunk by chunk (fusion_options::chunk_qubits, see
// circuit/fuse.hpp), so fusion adds no trips to memory; unchanged when it uses no chunks.
template <class S>
fusion_options dense_fusion_options(fusion_options options = {}, const dense_options& dense = {}) {
  const unsigned m = detail::chunk_qubits<S>(dense.chunk_bytes);
  if (m < 4) return options;
  options.chunk_qubits = m;
  options.chunk_low_qubits = detail::chunk_low_qubits<S>();
  return options;
}

namespace detail {
template <int = 0>
inline std::string format_bytes(long double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) {
    bytes /= 1024;
    ++u;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4Lg %s", bytes, units[u]);
  return buf;
}

template <int = 0>
inline std::uint64_t physical_memory_bytes() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
#endif
  return 0;
}
}  // namespace detail

// state_vector<S>: 2^n amplitudes, starting in |0...0>.
template <class Scalar = std::complex<double>>
class state_vector {
  static constexpr bool scalar_must_be_float_double_or_complex = detail::is_backend_scalar<Scalar>;
  static_assert(scalar_must_be_float_double_or_complex,
                "scalar_must_be_float_double_or_complex: state_vector<S> needs S = float, double, "
                "std::complex<float> or std::complex<double>");

 public:
  using scalar_type = Scalar;
  using real_type = typename detail::scalar_traits<Scalar>::real;
  static constexpr bool is_complex = detail::scalar_traits<Scalar>::is_complex;

  // Bytes a state of n qubits needs.
  static long double bytes_for(std::size_t n) { return std::ldexp(static_cast<long double>(sizeof(Scalar)), static_cast<int>(n)); }

  explicit state_vector(std::size_t num_qubits, dense_options opt = {});

  std::size_t num_qubits() const { return n_; }
  std::uint64_t size() const { return amps_.size(); }
  unsigned threads() const { return ex_.threads; }
  void set_threads(unsigned t) { ex_.threads = std::max(1u, t); }
  void set_min_parallel(std::uint64_t amplitudes) { ex_.min_parallel = amplitudes; }

  std::span<Scalar> amplitudes() { return amps_; }
  std::span<const Scalar> amplitudes() const { return amps_; }
  Scalar amplitude(std::uint64_t index) const {
    if (index >= amps_.size())
      throw std::out_of_range("state_vector::amplitude: index " + std::to_string(index) + " >= 2^" + std::to_string(n_));
    return amps_[index];
  }
  // |index>
  void set_basis_state(std::uint64_t index) {
    if (index >= amps_.size())
      throw std::out_of_range("state_vector::set_basis_state: index " + std::to_string(index) + " >= 2^" +
                              std::to_string(n_));
    std::fill(amps_.begin(), amps_.end(), Scalar{});
    amps_[index] = Scalar{1};
  }
  void set_amplitudes(std::span<const Scalar> a) {
    if (a.size() != amps_.size())
      throw std::invalid_argument("state_vector::set_amplitudes: got " + std::to_string(a.size()) + " amplitudes, need " +
                                  std::to_string(amps_.size()));
    std::copy(a.begin(), a.end(), amps_.begin());
  }
  // A copy of the 2^n amplitudes (amplitudes() is the view without a copy).
  std::vector<Scalar> to_dense() const { return std::vector<Scalar>(amps_.begin(), amps_.end()); }

  // ---- gate_sink --------------------------------------------------------------------------

  void apply_gate1(const gate1& g, qubit_index target, std::span<const control> controls);
  void apply_unitary(const dense_matrix& m, std::span<const qubit_index> targets, std::span<const control> controls);
  void apply_add(std::int64_t constant, std::span<const qubit_index> bits, std::span<const control> controls);
  void apply_mux1(std::span<const mux1_entry> entries, qubit_index target, std::span<const qubit_index> select,
                  std::span<const control> controls);
  void apply_mux_unitary(std::span<const dense_matrix> matrices, std::span<const mux_unitary_entry> entries,
                         std::span<const qubit_index> targets, std::span<const qubit_index> select,
                         std::span<const control> controls);

  // Applies ops (qrm::run calls this): the state of applying them one by one in order, to
  // rounding, with runs of ops that fit a chunk of dense_options::chunk_bytes applied chunk by
  // chunk (commuting ops possibly reordered to fill a run: detail::plan_runs).
  void run_ops(std::span<const op::any> ops);
  void set_chunk_bytes(std::uint64_t bytes) { chunk_bytes_ = bytes; }
  void set_chunk_min_passes(double passes);

  // ---- reading the state ----------------------------------------------------------------------

  // Sum of |a|^2 (1 for a normalised state), summed in a fixed order.
  double norm_squared() const;
  // Probability that every control holds (e.g. out = 1).
  double probability(std::span<const control> condition) const;
  // Probabilities of every value of the register `bits` (2^k numbers).
  std::vector<double> distribution(std::span<const qubit_index> bits) const;

 private:
  detail::op_checks<std::uint64_t, Scalar> checks() const;
  unsigned n_;
  std::vector<Scalar, detail::huge_page_allocator<Scalar>> amps_;
  detail::exec_policy ex_;
  std::uint64_t chunk_bytes_ = 0;
  double chunk_min_passes_ = detail::min_chunked_passes;
};

// dense_backend: the dense backend as a type (qrm::backend_family): real or complex double.
struct dense_backend {
  static constexpr std::string_view name = "dense";
  template <class S>
  using state = state_vector<S>;
  template <class F>
  static decltype(auto) visit(std::size_t, bool real, F&& f) {
    if (real) return f(std::type_identity<state_vector<double>>{});
    return f(std::type_identity<state_vector<std::complex<double>>>{});
  }
  // One thread per state: the callers already run their states in parallel.
  template <class B>
  static B make(std::size_t n) {
    dense_options o;
    o.threads = 1;
    return B(n, o);
  }
};

}  // namespace qrm

// The dense backend's part of <qrm/backends/compiled_backends.hpp> (QRM_COMPILED_BACKENDS): the
// state classes and the six functions every kernel a state_vector runs is reached from. PREFIX is
// `extern template` or `template`, expanded in namespace qrm.
#define QRM_DETAIL_DENSE_INSTANCES_FOR(PREFIX, S)                                                                   \
  PREFIX class state_vector<S>;                                                                                     \
  PREFIX void detail::kernel_gate1<S>(S*, unsigned, const gate1&, unsigned, std::uint64_t, std::uint64_t,           \
                                      const detail::exec_policy&);                                                  \
  PREFIX void detail::kernel_unitary<S>(S*, unsigned, const dense_matrix&, std::span<const qubit_index>,            \
                                        std::uint64_t, std::uint64_t, std::uint64_t, const detail::exec_policy&);   \
  PREFIX void detail::kernel_add<S>(S*, unsigned, std::int64_t, std::span<const qubit_index>, std::uint64_t,        \
                                    std::uint64_t, std::uint64_t, const detail::exec_policy&);                      \
  PREFIX void detail::kernel_mux1<S>(S*, unsigned, std::span<const mux1_entry>, unsigned,                           \
                                     std::span<const qubit_index>, std::uint64_t, std::uint64_t, std::uint64_t,     \
                                     const detail::exec_policy&);                                                   \
  PREFIX void detail::kernel_mux_unitary<S>(S*, unsigned, std::span<const dense_matrix>,                            \
                                            std::span<const mux_unitary_entry>, std::span<const qubit_index>,       \
                                            std::uint64_t, std::span<const qubit_index>, std::uint64_t,             \
                                            std::uint64_t, std::uint64_t, const detail::exec_policy&);              \
  PREFIX void detail::run_in_chunks<S>(S*, unsigned, std::span<const op::any>, std::span<const std::size_t>,        \
                                       std::uint64_t, const detail::exec_policy&);
#define QRM_DETAIL_DENSE_INSTANCES(PREFIX)                  \
  QRM_DETAIL_DENSE_INSTANCES_FOR(PREFIX, float)             \
  QRM_DETAIL_DENSE_INSTANCES_FOR(PREFIX, double)            \
  QRM_DETAIL_DENSE_INSTANCES_FOR(PREFIX, std::complex<float>) \
  QRM_DETAIL_DENSE_INSTANCES_FOR(PREFIX, std::complex<double>)

#ifdef QRM_COMPILED_BACKENDS
namespace qrm {
QRM_DETAIL_DENSE_INSTANCES(extern template)
}  // namespace qrm
#endif

// The members that reach the kernels, and the kernels: in every file that includes this one, or
// with QRM_COMPILED_BACKENDS in the one file that includes <qrm/backends/compiled_backends.hpp>.
#ifndef QRM_COMPILED_BACKENDS
#include "detail/dense_members.hpp"
#endif
