// Fault-tolerant resources (qrm/resources): Clifford+T counts of circuits whose costs are known
// by hand, the surface-code plan's formulas, monotonicity in the error budget, and a QASM round
// trip that must not change a count.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <qrm/qrm.hpp>
#include <vector>

#include "support/errors.hpp"

namespace {

using qrm::control;
using qrm::program;

program with_gate(std::size_t width, const qrm::gate1& g, qrm::qubit_index target, std::vector<control> cs = {}) {
  program p(width);
  p.apply_gate1(g, target, cs);
  return p;
}

qrm::clifford_t_counts counts_of(const program& p, qrm::clifford_t_rules rules = {}) {
  return qrm::clifford_t_counts_of(qrm::clifford_t_lowering(p), rules);
}

// A paper_4x4 walk circuit of 2 steps (small, with Toffolis and rotations).
qrm::walk_program small_walk() {
  const qrm::scene sc = qrm::paper_4x4();
  const qrm::walk_model m(sc, qrm::king_2d());
  qrm::walk_options o;
  o.steps = 2;
  return qrm::make_walk_program(m, m.light_map_start({1, 1, 0}), o);
}

qrm::t_cost t_of(const program& p, qrm::clifford_t_rules rules = {}, double eps = 1e-10) {
  const program lowered = qrm::clifford_t_lowering(p);
  return qrm::t_cost_of(lowered, qrm::clifford_t_counts_of(lowered, rules), rules, eps);
}

}  // namespace

TEST_CASE("Clifford+T: single-qubit gates are Clifford, T or a rotation as their angles say") {
  using namespace qrm::gate;
  constexpr double pi = std::numbers::pi;
  struct row {
    qrm::gate1 g;
    std::size_t t_gates, rotations;
  };
  for (const row& r : {row{h(), 0, 0}, row{x(), 0, 0}, row{z(), 0, 0}, row{phase(pi / 2), 0, 0}, row{ry(pi / 2), 0, 0},
                       row{phase(pi / 4), 1, 0}, row{phase(-pi / 4), 1, 0}, row{rz(3 * pi / 4), 1, 0},
                       row{ry(0.3), 0, 1}, row{rz(1.0), 0, 1}}) {
    const auto c = counts_of(with_gate(1, r.g, 0));
    CHECK(c.t_gates == r.t_gates);
    CHECK(c.rotation_count == r.rotations);
    CHECK(c.cnot_count == 0);
  }
  // H Rz(0.3) H = Rx(0.3): one rotation, not three (the Euler angles that matter are counted).
  program p(1);
  p.apply_gate1(h(), 0, {});
  p.apply_gate1(rz(0.3), 0, {});
  p.apply_gate1(h(), 0, {});
  CHECK(counts_of(p).rotation_count == 1);
}

TEST_CASE("Clifford+T: a Toffoli, C^k X on the ancilla ladder, and Ry at a given error, against hand counts") {
  const std::vector<control> two{{0, true}, {1, true}};
  const program toffoli = with_gate(3, qrm::gate::x(), 2, two);
  const auto c7 = counts_of(toffoli);
  CHECK(c7.toffoli_count == 1);
  CHECK(c7.logical_qubits == 3);
  CHECK(t_of(toffoli).t_count == 7);
  CHECK(t_of(toffoli).t_depth == 3);
  const qrm::clifford_t_rules four{qrm::toffoli_costing::four_t, qrm::rotation_synthesis::mixed_fallback};
  CHECK(counts_of(toffoli, four).logical_qubits == 4);  // Jones's ancilla
  CHECK(t_of(toffoli, four).t_count == 4);
  CHECK(t_of(toffoli, four).t_depth == 1);

  // C^k X: AND of the first k-1 controls into k-2 ancillas (k-2 Toffolis), one Toffoli onto the
  // target, the k-2 undone: 2k-3 Toffolis, 7 (2k-3) T gates, k+1 + k-2 qubits.
  for (unsigned k : {3u, 4u, 5u}) {
    std::vector<control> cs;
    for (unsigned i = 0; i < k; ++i) cs.push_back({i, true});
    const program p = with_gate(k + 1, qrm::gate::x(), k, cs);
    const auto c = counts_of(p);
    CHECK(c.toffoli_count == 2 * k - 3);
    CHECK(c.logical_qubits == 2 * k - 1);
    CHECK(t_of(p).t_count == 7 * (2 * k - 3));
    CHECK(t_of(p).t_depth == 3 * (2 * k - 3));  // each Toffoli of the ladder waits for the one before
  }

  // Ry(0.3) to 1e-10: mixed fallback ceil(0.53 * 33.2193 + 5.3) = ceil(22.906) = 23;
  // Ross-Selinger ceil(3 * 33.2193) = ceil(99.658) = 100.
  const program ry = with_gate(1, qrm::gate::ry(0.3), 0);
  CHECK(t_of(ry).t_count == 23);
  CHECK(t_of(ry).t_depth == 23);
  CHECK(t_of(ry, {qrm::toffoli_costing::seven_t, qrm::rotation_synthesis::ross_selinger}).t_count == 100);
  CHECK(qrm_test::error_of([] { (void)qrm::t_per_rotation(qrm::rotation_synthesis::mixed_fallback, 0.0); })
            .find("eps must be in (0, 1)") != std::string::npos);
}

