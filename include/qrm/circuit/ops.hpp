// qrm/circuit/ops.hpp: the run-time instruction set every backend implements.
//
// Static gate templates (gates.hpp) and run-time programs (program.hpp) both lower to five
// primitive operations; a backend is any type with the five `apply_*` members (see
// `qrm::gate_sink`). Qubit indices are run-time numbers here; the compile-time layer computes
// them from layouts as constants.
#pragma once

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace qrm {

using qubit_index = std::uint32_t;
using complex = std::complex<double>;

// A control: the operation acts only where `qubit` holds `value`.
struct control {
  qubit_index qubit;
  bool value = true;
  constexpr bool operator==(const control&) const = default;
};

// Single-qubit gate kinds; the kind lets kernels specialise (permutation, diagonal, real).
enum class gate1_kind : unsigned char { x, y, z, h, ry, rz, phase, u };

constexpr std::string_view gate1_name(gate1_kind k) {
  switch (k) {
    case gate1_kind::x: return "x";
    case gate1_kind::y: return "y";
    case gate1_kind::z: return "z";
    case gate1_kind::h: return "h";
    case gate1_kind::ry: return "ry";
    case gate1_kind::rz: return "rz";
    case gate1_kind::phase: return "p";
    case gate1_kind::u: return "u";
  }
  return "?";
}

// gate1: a 2x2 matrix m (row-major, U|c> = sum_r m[r][c] |r>) with its kind and angle.
struct gate1 {
  gate1_kind kind = gate1_kind::u;
  double angle = 0.0;  // ry, rz, phase
  complex m[2][2] = {{1.0, 0.0}, {0.0, 1.0}};

  constexpr bool is_real() const {
    return m[0][0].imag() == 0 && m[0][1].imag() == 0 && m[1][0].imag() == 0 && m[1][1].imag() == 0;
  }
  constexpr bool is_diagonal() const { return m[0][1] == complex{} && m[1][0] == complex{}; }
  constexpr bool is_identity() const { return is_diagonal() && m[0][0] == complex{1.0} && m[1][1] == complex{1.0}; }
};

// Constructors for the named single-qubit gates.
namespace gate {
inline gate1 x() { return {gate1_kind::x, 0.0, {{0.0, 1.0}, {1.0, 0.0}}}; }
inline gate1 y() { return {gate1_kind::y, 0.0, {{0.0, complex{0, -1}}, {complex{0, 1}, 0.0}}}; }
inline gate1 z() { return {gate1_kind::z, 0.0, {{1.0, 0.0}, {0.0, -1.0}}}; }
template <int = 0>
inline gate1 h() {
  const double r = 1.0 / std::sqrt(2.0);
  return {gate1_kind::h, 0.0, {{r, r}, {r, -r}}};
}
// Ry(theta) = [[cos t/2, -sin t/2], [sin t/2, cos t/2]]; Ry(2 asin sqrt v)|0> has P(|1>) = v.
template <int = 0>
inline gate1 ry(double theta) {
  const double c = std::cos(theta / 2), s = std::sin(theta / 2);
  return {gate1_kind::ry, theta, {{c, -s}, {s, c}}};
}
template <int = 0>
inline gate1 rz(double theta) {
  return {gate1_kind::rz, theta, {{std::polar(1.0, -theta / 2), 0.0}, {0.0, std::polar(1.0, theta / 2)}}};
}
// phase(theta) = diag(1, e^{i theta}).
inline gate1 phase(double theta) { return {gate1_kind::phase, theta, {{1.0, 0.0}, {0.0, std::polar(1.0, theta)}}}; }
template <int = 0>
inline gate1 u(complex m00, complex m01, complex m10, complex m11) {
  return {gate1_kind::u, 0.0, {{m00, m01}, {m10, m11}}};
}
}  // namespace gate

// The conjugate transpose of g, keeping its kind (ry(t) -> ry(-t)).
template <int = 0>
inline gate1 adjoint(const gate1& g) {
  gate1 r = g;
  r.angle = -g.angle;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) r.m[i][j] = std::conj(g.m[j][i]);
  return r;
}

// dense_matrix: a 2^k x 2^k matrix on k target qubits, row-major; target j is bit j of the index.
struct dense_matrix {
  std::size_t dim = 0;
  std::vector<complex> data;

