// tests/support/random_programs.hpp: random programs with every op kind (random placements,
// positive and negative controls, unitary matrices), and running a program from a given state.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include <qrm/backends/dense.hpp>
#include <qrm/circuit/program.hpp>
#include <qrm/support/random.hpp>

#include "random_ops.hpp"

namespace qrm_test {

enum class op_kind { gate1, unitary, add, mux1, mux_ry, mux_unitary };
inline constexpr op_kind all_op_kinds[] = {op_kind::gate1, op_kind::unitary, op_kind::add,
                                           op_kind::mux1,  op_kind::mux_ry,  op_kind::mux_unitary};
inline const char* op_kind_name(op_kind k) {
  switch (k) {
    case op_kind::gate1: return "gate1";
    case op_kind::unitary: return "unitary";
    case op_kind::add: return "add";
    case op_kind::mux1: return "mux1";
    case op_kind::mux_ry: return "mux_ry";
    case op_kind::mux_unitary: return "mux_unitary";
  }
  return "?";
}

// Distinct qubits 0..n-1 in random order.
inline std::vector<qrm::qubit_index> shuffled_qubits(std::size_t n, qrm::rng& g) {
  std::vector<qrm::qubit_index> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = static_cast<qrm::qubit_index>(i);
  for (std::size_t i = n; i > 1; --i) std::swap(q[i - 1], q[g.below(i)]);
  return q;
}

// Takes `count` qubits from the back of the pool.
inline std::vector<qrm::qubit_index> take(std::vector<qrm::qubit_index>& pool, std::size_t count) {
  std::vector<qrm::qubit_index> r(pool.end() - static_cast<std::ptrdiff_t>(count), pool.end());
  pool.resize(pool.size() - count);
  return r;
}

inline std::vector<qrm::control> random_controls(std::vector<qrm::qubit_index>& pool, std::size_t max, qrm::rng& g) {
  const std::size_t count = g.below(std::min(max, pool.size()) + 1);
  std::vector<qrm::control> cs;
  for (qrm::qubit_index q : take(pool, count)) cs.push_back({q, g.below(2) == 1});
  return cs;
}

// A random named or general single-qubit unitary.
inline qrm::gate1 random_named_or_general(qrm::rng& g) {
  const double angle = 4.0 * std::acos(-1.0) * (g.uniform() - 0.5);
  switch (g.below(8)) {
    case 0: return qrm::gate::x();
    case 1: return qrm::gate::y();
    case 2: return qrm::gate::z();
    case 3: return qrm::gate::h();
    case 4: return qrm::gate::ry(angle);
    case 5: return qrm::gate::rz(angle);
    case 6: return qrm::gate::phase(angle);
    default: return random_gate1_unitary(g, true);
  }
}

// A real orthogonal matrix with entries 0 and +-1/2, 4 nonzeros per column (like the paper's
// coins): a signed permutation of rows and columns of the 4x4 block H (x) H / 2 pattern.
inline qrm::dense_matrix sparse_coin(std::size_t k, qrm::rng& g) {
  const std::size_t d = std::size_t{1} << k;
  qrm::dense_matrix m(d);
  // Blocks of 4: [[1,1,1,1],[1,-1,1,-1],[1,1,-1,-1],[1,-1,-1,1]] / 2 (orthogonal), placed on a
  // random permutation of rows and columns, with random column signs.
  std::vector<qrm::qubit_index> rows = shuffled_qubits(d, g), cols = shuffled_qubits(d, g);
  for (std::size_t b = 0; b + 4 <= d; b += 4)
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) {
        const int sign = (std::popcount(i & j) % 2 == 0) ? 1 : -1;
        m(rows[b + i], cols[b + j]) = 0.5 * sign;
      }
  for (std::size_t c = 0; c < d; ++c)
    if (g.below(2))
      for (std::size_t r = 0; r < d; ++r) m(r, c) = -m(r, c);
  return m;
}

