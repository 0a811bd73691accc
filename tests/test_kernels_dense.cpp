// The kernel tests (kernel_cases.hpp) on the dense backend, every amplitude type, plus the
// dense backend's threading.
#include <algorithm>
#include <complex>
#include <string>
#include <type_traits>
#include <vector>

#include "kernel_cases.hpp"

#define QRM_DENSE_BACKENDS                                                                            \
  qrm::state_vector<double>, qrm::state_vector<float>, qrm::state_vector<std::complex<double>>, \
      qrm::state_vector<std::complex<float>>
TEST_CASE_TEMPLATE_INVOKE(gate1_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(unitary_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(add_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(mux_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(norm_drift, QRM_DENSE_BACKENDS);
// Only the dense backend uses threads (the compact one is single-threaded; its determinism is
// tested in test_compact.cpp).
TEST_CASE_TEMPLATE_INVOKE(thread_determinism, qrm::state_vector<double>, qrm::state_vector<std::complex<double>>);
TEST_CASE_TEMPLATE_INVOKE(chunked_subspaces, qrm::state_vector<double>, qrm::state_vector<std::complex<float>>);

// X is a byte move (detail/dense_swap.hpp): blocks of 2^t amplitudes narrower than a vector are
// swapped by one shuffle inside the register, wider ones as whole vectors, at each vector width.
// Every target 0..8 (blocks of 4 bytes to 4 KiB), targets below, between and above controls, one
// and two threads with chunks, each scalar: the state must be the exact index permutation.
TEST_CASE_TEMPLATE("X swaps blocks of every width exactly at every vector level", S, double, float,
                   std::complex<double>, std::complex<float>) {
  const unsigned n = 14;
  std::vector<S> start(std::size_t{1} << n);
  for (std::size_t i = 0; i < start.size(); ++i) {
    if constexpr (std::is_floating_point_v<S>)
      start[i] = static_cast<S>(i + 1);
    else
      start[i] = S(static_cast<float>(i + 1), -static_cast<float>(i) - 0.5f);
  }
  const std::vector<std::vector<qrm::control>> control_sets = {
      {}, {{13, true}, {12, false}, {11, true}}, {{13, true}, {12, true}, {11, true}, {10, false}, {9, true}, {8, true}},
      {{4, true}}};
  std::size_t cases = 0;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (unsigned threads : {1u, 2u})
      for (const auto& cs : control_sets)
        for (qrm::qubit_index t = 0; t <= 8; ++t) {
          if (std::any_of(cs.begin(), cs.end(), [&](const qrm::control& c) { return c.qubit == t; })) continue;
          qrm::dense_options o;
          o.threads = threads;
          o.simd = level;
          qrm::state_vector<S> s(n, o);
          s.set_min_parallel(1);
          s.set_amplitudes(start);
          s.apply_gate1(qrm::gate::x(), t, cs);
          std::size_t wrong = 0;
          for (std::uint64_t i = 0; i < start.size(); ++i) {
            const bool on = std::all_of(cs.begin(), cs.end(), [&](const qrm::control& c) { return ((i >> c.qubit) & 1u) == c.value; });
            const S expect = on ? start[i ^ (std::uint64_t{1} << t)] : start[i];
            wrong += s.amplitudes()[i] != expect;
          }
          INFO("level " << std::string(qrm::simd_level_name(level)) << " threads " << threads << " controls " << cs.size() << " target " << t);
          CHECK(wrong == 0);
          ++cases;
        }
  CHECK(cases == 3 * 2 * (9 + 9 + 8 + 8));
}
