// qrm/backends/backend.hpp: what a backend is, as a concept built from named parts, and a backend
// chosen as a type (a family such as dense_backend or compact_backend, declared beside each backend).
//
// Light maps, quantum renders and estimators are written against these names only, so a new
// simulator plugs into all of them by satisfying qrm::backend and declaring a family.
#pragma once

#include <complex>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

#include "detail/scalar.hpp"
#include "../circuit/ops.hpp"

namespace qrm {

// amplitude_store<B>: B names its amplitude type (float, double or their complex forms), the real
// type under it, and whether it is complex.
template <class B>
concept amplitude_store = requires {
  typename B::scalar_type;
  typename B::real_type;
  { B::is_complex } -> std::convertible_to<bool>;
} && detail::is_backend_scalar<typename B::scalar_type> &&
    (B::is_complex == detail::scalar_traits<typename B::scalar_type>::is_complex);

// state_loader<B>: puts the state into |index> (set_basis_state) or into given 2^n amplitudes
// (set_amplitudes).
template <class B>
concept state_loader =
    amplitude_store<B> && requires(B& b, std::uint64_t index, std::span<const typename B::scalar_type> amplitudes) {
      b.set_basis_state(index);
      b.set_amplitudes(amplitudes);
    };

// state_reader<B>: reads the state without changing it: its width, one amplitude, all 2^n of them
// (to_dense), the norm, the probability that controls hold, a register's distribution.
template <class B>
concept state_reader = amplitude_store<B> && requires(const B& b, std::uint64_t index, std::span<const control> cs,
                                                      std::span<const qubit_index> qs) {
  { b.num_qubits() } -> std::convertible_to<std::size_t>;
  { b.amplitude(index) } -> std::same_as<typename B::scalar_type>;
  { b.to_dense() } -> std::same_as<std::vector<typename B::scalar_type>>;
  { b.norm_squared() } -> std::same_as<double>;
  { b.probability(cs) } -> std::same_as<double>;
  { b.distribution(qs) } -> std::same_as<std::vector<double>>;
};

// backend<B>: a simulator: B(n) is n qubits in |0...0>; it is movable, runs the five primitive ops
// (gate_sink, circuit/ops.hpp), and loads and reads states.
template <class B>
concept backend =
    std::constructible_from<B, std::size_t> && std::movable<B> && gate_sink<B> && state_loader<B> && state_reader<B>;

namespace detail {
// What backend_family hands to F::visit to see that it calls back.
struct visit_probe {
  template <class B>
  int operator()(std::type_identity<B>) const {
    return 0;
  }
};
}  // namespace detail

// backend_family<F>: a backend chosen as a type. F::name names it (e.g. on a command line);
// F::state<S> is its backend storing S; F::visit(width, real, f) calls f(std::type_identity<B>{})
// with the backend F runs a `width`-qubit circuit on (real amplitudes when every gate is real);
// F::make<B>(n) builds that B for n qubits, for callers that run many states in parallel.
template <class F>
concept backend_family = requires(std::size_t n, bool real) {
  { F::name } -> std::convertible_to<std::string_view>;
  { F::visit(n, real, detail::visit_probe{}) } -> std::same_as<int>;
  { F::template make<typename F::template state<double>>(n) } -> std::same_as<typename F::template state<double>>;
} && backend<typename F::template state<double>> && backend<typename F::template state<std::complex<double>>>;

}  // namespace qrm
