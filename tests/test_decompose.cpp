// Decomposition into single-qubit gates and CNOTs: equivalence (state by state, global phase
// included), clean ancillas, the output gate set, and textbook gate counts.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include <qrm/circuit/decompose.hpp>
#include <qrm/circuit/program.hpp>

#include "support/random_programs.hpp"
#include "support/reference.hpp"

namespace {

using qrm::control;
using qrm::qubit_index;
using cvec = std::vector<std::complex<double>>;

// Every op is an uncontrolled single-qubit gate or a CNOT (X with one control of value 1), or,
// with keep_toffoli, X with two controls of value 1.
bool only_allowed_gates(const qrm::program& p, bool toffolis_allowed) {
  for (const qrm::op::any& o : p.ops()) {
    const auto* g = std::get_if<qrm::op::gate1_op>(&o);
    if (g == nullptr) return false;
    if (g->controls.empty()) continue;
    if (!qrm::detail::is_pauli_x(g->gate)) return false;
    if (g->controls.size() > (toffolis_allowed ? 2u : 1u)) return false;
    for (const control& c : g->controls)
      if (!c.value) return false;
  }
  return true;
}

// The original program on the naive reference simulator from `initial`.
cvec reference_run(const qrm::program& p, const cvec& initial) {
  qrm_test::reference_state r(p.width());
  r.amp = initial;
  p.emit(r);
  return r.amp;
}

struct comparison {
  double amplitude_error = 0;     // largest |a_i - b_i| on the program's qubits
  double ancilla_probability = 0; // probability that some ancilla is |1>
};

// decompose(p) run from `initial` (ancillas |0>) against p on the reference simulator.
comparison compare(const qrm::program& p, const qrm::decomposition_result& d, const cvec& initial) {
  const cvec want = reference_run(p, initial);
  const cvec got = qrm_test::run_from(d.circuit, initial);
  comparison c;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (i < want.size()) c.amplitude_error = std::max(c.amplitude_error, std::abs(got[i] - want[i]));
    else c.ancilla_probability += std::norm(got[i]);
  }
  return c;
}

qrm::program single_op_program(std::size_t n, qrm::op::any o) {
  qrm::program p(n);
  p.push(std::move(o));
  return p;
}

std::size_t cnots(const qrm::program& p, qrm::decompose_options o = {}) { return qrm::decomposed_metrics(p, o).cnot_count; }

qrm::program mcx(std::size_t controls) {
  qrm::program p(controls + 1);
  std::vector<control> cs;
  for (std::size_t i = 0; i < controls; ++i) cs.push_back({static_cast<qubit_index>(i), true});
  p.apply_gate1(qrm::gate::x(), static_cast<qubit_index>(controls), cs);
  return p;
}

const qrm::decompose_options option_sets[] = {
    {false, false, true},   // default
    {false, false, false},  // no peephole
    {false, true, true},    // relative-phase Toffolis
    {true, false, true},    // keep Toffolis
};

}  // namespace

TEST_CASE("every op kind decomposes exactly, ancillas return to |0>, only 1q gates and CNOTs remain") {
  qrm::rng g(20261122);
  for (const qrm::decompose_options& opt : option_sets) {
    for (qrm_test::op_kind kind : qrm_test::all_op_kinds) {
      for (std::size_t n = 3; n <= 7; ++n) {
        for (int rep = 0; rep < 5; ++rep) {
          const qrm::program p = single_op_program(n, qrm_test::random_op(kind, n, g));
          const qrm::decomposition_result d = qrm::decompose(p, opt);
          const std::string kind_name = qrm_test::op_kind_name(kind);
          CAPTURE(kind_name);
          CAPTURE(n);
          CAPTURE(opt.keep_toffoli);
          CAPTURE(opt.relative_phase_toffoli);
          CAPTURE(opt.optimize);
          CHECK(d.circuit.width() == n + d.ancillas);
          CHECK(only_allowed_gates(d.circuit, opt.keep_toffoli));
          const comparison c = compare(p, d, qrm_test::random_unit_state(n, g));
          // 1e-12: each of up to a few thousand gates rounds O(1) amplitudes at 1e-16, plus at
          // most 1e-14 per dropped near-zero entry; a wrong phase or rule is O(1).
          CHECK(c.amplitude_error < 1e-12);
          // Ancilla amplitudes come only from rounding (~1e-15), so their probability is ~1e-30;
          // an ancilla left in |1> has probability O(1).
          CHECK(c.ancilla_probability < 1e-24);
        }
      }
    }
  }
}

TEST_CASE("whole random programs decompose exactly") {
  qrm::rng g(77);
  for (std::size_t n = 3; n <= 7; ++n) {
    qrm::program p(n);
    for (int i = 0; i < 12; ++i) p.push(qrm_test::random_op(qrm_test::all_op_kinds[g.below(6)], n, g));
    const qrm::decomposition_result d = qrm::decompose(p);
    CHECK(only_allowed_gates(d.circuit, false));
    const comparison c = compare(p, d, qrm_test::random_unit_state(n, g));
    CHECK(c.amplitude_error < 1e-12);  // as above
    CHECK(c.ancilla_probability < 1e-24);
  }
}

