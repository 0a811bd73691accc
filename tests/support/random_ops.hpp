// tests/support/random_ops.hpp: random states, matrices and controls for tests.
#pragma once

#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include <qrm/circuit/ops.hpp>
#include <qrm/support/random.hpp>

namespace qrm_test {

inline double signed_uniform(qrm::rng& g) { return 2.0 * g.uniform() - 1.0; }

inline std::complex<double> random_entry(qrm::rng& g, bool complex_values) {
  return {signed_uniform(g), complex_values ? signed_uniform(g) : 0.0};
}

// A random (unnormalised) vector of 2^n amplitudes.
inline std::vector<std::complex<double>> random_state(std::size_t n, qrm::rng& g, bool complex_values) {
  std::vector<std::complex<double>> v(std::size_t{1} << n);
  for (auto& a : v) a = random_entry(g, complex_values);
  return v;
}

// A random matrix with no structure: not unitary, so a kernel that mixes up rows and columns,
// or drops a term, cannot hide behind orthogonality.
inline qrm::dense_matrix random_matrix(std::size_t k, qrm::rng& g, bool complex_values) {
  qrm::dense_matrix m(std::size_t{1} << k);
  for (auto& z : m.data) z = random_entry(g, complex_values);
  return m;
}

inline qrm::gate1 random_gate1_nonunitary(qrm::rng& g, bool complex_values) {
  return qrm::gate::u(random_entry(g, complex_values), random_entry(g, complex_values), random_entry(g, complex_values),
                      random_entry(g, complex_values));
}

// A random unitary (orthogonal when real), by Gram-Schmidt on a random matrix.
inline qrm::dense_matrix random_unitary(std::size_t k, qrm::rng& g, bool complex_values) {
  qrm::dense_matrix m = random_matrix(k, g, complex_values);
  const std::size_t d = m.dim;
  for (std::size_t c = 0; c < d; ++c) {
    for (std::size_t p = 0; p < c; ++p) {
      std::complex<double> dot{};
      for (std::size_t r = 0; r < d; ++r) dot += std::conj(m(r, p)) * m(r, c);
      for (std::size_t r = 0; r < d; ++r) m(r, c) -= dot * m(r, p);
    }
    double norm = 0;
    for (std::size_t r = 0; r < d; ++r) norm += std::norm(m(r, c));
    norm = std::sqrt(norm);
    for (std::size_t r = 0; r < d; ++r) m(r, c) /= norm;
  }
  return m;
}

inline qrm::gate1 random_gate1_unitary(qrm::rng& g, bool complex_values) {
  const qrm::dense_matrix m = random_unitary(1, g, complex_values);
  return qrm::gate::u(m(0, 0), m(0, 1), m(1, 0), m(1, 1));
}

}  // namespace qrm_test