// One random op of kind `kind` on n qubits (n >= 3).
inline qrm::op::any random_op(op_kind kind, std::size_t n, qrm::rng& g) {
  std::vector<qrm::qubit_index> pool = shuffled_qubits(n, g);
  switch (kind) {
    case op_kind::gate1: {
      const qrm::qubit_index t = take(pool, 1)[0];
      auto cs = random_controls(pool, 4, g);
      return qrm::op::gate1_op{random_named_or_general(g), t, cs};
    }
    case op_kind::unitary: {
      const std::size_t k = 1 + g.below(std::min<std::size_t>(3, n - 1));
      auto ts = take(pool, k);
      auto cs = random_controls(pool, 3, g);
      qrm::dense_matrix m = (k >= 2 && g.below(3) == 0) ? sparse_coin(k, g) : random_unitary(k, g, g.below(2) == 1);
      return qrm::op::unitary_op{m, ts, cs};
    }
    case op_kind::add: {
      const std::size_t k = 1 + g.below(std::min<std::size_t>(4, n - 1));
      auto bits = take(pool, k);
      auto cs = random_controls(pool, 3, g);
      // Nonzero modulo 2^k, plus a random multiple of 2^k (negative too): the wrap is tested.
      const auto dim = static_cast<std::int64_t>(std::uint64_t{1} << k);
      const auto c = 1 + static_cast<std::int64_t>(g.below(static_cast<std::uint64_t>(dim - 1))) +
                     dim * (static_cast<std::int64_t>(g.below(5)) - 2);
      return qrm::op::add_op{c, bits, cs};
    }
    case op_kind::mux1:
    case op_kind::mux_ry: {
      const qrm::qubit_index t = take(pool, 1)[0];
      const std::size_t m = 1 + g.below(std::min<std::size_t>(3, pool.size()));
      auto sel = take(pool, m);
      auto cs = random_controls(pool, 2, g);
      std::vector<qrm::mux1_entry> es;
      for (std::uint64_t s = 0; s < (std::uint64_t{1} << m); ++s)
        if (g.below(4) != 0)
          es.push_back({s, kind == op_kind::mux_ry ? qrm::gate::ry(6.0 * (g.uniform() - 0.5)) : random_named_or_general(g)});
      return qrm::op::mux1_op{es, t, sel, cs};
    }
    case op_kind::mux_unitary: {
      const std::size_t k = 1 + g.below(std::min<std::size_t>(2, n - 2));
      auto ts = take(pool, k);
      const std::size_t m = 1 + g.below(std::min<std::size_t>(2, pool.size()));
      auto sel = take(pool, m);
      auto cs = random_controls(pool, 1, g);
      std::vector<qrm::dense_matrix> ms;
      const std::size_t count = 1 + g.below(3);
      for (std::size_t i = 0; i < count; ++i)
        ms.push_back(k >= 2 && g.below(2) == 0 ? sparse_coin(k, g) : random_unitary(k, g, g.below(2) == 1));
      std::vector<qrm::mux_unitary_entry> es;
      for (std::uint64_t s = 0; s < (std::uint64_t{1} << m); ++s)
        if (g.below(4) != 0) es.push_back({s, static_cast<std::uint32_t>(g.below(count))});
      return qrm::op::mux_unitary_op{ms, es, ts, sel, cs};
    }
  }
  return qrm::op::gate1_op{qrm::gate::x(), 0, {}};
}

// A random normalised state of n qubits.
inline std::vector<std::complex<double>> random_unit_state(std::size_t n, qrm::rng& g) {
  auto v = random_state(n, g, true);
  double norm = 0;
  for (const auto& a : v) norm += std::norm(a);
  for (auto& a : v) a /= std::sqrt(norm);
  return v;
}

// p run on the dense backend from `initial` (padded with zeros to p's width: extra qubits |0>).
inline std::vector<std::complex<double>> run_from(const qrm::program& p, const std::vector<std::complex<double>>& initial) {
  qrm::dense_options o;
  o.threads = 1;
  qrm::state_vector<> s(p.width(), o);
  std::vector<std::complex<double>> v(s.size());
  std::copy(initial.begin(), initial.end(), v.begin());
  s.set_amplitudes(v);
  qrm::run(s, p);
  return {s.amplitudes().begin(), s.amplitudes().end()};
}

}  // namespace qrm_test
