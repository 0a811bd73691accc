// tests/support/reference.hpp: a deliberately naive simulator, written from the definitions of
// the primitive operations (each basis state is scattered through the operator column by
// column), sharing no code with the backends' kernels. Backends are tested against it.
#pragma once

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include <qrm/circuit/ops.hpp>

namespace qrm_test {

using qrm::complex;
using qrm::qubit_index;

inline bool bit_of(std::uint64_t i, qubit_index q) { return ((i >> q) & 1u) != 0; }

inline bool controls_hold(std::uint64_t i, std::span<const qrm::control> cs) {
  for (const auto& c : cs)
    if (bit_of(i, c.qubit) != c.value) return false;
  return true;
}

// Value of the register `bits` (least significant first) in basis state i.
inline std::uint64_t read_bits(std::uint64_t i, std::span<const qubit_index> bits) {
  std::uint64_t v = 0;
  for (std::size_t k = 0; k < bits.size(); ++k) v |= std::uint64_t{bit_of(i, bits[k])} << k;
  return v;
}
inline std::uint64_t write_bits(std::uint64_t i, std::span<const qubit_index> bits, std::uint64_t v) {
  for (std::size_t k = 0; k < bits.size(); ++k) {
    i &= ~(std::uint64_t{1} << bits[k]);
    i |= ((v >> k) & 1u) << bits[k];
  }
  return i;
}

struct reference_state {
  std::size_t n;
  std::vector<complex> amp;
  explicit reference_state(std::size_t qubits) : n(qubits), amp(std::size_t{1} << qubits) { amp[0] = 1; }
  std::size_t num_qubits() const { return n; }

  // out[write(j, targets = r)] += M[r][read(j, targets)] * in[j] where controls hold.
  template <class M>
  void scatter(std::span<const qubit_index> targets, std::size_t dim, M matrix, std::span<const qrm::control> cs) {
    std::vector<complex> out(amp.size());
    for (std::uint64_t j = 0; j < amp.size(); ++j) {
      if (!controls_hold(j, cs)) {
        out[j] += amp[j];
        continue;
      }
      const std::uint64_t c = read_bits(j, targets);
      for (std::uint64_t r = 0; r < dim; ++r) out[write_bits(j, targets, r)] += matrix(j, r, c) * amp[j];
    }
    amp = out;
  }

  void apply_gate1(const qrm::gate1& g, qubit_index t, std::span<const qrm::control> cs) {
    scatter(std::span<const qubit_index>(&t, 1), 2,
            [&](std::uint64_t, std::uint64_t r, std::uint64_t c) { return g.m[r][c]; }, cs);
  }
  void apply_unitary(const qrm::dense_matrix& m, std::span<const qubit_index> ts, std::span<const qrm::control> cs) {
    scatter(ts, m.dim, [&](std::uint64_t, std::uint64_t r, std::uint64_t c) { return m(r, c); }, cs);
  }
  void apply_add(std::int64_t k, std::span<const qubit_index> bits, std::span<const qrm::control> cs) {
    const std::uint64_t dim = std::uint64_t{1} << bits.size();
    scatter(bits, dim,
            [&](std::uint64_t, std::uint64_t r, std::uint64_t c) {
              const std::uint64_t moved = (c + static_cast<std::uint64_t>(k)) & (dim - 1);
              return complex(r == moved ? 1.0 : 0.0);
            },
            cs);
  }
  void apply_mux1(std::span<const qrm::mux1_entry> es, qubit_index t, std::span<const qubit_index> sel,
                  std::span<const qrm::control> cs) {
    scatter(std::span<const qubit_index>(&t, 1), 2,
            [&](std::uint64_t j, std::uint64_t r, std::uint64_t c) {
              const std::uint64_t s = read_bits(j, sel);
              for (const auto& e : es)
                if (e.select == s) return e.gate.m[r][c];
              return complex(r == c ? 1.0 : 0.0);
            },
            cs);
  }
  void apply_mux_unitary(std::span<const qrm::dense_matrix> ms, std::span<const qrm::mux_unitary_entry> es,
                         std::span<const qubit_index> ts, std::span<const qubit_index> sel,
                         std::span<const qrm::control> cs) {
    scatter(ts, std::size_t{1} << ts.size(),
            [&](std::uint64_t j, std::uint64_t r, std::uint64_t c) {
              const std::uint64_t s = read_bits(j, sel);
              for (const auto& e : es)
                if (e.select == s) return ms[e.matrix](r, c);
              return complex(r == c ? 1.0 : 0.0);
            },
            cs);
  }
};

}  // namespace qrm_test
