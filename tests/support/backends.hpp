// tests/support/backends.hpp: one way to build, load and read every backend, so a single test
// body (doctest TEST_CASE_TEMPLATE_DEFINE) runs on all of them. A new backend adds its traits here.
#pragma once

#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include <qrm/qrm.hpp>

namespace qrm_test {

// Loading and reading go through the names every qrm::backend shares (set_amplitudes, to_dense),
// so a backend's traits only say how to build it, what to call it and how close it must come.
template <qrm::backend B>
struct backend_io {
  using backend = B;
  using scalar = typename B::scalar_type;
  static void load(B& b, const std::vector<std::complex<double>>& v) {
    using R = typename B::real_type;
    std::vector<scalar> a(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if constexpr (B::is_complex)
        a[i] = scalar(static_cast<R>(v[i].real()), static_cast<R>(v[i].imag()));
      else
        a[i] = static_cast<scalar>(v[i].real());
    }
    b.set_amplitudes(a);
  }
  static std::vector<std::complex<double>> dump(const B& b) {
    const auto d = b.to_dense();
    std::vector<std::complex<double>> v(d.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::complex<double>(d[i]);
    return v;
  }
};

template <class B>
struct backend_traits;

template <class S>
struct backend_traits<qrm::state_vector<S>> : backend_io<qrm::state_vector<S>> {
  using backend = qrm::state_vector<S>;
  static constexpr bool is_complex = backend::is_complex;
  // Agreement with the double-precision reference: 1e-12 for double (a few roundings of O(1)
  // numbers), 2e-5 for float (eps 6e-8 times a few dozen operations on values up to ~4).
  static constexpr double tolerance = std::is_same_v<typename backend::real_type, double> ? 1e-12 : 2e-5;
  static const char* name() { return qrm::detail::scalar_name<S>(); }
  static backend make(std::size_t n, unsigned threads = 1, qrm::mux_strategy mux = qrm::mux_strategy::automatic) {
    qrm::dense_options o;
    o.threads = threads;
    o.mux = mux;
    return backend(n, o);
  }
};

// The compact backend: threads and the multiplexing strategy do not apply to it (it is
// single-threaded and always visits the nonzero entries once).
template <class S, class L>
struct backend_traits<qrm::compact_state<S, L>> : backend_io<qrm::compact_state<S, L>> {
  using backend = qrm::compact_state<S, L>;
  static constexpr bool is_complex = backend::is_complex;
  // Same arithmetic (double, one rounding per stored value) as the dense backend: same bars.
  static constexpr double tolerance = backend_traits<qrm::state_vector<S>>::tolerance;
  static std::string name() { return std::string("compact ") + qrm::detail::scalar_name<S>(); }
  static backend make(std::size_t n, unsigned = 1, qrm::mux_strategy = qrm::mux_strategy::automatic) { return backend(n); }
};

// Largest |a_i - b_i|.
inline double max_diff(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b) {
  double d = a.size() == b.size() ? 0.0 : 1e300;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace qrm_test