TEST_CASE("the global phase of a controlled gate is kept") {
  // diag(e^{ia}, e^{ia}) controlled by one qubit is a phase on the control, which a
  // decomposition that drops global phases would lose.
  const std::complex<double> z = std::polar(1.0, 0.7);
  for (std::size_t controls = 0; controls <= 3; ++controls) {
    qrm::program p(controls + 1);
    std::vector<control> cs;
    for (std::size_t i = 0; i < controls; ++i) cs.push_back({static_cast<qubit_index>(i + 1), i % 2 == 0});
    p.apply_gate1(qrm::gate::u(z, 0.0, 0.0, z), 0, cs);
    qrm::rng g(controls);
    const comparison c = compare(p, qrm::decompose(p), qrm_test::random_unit_state(controls + 1, g));
    CHECK(c.amplitude_error < 1e-12);  // see above
  }
}

TEST_CASE("textbook CNOT counts") {
  const qrm::decompose_options raw{false, false, false}, rel{false, true, true};
  // Toffoli = 6 CNOTs (N&C Fig. 4.9), with or without the peephole pass.
  CHECK(cnots(mcx(2)) == 6);
  CHECK(cnots(mcx(2), raw) == 6);
  CHECK(qrm::decomposed_metrics(mcx(2)).ancillas == 0);
  // C^k X: k-2 Toffolis compute an AND, one Toffoli hits the target, k-2 undo: 6 (2k - 3).
  for (std::size_t k = 3; k <= 6; ++k) {
    CAPTURE(k);
    CHECK(cnots(mcx(k)) == 6 * (2 * k - 3));
    CHECK(qrm::decomposed_metrics(mcx(k)).ancillas == k - 2);
    // Relative-phase Toffolis (3 CNOTs) for the 2 (k-2) AND gates: 6 (k-2) + 6.
    CHECK(cnots(mcx(k), rel) == 6 * (k - 2) + 6);
  }
  // C^k U for a generic U: k-1 Toffolis compute the AND, a controlled-U (2), k-1 undo:
  // 12 (k-1) + 2; with relative-phase Toffolis 6 (k-1) + 2.
  {
    qrm::rng h(13);
    for (std::size_t k = 2; k <= 5; ++k) {
      CAPTURE(k);
      qrm::program p(k + 1);
      std::vector<control> cs;
      for (std::size_t i = 0; i < k; ++i) cs.push_back({static_cast<qubit_index>(i + 1), true});
      p.apply_gate1(qrm_test::random_gate1_unitary(h, true), 0, cs);
      CHECK(cnots(p) == 12 * (k - 1) + 2);
      CHECK(cnots(p, rel) == 6 * (k - 1) + 2);
      CHECK(qrm::decomposed_metrics(p).ancillas == k - 1);
    }
  }
  // Controlled-U: 2 CNOTs for a generic U (N&C Corollary 4.2), 1 for CNOT and for trace-zero
  // gates (CZ = H CNOT H), 0 for a controlled global phase.
  qrm::rng g(5);
  for (int i = 0; i < 10; ++i) {
    qrm::program p(2);
    const control c{0, true};
    p.apply_gate1(qrm_test::random_gate1_unitary(g, true), 1, std::span<const control>(&c, 1));
    CHECK(cnots(p) == 2);
    CHECK(qrm::decomposed_metrics(p).ancillas == 0);
  }
  {
    qrm::program p(2);
    const control c{0, true};
    p.apply_gate1(qrm::gate::ry(0.3), 1, std::span<const control>(&c, 1));
    CHECK(cnots(p) == 2);
  }
  for (const qrm::gate1& u : {qrm::gate::x(), qrm::gate::y(), qrm::gate::z(), qrm::gate::h()}) {
    qrm::program p(2);
    const control c{1, true};
    p.apply_gate1(u, 0, std::span<const control>(&c, 1));
    CHECK(cnots(p) == 1);
  }
  // Add 1 on 3 qubits: X, CNOT, Toffoli = 7 CNOTs.
  {
    qrm::program p(3);
    const qubit_index bits[] = {0, 1, 2};
    p.apply_add(1, bits, {});
    CHECK(cnots(p) == 7);
  }
  // Uniformly controlled Ry with m select qubits and all 2^m entries: 2^m CNOTs and 2^m Ry
  // (Mottonen et al. 2004).
  // Random angles: structured ones (e.g. linear in s) give exactly zero transformed angles,
  // whose identity rotations are skipped.
  qrm::rng angles(21);
  for (std::size_t m = 1; m <= 6; ++m) {
    CAPTURE(m);
    qrm::program p(m + 1);
    std::vector<qrm::mux1_entry> es;
    for (std::uint64_t s = 0; s < (std::uint64_t{1} << m); ++s) es.push_back({s, qrm::gate::ry(6 * (angles.uniform() - 0.5))});
    std::vector<qubit_index> sel;
    for (std::size_t i = 0; i < m; ++i) sel.push_back(static_cast<qubit_index>(i + 1));
    p.apply_mux1(es, 0, sel, {});
    const auto d = qrm::decomposed_metrics(p, raw);
    CHECK(d.cnot_count == (std::size_t{1} << m));
    CHECK(d.single_qubit_count == (std::size_t{1} << m));
    CHECK(d.ancillas == 0);
    qrm::rng h(m);
    const comparison c = compare(p, qrm::decompose(p), qrm_test::random_unit_state(m + 1, h));
    CHECK(c.amplitude_error < 1e-12);  // see above
  }
}