  dense_matrix() = default;
  explicit dense_matrix(std::size_t d) : dim(d), data(d * d) {}
  complex& operator()(std::size_t r, std::size_t c) { return data[r * dim + c]; }
  const complex& operator()(std::size_t r, std::size_t c) const { return data[r * dim + c]; }
  template <int = 0>
  bool is_real() const {
    for (const complex& z : data)
      if (z.imag() != 0) return false;
    return true;
  }
  template <int = 0>
  static dense_matrix of(const gate1& g) {  // the 2x2 matrix of a 1-qubit gate
    dense_matrix m(2);
    for (std::size_t r = 0; r < 2; ++r)
      for (std::size_t c = 0; c < 2; ++c) m(r, c) = g.m[r][c];
    return m;
  }
  template <int = 0>
  static dense_matrix identity(std::size_t d) {
    dense_matrix m(d);
    for (std::size_t i = 0; i < d; ++i) m(i, i) = 1.0;
    return m;
  }
  bool operator==(const dense_matrix&) const = default;
};

template <int = 0>
inline dense_matrix adjoint(const dense_matrix& m) {
  dense_matrix r(m.dim);
  for (std::size_t i = 0; i < m.dim; ++i)
    for (std::size_t j = 0; j < m.dim; ++j) r(i, j) = std::conj(m(j, i));
  return r;
}

template <int = 0>
inline dense_matrix operator*(const dense_matrix& a, const dense_matrix& b) {
  if (a.dim != b.dim) throw std::invalid_argument("dense_matrix product: dimensions differ");
  dense_matrix r(a.dim);
  for (std::size_t i = 0; i < a.dim; ++i)
    for (std::size_t k = 0; k < a.dim; ++k) {
      const complex aik = a(i, k);
      if (aik == complex{}) continue;
      for (std::size_t j = 0; j < a.dim; ++j) r(i, j) += aik * b(k, j);
    }
  return r;
}

// Largest |(U^dagger U - I)_ij|: how far m is from unitary.
template <int = 0>
inline double unitarity_error(const dense_matrix& m) {
  double worst = 0;
  for (std::size_t i = 0; i < m.dim; ++i)
    for (std::size_t j = 0; j < m.dim; ++j) {
      complex s{};
      for (std::size_t k = 0; k < m.dim; ++k) s += std::conj(m(k, i)) * m(k, j);
      worst = std::max(worst, std::abs(s - complex(i == j ? 1.0 : 0.0)));
    }
  return worst;
}

// Entries of multiplexed (uniformly controlled) operations: where the select qubits read
// `select`, apply the entry's gate; select values without an entry get the identity.
struct mux1_entry {
  std::uint64_t select;
  gate1 gate;
};
struct mux_unitary_entry {
  std::uint64_t select;
  std::uint32_t matrix;  // index into the operation's matrix list
};

// gate_sink: what a backend (or a recorder, or a metrics counter) must accept.
//   apply_gate1:        a 2x2 gate on `target` where all controls hold.
//   apply_unitary:      a 2^k x 2^k matrix on `targets` (target j = bit j of the matrix index).
//   apply_add:          |v> -> |v + constant mod 2^k> on the register `bits` (least significant first).
//   apply_mux1:         per select value, one entry's 2x2 gate on `target`.
//   apply_mux_unitary:  per select value, one entry's matrix on `targets`.
template <class S>
concept gate_sink = requires(S& s, const gate1& g, qubit_index q, std::span<const qubit_index> qs,
                             std::span<const control> cs, const dense_matrix& m, std::int64_t c,
                             std::span<const mux1_entry> e1, std::span<const dense_matrix> ms,
                             std::span<const mux_unitary_entry> ek) {
  s.apply_gate1(g, q, cs);
  s.apply_unitary(m, qs, cs);
  s.apply_add(c, qs, cs);
  s.apply_mux1(e1, q, qs, cs);
  s.apply_mux_unitary(ms, ek, qs, qs, cs);
};

// enter_layer(sink, name): the ops that follow belong to the layer `name` (a string literal,
// e.g. the walk's "coin"). A sink that records (program) keeps the label with each op, so the
// layers survive lowering; a backend has no such member and ignores it.
template <class S>
void enter_layer(S& sink, const char* name) {
  if constexpr (requires { sink.enter_layer(name); }) sink.enter_layer(name);
}

}  // namespace qrm
