// tests/support/backends.hpp: one way to build, load and read every backend, so a single test
// body (doctest TEST_CASE_TEMPLATE_DEFINE) runs on all of them.
#pragma once

#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include <qrm/qrm.hpp>

namespace qrm_test {

template <class B>
struct backend_traits;

template <class S>
struct backend_traits<qrm::state_vector<S>> {
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
  static void load(backend& b, const std::vector<std::complex<double>>& v) {
    std::vector<S> a(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if constexpr (is_complex)
        a[i] = S(static_cast<typename backend::real_type>(v[i].real()), static_cast<typename backend::real_type>(v[i].imag()));
      else
        a[i] = static_cast<S>(v[i].real());
    }
    b.set_amplitudes(a);
  }
  static std::vector<std::complex<double>> dump(const backend& b) {
    std::vector<std::complex<double>> v(b.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::complex<double>(b.amplitudes()[i]);
    return v;
  }
};

// The compact backend: threads and the multiplexing strategy do not apply to it (it is
// single-threaded and always visits the nonzero entries once).
template <class S, class L>
struct backend_traits<qrm::compact_state<S, L>> {
  using backend = qrm::compact_state<S, L>;
  static constexpr bool is_complex = backend::is_complex;
  // Same arithmetic (double, one rounding per stored value) as the dense backend: same bars.
  static constexpr double tolerance = backend_traits<qrm::state_vector<S>>::tolerance;
  static std::string name() { return std::string("compact ") + qrm::detail::scalar_name<S>(); }
  static backend make(std::size_t n, unsigned = 1, qrm::mux_strategy = qrm::mux_strategy::automatic) { return backend(n); }
  static void load(backend& b, const std::vector<std::complex<double>>& v) {
    std::vector<S> a(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if constexpr (is_complex)
        a[i] = S(static_cast<typename backend::real_type>(v[i].real()), static_cast<typename backend::real_type>(v[i].imag()));
      else
        a[i] = static_cast<S>(v[i].real());
    }
    b.from_dense(a);
  }
  static std::vector<std::complex<double>> dump(const backend& b) {
    const auto d = b.to_dense();
    std::vector<std::complex<double>> v(d.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::complex<double>(d[i]);
    return v;
  }
};

// Largest |a_i - b_i|.
inline double max_diff(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b) {
  double d = a.size() == b.size() ? 0.0 : 1e300;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace qrm_test