TEST_CASE("two-level factors multiply back to the matrix and number at most d(d-1)/2 + d") {
  qrm::rng g(3);
  for (std::size_t k = 1; k <= 4; ++k) {
    for (int rep = 0; rep < 3; ++rep) {
      const qrm::dense_matrix u = (k >= 2 && rep == 2) ? qrm_test::sparse_coin(k, g) : qrm_test::random_unitary(k, g, rep == 1);
      const auto factors = qrm::detail::two_level_factors(u);
      const std::size_t d = u.dim;
      // Each factor written out as a full d x d matrix, multiplied in time order.
      qrm::dense_matrix prod = qrm::dense_matrix::identity(d);
      for (const auto& f : factors) {
        qrm::dense_matrix full = qrm::dense_matrix::identity(d);
        full(f.s, f.s) = f.g.m[0][0];
        full(f.s, f.t) = f.g.m[0][1];
        full(f.t, f.s) = f.g.m[1][0];
        full(f.t, f.t) = f.g.m[1][1];
        prod = full * prod;
      }
      double err = 0;
      for (std::size_t i = 0; i < d * d; ++i) err = std::max(err, std::abs(prod.data[i] - u.data[i]));
      CHECK(err < 1e-13);  // a few dozen roundings of O(1) entries
      // N&C: at most d(d-1)/2 eliminations, plus at most d diagonal phase fixes.
      CHECK(factors.size() <= d * (d - 1) / 2 + d);
    }
  }
}

TEST_CASE("Mottonen angles reproduce every entry's rotation") {
  // Independent check of the transform: for select value s, the rotations seen by the target
  // are theta_i with sign (-1)^{popcount(s & gray(i))}; their sum must be alpha_s.
  qrm::rng g(9);
  for (std::size_t m = 1; m <= 5; ++m) {
    const std::size_t n = std::size_t{1} << m;
    std::vector<double> alpha(n);
    for (auto& a : alpha) a = 6 * (g.uniform() - 0.5);
    const auto theta = qrm::detail::mottonen_angles(alpha);
    for (std::size_t s = 0; s < n; ++s) {
      double sum = 0;
      for (std::size_t i = 0; i < n; ++i) sum += (std::popcount(s & (i ^ (i >> 1))) % 2 ? -1.0 : 1.0) * theta[i];
      CHECK(std::abs(sum - alpha[s]) < 1e-13);  // n additions of O(1) numbers
    }
  }
}

TEST_CASE("decomposed_metrics agrees with the decomposed program") {
  qrm::rng g(11);
  qrm::program p(6);
  for (int i = 0; i < 10; ++i) p.push(qrm_test::random_op(qrm_test::all_op_kinds[g.below(6)], 6, g));
  const auto d = qrm::decompose(p);
  const auto m = qrm::decomposed_metrics(p);
  const auto logical = qrm::circuit_metrics_of(d.circuit);
  CHECK(m.depth == logical.logical_depth);
  CHECK(m.width == d.circuit.width());
  CHECK(m.gate_count == d.circuit.ops().size());
  CHECK(m.cnot_count + m.single_qubit_count == m.gate_count);
  CHECK(m.cnot_count == logical.by_kind.at("cx"));
}

TEST_CASE("non-unitary input is rejected with the op and the error") {
  qrm::program p(2);
  const qubit_index ts[] = {0, 1};
  qrm::dense_matrix m = qrm::dense_matrix::identity(4);
  m(0, 0) = 2.0;
  p.apply_unitary(m, ts, {});
  CHECK_THROWS_WITH_AS(qrm::decompose(p), doctest::Contains("op 0: the 4x4 matrix is not unitary"), std::invalid_argument);
  qrm::program q(1);
  q.apply_gate1(qrm::gate::u(1.0, 1.0, 0.0, 1.0), 0, {});
  CHECK_THROWS_WITH_AS(qrm::decompose(q), doctest::Contains("not unitary"), std::invalid_argument);
  // A multiplexed op listing a select value twice (the backend refuses it too).
  qrm::program r(2);
  r.ops().push_back(qrm::op::mux1_op{{{1, qrm::gate::ry(0.1)}, {1, qrm::gate::ry(0.2)}}, 0, {1}, {}});
  CHECK_THROWS_WITH_AS(qrm::decompose(r), doctest::Contains("op 0: select value 1 has two entries"), std::invalid_argument);
}