TEST_CASE("Clifford+T: a lowered walk circuit read back from QASM costs the same") {
  const auto w = small_walk();
  const program lowered = qrm::clifford_t_lowering(w.circuit);
  const program back = qrm::from_qasm(qrm::to_qasm(lowered));
  const auto a = qrm::clifford_t_counts_of(lowered), b = qrm::clifford_t_counts_of(back);
  CHECK(a.logical_qubits == b.logical_qubits);
  CHECK(a.cnot_count == b.cnot_count);
  CHECK(a.cnot_depth == b.cnot_depth);
  CHECK(a.toffoli_count == b.toffoli_count);
  CHECK(a.t_gates == b.t_gates);
  CHECK(a.rotation_count == b.rotation_count);
  CHECK(a.clifford_1q_count == b.clifford_1q_count);
  const auto ta = qrm::t_cost_of(lowered, a, {}, 1e-12), tb = qrm::t_cost_of(back, b, {}, 1e-12);
  CHECK(ta.t_count == tb.t_count);
  CHECK(ta.t_depth == tb.t_depth);
  CHECK(a.toffoli_count > 0);
  CHECK(a.rotation_count > 0);
}

TEST_CASE("surface code: P_L, the distance is the smallest that meets the budget, qubits and time add up") {
  CHECK(qrm::logical_error_per_cycle(1e-3, 3) == doctest::Approx(0.03 * 1e-2));
  CHECK(qrm::logical_error_per_cycle(1e-3, 5) == doctest::Approx(0.03 * 1e-3));
  const qrm::hardware sc = qrm::hardware_preset("superconducting");
  const auto split = qrm::split_error_budget(1e-3, false);
  const auto plan = qrm::plan_surface_code(sc, 20, 100000, split);
  // Layout 2*20 + ceil(sqrt(160)) + 1 = 54 patches; volume 54 * 1e5 = 5.4e6; P_L(d) <= 5e-4 / 5.4e6
  // = 9.26e-11: 0.03 * 0.1^((d+1)/2) <= 9.26e-11 needs (d+1)/2 >= 8.51, d = 17 (odd).
  CHECK(plan.layout_qubits == 54);
  CHECK(plan.code_distance == 17);
  CHECK(5.4e6 * qrm::logical_error_per_cycle(1e-3, 15) > 5e-4);
  CHECK(plan.data_physical_qubits == 54u * 2 * 17 * 17);
  // T states: 1e-3 -> 3.5e-8 -> 1.5e-21; the target is 5e-4 / 1e5 = 5e-9: two levels.
  CHECK(plan.distillation_levels == 2);
  CHECK(plan.factory_units == 11 + 11 * 15);
  CHECK(plan.physical_qubits == plan.data_physical_qubits + plan.factory_units * 11 * 2 * 17 * 17);
  CHECK(plan.seconds == doctest::Approx(1e5 * 17 * 1e-6));
  CHECK(plan.physical_qubits >= 20u * 17 * 17);

  CHECK(qrm_test::error_of([] { (void)qrm::hardware_preset("photonic"); }).find("'photonic'") != std::string::npos);
  CHECK(qrm_test::error_of([] { (void)qrm::split_error_budget(1.5, true); }).find("1.5") != std::string::npos);
  CHECK(qrm_test::error_of([&] { (void)qrm::plan_surface_code({"x", 1e-3, -1.0}, 2, 2, split); }).find("cycle time") !=
        std::string::npos);
}

TEST_CASE("resources never fall when the error budget tightens") {
  const auto w = small_walk();
  const qrm::estimation_problem problem{w.circuit, {control{w.out, true}}};
  qrm::estimation_result r;
  r.shots = 500;
  r.grover_calls = 4000;
  r.rounds = {{0, 100, 10, 0}, {16, 400, 200, 0}};
  const qrm::hardware hw = qrm::hardware_preset("superconducting");
  std::uint64_t last_t = 0, last_d = 0, last_q = 0;
  for (double eps : {1e-1, 1e-2, 1e-3, 1e-5, 1e-8, 1e-12}) {
    const auto e = qrm::cost_of_estimate(problem, r, {}, hw, eps);
    CHECK(e.max_power == 16);
    CHECK(e.a.t.t_count >= last_t);
    CHECK(e.plan.code_distance >= last_d);
    CHECK(e.plan.physical_qubits >= last_q);
    CHECK(e.seconds == doctest::Approx(500 * e.a.seconds + 4000 * e.q.seconds));
    CHECK(e.q.t.t_count > e.a.t.t_count);  // Q holds A twice
    last_t = e.a.t.t_count;
    last_d = e.plan.code_distance;
    last_q = e.plan.physical_qubits;
  }
}
