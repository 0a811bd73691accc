// qrm/backends/detail/scalar.hpp: the amplitude types backends accept (float, double and their complex
// forms), shared by the dense and compact backends.
#pragma once

#include <complex>
#include <type_traits>

namespace qrm::detail {

template <class S>
struct scalar_traits {
  using real = S;
  static constexpr bool is_complex = false;
};
template <class R>
struct scalar_traits<std::complex<R>> {
  using real = R;
  static constexpr bool is_complex = true;
};

// The rule every backend states in its static_assert.
template <class S>
inline constexpr bool is_backend_scalar =
    std::is_same_v<S, double> || std::is_same_v<S, float> || std::is_same_v<S, std::complex<double>> ||
    std::is_same_v<S, std::complex<float>>;

template <class S>
constexpr const char* scalar_name() {
  if constexpr (std::is_same_v<S, double>)
    return "double";
  else if constexpr (std::is_same_v<S, float>)
    return "float";
  else if constexpr (std::is_same_v<S, std::complex<double>>)
    return "complex<double>";
  else
    return "complex<float>";
}

}  // namespace qrm::detail
