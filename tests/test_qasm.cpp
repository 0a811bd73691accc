// OpenQASM 3 export and import: round trips of random programs (logical and decomposed forms)
// compared amplitude by amplitude (global phase included), a hand-written program against a
// state worked out by hand, and error messages for malformed input.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include <qrm/circuit/qasm.hpp>

#include "support/random_programs.hpp"

namespace {

using qrm::control;
using qrm::qubit_index;
using cvec = std::vector<std::complex<double>>;

double max_diff(const cvec& a, const cvec& b, std::size_t count) {
  double d = 0;
  for (std::size_t i = 0; i < count; ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

std::size_t count_lines_starting(const std::string& text, const std::string& prefix) {
  std::size_t n = 0, pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    if (text.compare(pos, prefix.size(), prefix) == 0) ++n;
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  return n;
}

std::string error_of(const std::string& text) {
  try {
    qrm::from_qasm(text);
  } catch (const qrm::qasm_error& e) {
    return e.what();
  }
  return "no error";
}

const std::string header = "OPENQASM 3.0;\ninclude \"stdgates.inc\";\nqubit[2] q;\n";

}  // namespace

TEST_CASE("logical round trip: every op kind, random placements and controls") {
  qrm::rng g(2026);
  for (qrm_test::op_kind kind : qrm_test::all_op_kinds) {
    for (std::size_t n = 3; n <= 7; ++n) {
      qrm::program p(n);
      for (int i = 0; i < 4; ++i) p.push(qrm_test::random_op(kind, n, g));
      const std::string text = qrm::to_qasm(p);
      const qrm::program back = qrm::from_qasm(text);
      const std::string kind_name = qrm_test::op_kind_name(kind);
      CAPTURE(kind_name);
      CAPTURE(n);
      REQUIRE(back.width() == n);
      const cvec initial = qrm_test::random_unit_state(n, g);
      // 1e-12: angles round-trip exactly (17 digits); the rest is rounding of a few hundred
      // O(1) products (two-level bodies of dense matrices); a lost phase or control is O(1).
      CHECK(max_diff(qrm_test::run_from(p, initial), qrm_test::run_from(back, initial), std::size_t{1} << n) < 1e-12);
    }
  }
}

TEST_CASE("logical round trip of whole random programs, and the decomposed export") {
  qrm::rng g(99);
  for (std::size_t n = 3; n <= 6; ++n) {
    qrm::program p(n);
    for (int i = 0; i < 10; ++i) p.push(qrm_test::random_op(qrm_test::all_op_kinds[g.below(6)], n, g));
    const cvec initial = qrm_test::random_unit_state(n, g);
    const cvec want = qrm_test::run_from(p, initial);
    CHECK(max_diff(want, qrm_test::run_from(qrm::from_qasm(qrm::to_qasm(p)), initial), want.size()) < 1e-12);  // as above

    qrm::qasm_options o;
    o.decomposed = true;
    const std::string text = qrm::to_qasm(p, o);
    const qrm::program back = qrm::from_qasm(text);
    const auto d = qrm::decompose(p);
    CHECK(back.width() == n + d.ancillas);
    // Only single-qubit gates, cx and declarations: no modifiers, no gate definitions.
    CHECK(text.find(" @ ") == std::string::npos);
    CHECK(text.find("gate ") == std::string::npos);
    const cvec got = qrm_test::run_from(back, initial);
    CHECK(max_diff(want, got, want.size()) < 1e-12);  // as above, over a few thousand gates
    double ancilla = 0;
    for (std::size_t i = want.size(); i < got.size(); ++i) ancilla += std::norm(got[i]);
    CHECK(ancilla < 1e-24);  // rounding only (~1e-30); an ancilla left in |1> is O(1)
  }
}

TEST_CASE("angles are written with 17 digits and read back bit for bit") {
  qrm::rng g(4);
  qrm::program p(1);
  std::vector<double> angles;
  for (int i = 0; i < 50; ++i) {
    angles.push_back((g.uniform() - 0.5) * std::pow(10.0, static_cast<double>(g.below(20)) - 10.0));
    p.apply_gate1(qrm::gate::ry(angles.back()), 0, {});
  }
  const qrm::program back = qrm::from_qasm(qrm::to_qasm(p));
  REQUIRE(back.size() == angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    const auto& op = std::get<qrm::op::gate1_op>(back.ops()[i]);
    CHECK(op.gate.kind == qrm::gate1_kind::ry);
    CHECK(op.gate.angle == angles[i]);  // exact: shortest round-trip needs at most 17 digits
  }
}

TEST_CASE("the logical form: modifiers, one line per multiplexed entry, gate definitions") {
  qrm::program p(5);
  const control cs[] = {{0, true}, {1, false}, {2, true}};
  p.apply_gate1(qrm::gate::ry(0.25), 4, cs);
  std::vector<qrm::mux1_entry> es;
  for (std::uint64_t s = 0; s < 8; ++s) es.push_back({s, qrm::gate::ry(0.1 * static_cast<double>(s + 1))});
  const qubit_index sel[] = {0, 1, 2};
  p.apply_mux1(es, 3, sel, {});
  const qubit_index ts[] = {2, 3, 4};
  qrm::rng g(1);
  const qrm::dense_matrix coin = qrm_test::sparse_coin(3, g);
  p.apply_unitary(coin, ts, std::span<const control>(cs, 1));
  p.apply_unitary(coin, ts, std::span<const control>(cs + 1, 1));
  p.apply_add(5, ts, {});
  p.set_registers({{"x", qrm::role::position, 0, 2}, {"out", qrm::role::out, 4, 1}});
  const std::string text = qrm::to_qasm(p);
  CHECK(text.find("// register x (position): q[0:1]\n") != std::string::npos);
  CHECK(text.find("// register out (out): q[4]\n") != std::string::npos);
  CHECK(text.find("ctrl(2) @ negctrl @ ry(0.25) q[0], q[2], q[1], q[4];") != std::string::npos);
  CHECK(count_lines_starting(text, "ctrl(3) @ ry(") == 1);            // select value 7
  CHECK(count_lines_starting(text, "negctrl(3) @ ry(") == 1);         // select value 0
  CHECK(text.find("gate qrm_unitary3_0 a0, a1, a2 {") != std::string::npos);
  CHECK(text.find("gate qrm_unitary3_1") == std::string::npos);      // one definition per distinct matrix
  CHECK(text.find("ctrl @ qrm_unitary3_0 q[0], q[2], q[3], q[4];") != std::string::npos);
  CHECK(text.find("negctrl @ qrm_unitary3_0 q[1], q[2], q[3], q[4];") != std::string::npos);
  CHECK(text.find("qrm_add3_5 q[2], q[3], q[4];") != std::string::npos);
  const cvec initial = qrm_test::random_unit_state(5, g);
  CHECK(max_diff(qrm_test::run_from(p, initial), qrm_test::run_from(qrm::from_qasm(text), initial), 32) < 1e-12);  // as above
}

TEST_CASE("a walk-sized program (17 qubits, like the paper's 8x8 scene) round-trips in a few hundred lines") {
  // Registers: x 0-2, y 3-5, direction 6-8, steps 9-10, reflectance 11, out 12, others 13-16.
  qrm::program p(17);
  qrm::rng g(8);
  std::vector<qubit_index> position = {0, 1, 2, 3, 4, 5}, direction = {6, 7, 8};
  // Uniform preparation on 2 qubits (Ry, and an Ry multiplexed on the other).
  p.apply_gate1(qrm::gate::ry(2 * std::asin(std::sqrt(0.5))), 10, {});
  const qrm::mux1_entry prep[] = {{0, qrm::gate::ry(2 * std::asin(std::sqrt(0.5)))}, {1, qrm::gate::ry(1.1)}};
  const qubit_index prep_sel[] = {10};
  p.apply_mux1(prep, 9, prep_sel, {});
  for (int step = 0; step < 2; ++step) {
    // Multiplexed Ry over the 64 cells.
    std::vector<qrm::mux1_entry> rys;
    for (std::uint64_t s = 0; s < 64; ++s) rys.push_back({s, qrm::gate::ry(3 * g.uniform())});
    p.apply_mux1(rys, 11, position, {});
    // Multiplexed 8x8 coins over the 64 cells (4 distinct matrices), controlled by reflectance.
    std::vector<qrm::dense_matrix> coins;
    for (int i = 0; i < 4; ++i) coins.push_back(qrm_test::sparse_coin(3, g));
    std::vector<qrm::mux_unitary_entry> entries;
    for (std::uint64_t s = 0; s < 64; ++s) entries.push_back({s, static_cast<std::uint32_t>(g.below(4))});
    const control refl{11, true};
    p.apply_mux_unitary(coins, entries, direction, position, std::span<const control>(&refl, 1));
    // Controlled adds on the 3-qubit position registers, one per direction value.
    for (std::uint64_t d = 0; d < 8; ++d) {
      std::vector<control> cs;
      for (int b = 0; b < 3; ++b) cs.push_back({direction[static_cast<std::size_t>(b)], ((d >> b) & 1u) != 0});
      p.apply_add(static_cast<std::int64_t>(d % 3) - 1, std::span<const qubit_index>(position.data(), 3), cs);
      p.apply_add(static_cast<std::int64_t>(d % 2 ? 1 : -1), std::span<const qubit_index>(position.data() + 3, 3), cs);
    }
    // A multi-controlled X with 6 controls.
    std::vector<control> cs;
    for (qubit_index q = 0; q < 6; ++q) cs.push_back({q, q % 2 == 0});
    p.apply_gate1(qrm::gate::x(), 12, cs);
  }
  const std::string text = qrm::to_qasm(p);
  const qrm::program back = qrm::from_qasm(text);
  // One line per logical gate and per multiplexed entry (2 x (64 + 64 + 16 + 1) + 2), plus the
  // coin definitions: a few hundred lines, not the decomposed tens of thousands.
  const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  CHECK(lines < 1000);
  const cvec initial = qrm_test::random_unit_state(17, g);
  // 1e-12 as above (the coins' two-level bodies are a few hundred roundings deep).
  CHECK(max_diff(qrm_test::run_from(p, initial), qrm_test::run_from(back, initial), std::size_t{1} << 17) < 1e-12);
}

TEST_CASE("a hand-written program gives the state worked out by hand") {
  const std::string text = R"(OPENQASM 3.0;
include "stdgates.inc";
/* two registers: a[0] = qubit 0, a[1] = qubit 1, b = qubit 2 */
qubit[2] a;
qubit b;
gate bell(theta) x, y { ry(theta) x; cx x, y; }
h b;                      // (|0> + |1>)/sqrt2 on b
bell(pi / 2) a[0], a[1];  // (|00> + |11>)/sqrt2 on a
negctrl @ x b, a[1];      // where b = 0, flip a[1]
ctrl @ gphase(π/2) b;     // where b = 1, multiply by i
inv @ s a[0];             // sdg: where a[0] = 1, multiply by -i
)";
  const qrm::program p = qrm::from_qasm(text);
  REQUIRE(p.width() == 3);
  const cvec got = qrm_test::run_from(p, cvec{1.0});
  // By hand (index = a0 + 2 a1 + 4 b): after h and bell, (1/2) sum_b (|00> + |11>)|b>; the
  // negctrl-x turns the b = 0 half into |a0=0,a1=1> + |a0=1,a1=0>; the controlled gphase
  // multiplies the b = 1 half by i; sdg multiplies a0 = 1 by -i.
  cvec want(8);
  want[2] = 0.5;                                   // a0=0 a1=1 b=0
  want[1] = std::complex<double>(0, -0.5);         // a0=1 a1=0 b=0: -i/2
  want[4] = std::complex<double>(0, 0.5);          // a0=0 a1=0 b=1: i/2
  want[7] = 0.5;                                   // a0=1 a1=1 b=1: i * -i / 2
  CHECK(max_diff(got, want, 8) < 1e-15);  // a handful of roundings of O(1) numbers

  // U, rz and gphase carry the OpenQASM 3 phases: rz(pi)|0> = -i|0>, U(pi/2, 0, pi) = H, then
  // e^{i pi/4}: both amplitudes -i e^{i pi/4}/sqrt2 = (1 - i)/2.
  const qrm::program q = qrm::from_qasm("OPENQASM 3;\ninclude \"stdgates.inc\";\nqreg r[1];\nrz(pi) r[0];\nU(pi/2, 0, pi) r[0];\ngphase(pi/4);\n");
  const cvec s = qrm_test::run_from(q, cvec{1.0});
  CHECK(max_diff(s, cvec{{0.5, -0.5}, {0.5, -0.5}}, 2) < 1e-15);  // as above
}

TEST_CASE("stdgates with modifiers match their definitions") {
  // Each line against the same gate written with U, gphase and ctrl modifiers per stdgates.inc.
  const char* pairs[][2] = {
      {"cx q[0], q[1];", "ctrl @ U(pi, 0, pi) q[0], q[1];"},
      {"ccx q[0], q[1], q[2];", "ctrl(2) @ U(pi, 0, pi) q[0], q[1], q[2];"},
      {"rz(0.3) q[1];", "gphase(-0.15); U(0, 0, 0.3) q[1];"},
      {"ctrl @ rz(0.3) q[0], q[1];", "ctrl @ gphase(-0.15) q[0]; ctrl @ U(0, 0, 0.3) q[0], q[1];"},
      {"p(0.7) q[2];", "ctrl @ gphase(0.7) q[2];"},
      {"y q[0];", "U(pi, pi/2, pi/2) q[0];"},
      {"rx(0.4) q[1];", "U(0.4, -pi/2, pi/2) q[1];"},
      {"t q[0]; s q[0]; tdg q[1]; sdg q[1];", "p(pi/4) q[0]; p(pi/2) q[0]; p(-pi/4) q[1]; p(-pi/2) q[1];"},
      {"sx q[0]; sx q[0];", "x q[0];"},
      {"swap q[0], q[2];", "cx q[0], q[2]; cx q[2], q[0]; cx q[0], q[2];"},
      {"cu(0.1, 0.2, 0.3, 0.4) q[0], q[1];", "p(0.4) q[0]; ctrl @ U(0.1, 0.2, 0.3) q[0], q[1];"},
      {"u3(0.1, 0.2, 0.3) q[2];", "gphase(-0.25); U(0.1, 0.2, 0.3) q[2];"},
      {"inv @ ry(0.5) q[0];", "ry(-0.5) q[0];"},
      {"negctrl @ h q[0], q[1];", "x q[0]; ctrl @ h q[0], q[1]; x q[0];"},
      {"cswap q[0], q[1], q[2];", "ctrl @ cx q[0], q[1], q[2]; ctrl @ cx q[0], q[2], q[1]; ctrl @ cx q[0], q[1], q[2];"},
  };
  qrm::rng g(6);
  for (const auto& pr : pairs) {
    CAPTURE(pr[0]);
    const std::string h = "OPENQASM 3.0;\ninclude \"stdgates.inc\";\nqubit[3] q;\n";
    const cvec initial = qrm_test::random_unit_state(3, g);
    const cvec a = qrm_test::run_from(qrm::from_qasm(h + pr[0]), initial);
    const cvec b = qrm_test::run_from(qrm::from_qasm(h + pr[1]), initial);
    CHECK(max_diff(a, b, 8) < 1e-14);  // a few roundings of O(1) numbers
  }
}

TEST_CASE("malformed input: errors name the line, the column and what was expected") {
  CHECK(error_of(header + "h q[0]\nx q[1];\n") == "qasm:5:1: expected ';' after the gate call, found 'x'");
  CHECK(error_of(header + "qubit[3] r\n") == "qasm:5:1: expected ';' after the qubit declaration, found end of input");
  CHECK(error_of(header + "foo q[0];\n") == "qasm:4:1: unknown gate 'foo'");
  CHECK(error_of("OPENQASM 3.0;\nqubit[2] q;\nh q[0];\n") ==
        "qasm:3:1: unknown gate 'h' (the standard gates need include \"stdgates.inc\";)");
  CHECK(error_of(header + "h q[5];\n") == "qasm:4:5: qubit index 5 is out of range for 'q' (2 qubits)");
  CHECK(error_of(header + "h q[-1];\n") == "qasm:4:5: a qubit index must be a non-negative integer, got -1");
  CHECK(error_of(header + "h r[0];\n") == "qasm:4:3: unknown qubit register 'r'");
  CHECK(error_of(header + "h q;\n") ==
        "qasm:4:3: register 'q' has 2 qubits: index it (q[i]); broadcasting is not supported");
  CHECK(error_of(header + "gate g a {\n  h a;\n") ==
        "qasm:6:1: expected '}' to close the body of gate 'g' opened at 4:10, found end of input");
  CHECK(error_of(header + "gate g a { h b; }\n") == "qasm:4:14: 'b' is not a qubit argument of this gate");
  CHECK(error_of(header + "gate g a { g a; }\n") == "qasm:4:12: unknown gate 'g'");
  CHECK(error_of(header + "gate h a { x a; }\n") == "qasm:4:6: gate 'h' is already defined");
  CHECK(error_of(header + "ry q[0];\n") == "qasm:4:1: gate 'ry' takes 1 parameter, got 0");
  CHECK(error_of(header + "cx q[0];\n") == "qasm:4:1: gate 'cx' acts on 2 qubits, got 1 operands");
  CHECK(error_of(header + "ctrl @ x q[0];\n") == "qasm:4:8: gate 'x' acts on 1 qubit plus 1 controls from its modifiers, got 1 operands");
  CHECK(error_of(header + "cx q[1], q[1];\n") == "qasm:4:1: qubit q[1] appears twice in this gate call");
  CHECK(error_of(header + "pow(2) @ x q[0];\n") == "qasm:4:1: the pow modifier is not supported");
  CHECK(error_of(header + "ctrl(0) @ x q[0];\n") == "qasm:4:6: a control count must be an integer in [1, 64], got 0");
  CHECK(error_of(header + "ry(2 * theta) q[0];\n") == "qasm:4:8: unknown identifier 'theta' in an expression");
  CHECK(error_of(header + "measure q[0];\n") == "qasm:4:1: 'measure' statements are not supported (qrm imports unitary circuits)");
  CHECK(error_of("OPENQASM 2.0;\n") == "qasm:1:10: only OpenQASM 3 is supported, found version 2.0");
  CHECK(error_of(header + "include \"qelib1.inc\";\n") == "qasm:4:9: cannot include \"qelib1.inc\": only \"stdgates.inc\" is built in");
  CHECK(error_of(header + "h q[0]; /* open\n") == "qasm:4:9: unterminated comment: expected '*/'");
  CHECK(error_of(header + "h q[0] $\n") == "qasm:4:8: unexpected character '$'");
  // The errors are std::invalid_argument, like every other bad input in qrm.
  CHECK_THROWS_AS(qrm::from_qasm(header + "h q[0]\n"), std::invalid_argument);
}

TEST_CASE("export rejects what OpenQASM cannot express") {
  qrm::program p(1);
  p.apply_gate1(qrm::gate::u(1.0, 1.0, 0.0, 1.0), 0, {});
  CHECK_THROWS_WITH_AS(qrm::to_qasm(p), doctest::Contains("op 0: the 2x2 matrix is not unitary"), std::invalid_argument);
  qrm::program r(2);
  r.ops().push_back(qrm::op::mux1_op{{{1, qrm::gate::ry(0.1)}, {1, qrm::gate::ry(0.2)}}, 0, {1}, {}});
  CHECK_THROWS_WITH_AS(qrm::to_qasm(r), doctest::Contains("op 0: select value 1 has two entries"), std::invalid_argument);
}

// Found by fuzzing (tests/fuzz/fuzz_qasm.cpp and its edge seeds): each of these was accepted
// (a NaN angle became a NaN state; a NaN index reached the number formatter, which threw a
// to_qasm error of the wrong type) or exhausted time, memory or the stack.
TEST_CASE("hostile input: non-finite values, deep nesting, multiplying definitions, huge registers") {
  // Angles must be finite, also when a definition computes them.
  CHECK(error_of(header + "ry(0/0) q[0];\n") == "qasm:4:1: gate 'ry': parameter 1 is nan; angles must be finite");
  CHECK(error_of(header + "gphase(ln(0));\n") == "qasm:4:1: gate 'gphase': parameter 1 is -inf; angles must be finite");
  CHECK(error_of(header + "U(0, 1e308 * 10, 0) q[0];\n") ==
        "qasm:4:1: gate 'U': parameter 2 is inf; angles must be finite");
  CHECK(error_of(header + "gate g(t) a { ry(1 / t) a; }\ng(0.5) q[0];\ng(0) q[1];\n") ==
        "qasm:4:15: gate 'ry': parameter 1 is inf; angles must be finite (expanding the call of 'g' at 6:1)");
  // Indices and counts that are not numbers are reported as such.
  CHECK(error_of(header + "h q[0/0];\n") == "qasm:4:5: a qubit index must be a non-negative integer, got nan");
  CHECK(error_of(header + "h q[1/0];\n") == "qasm:4:5: qubit index inf is out of range for 'q' (2 qubits)");
  CHECK(error_of(header + "ctrl(0/0) @ x q[0], q[1];\n") ==
        "qasm:4:6: a control count must be an integer in [1, 64], got nan");

  // Nesting: 1000 levels parse (and evaluate to the right angle), deeper is refused before the
  // recursion can exhaust the stack: parentheses, signs, and a long chain of additions.
  auto nested = [](std::size_t depth) { return std::string(depth, '(') + "0.5" + std::string(depth, ')'); };
  const qrm::program ok = qrm::from_qasm(header + "ry(" + nested(998) + ") q[0];\n");
  CHECK(std::get<qrm::op::gate1_op>(ok.ops()[0]).gate.angle == 0.5);
  const std::string too_deep = "expression nested more than 1000 levels deep";
  CHECK(error_of(header + "ry(" + nested(5000) + ") q[0];\n").find(too_deep) != std::string::npos);
  CHECK(error_of(header + "ry(" + std::string(5000, '-') + "1) q[0];\n").find(too_deep) != std::string::npos);
  CHECK(error_of(header + "ry(" + std::string(5000, '+') + "1) q[0];\n").find(too_deep) != std::string::npos);
  std::string chain = "1";
  for (int i = 0; i < 1500; ++i) chain += "+1";
  CHECK(error_of(header + "ry(" + chain + ") q[0];\n").find(too_deep) != std::string::npos);
  std::string powers = "1";
  for (int i = 0; i < 1500; ++i) powers += "**1";
  CHECK(error_of(header + "ry(" + powers + ") q[0];\n").find(too_deep) != std::string::npos);

  // Definitions that call the previous one twice double at each level: 2^25 gates from a few
  // hundred bytes. Refused at the top-level call, both for a gate imported as one matrix (at
  // most 6 qubits) and for a wider one expanded inline; ten levels (1024 gates) are fine.
  auto doubling = [](std::size_t levels, std::size_t qubits) {
    // Appended piece by piece: g++ 12 -O3 warns falsely (-Wrestrict) on "literal" + std::to_string(n).
    std::string args;
    for (std::size_t i = 0; i < qubits; ++i) {
      args += i ? ", a" : "a";
      args += std::to_string(i);
    }
    std::string t = "OPENQASM 3.0;\ninclude \"stdgates.inc\";\nqubit[";
    t += std::to_string(qubits) + "] q;\n";
    t += "gate g0 " + args + " { h a0; }\n";
    for (std::size_t l = 1; l <= levels; ++l) {
      std::string prev = "g";
      prev += std::to_string(l - 1) + " " + args + "; ";
      t += "gate g";
      t += std::to_string(l) + " " + args + " { " + prev + prev + "}\n";
    }
    t += "g";
    t += std::to_string(levels);
    for (std::size_t i = 0; i < qubits; ++i) {
      t += i ? ", q[" : " q[";
      t += std::to_string(i) + "]";
    }
    return t + ";\n";
  };
  const std::string multiplies = "' expands to more than 1048576 gates (gate definitions that call each other multiply)";
  CHECK(error_of(doubling(25, 1)) == "qasm:30:1: gate 'g25" + multiplies + "; qrm imports at most that many");
  CHECK(error_of(doubling(25, 7)) == "qasm:30:1: gate 'g25" + multiplies + "; qrm imports at most that many");
  CHECK(qrm::from_qasm(doubling(10, 1)).size() == 1);  // one 2x2 matrix: H^1024 = I
  CHECK(qrm::from_qasm(doubling(10, 7)).size() == 1024);
  // A 6-qubit definition of 3 * 2^17 gates stays under the gate limit, but its 64x64 matrix would
  // cost 3 * 2^17 * 4096 > 2^30 operations.
  std::string six = "OPENQASM 3.0;\ninclude \"stdgates.inc\";\nqubit[6] q;\n";
  six += "gate c0 a, b, c, d, e, f { h a; h b; h c; }\n";
  for (int l = 1; l <= 17; ++l)
    six += "gate c" + std::to_string(l) + " a, b, c, d, e, f { c" + std::to_string(l - 1) + " a, b, c, d, e, f; c" +
           std::to_string(l - 1) + " a, b, c, d, e, f; }\n";
  six += "c17 q[0], q[1], q[2], q[3], q[4], q[5];\n";
  CHECK(error_of(six) ==
        "qasm:22:1: gate 'c17' is too large to import: the matrices of the gate definitions need more than 1073741824 "
        "operations (gate definitions that call each other multiply)");

  // Registers: each at most 2^20 qubits, all together at most 2^24.
  std::string wide = "OPENQASM 3.0;\n";
  for (int i = 0; i < 17; ++i) wide += "qubit[1048576] r" + std::to_string(i) + ";\n";
  CHECK(error_of(wide) == "qasm:18:16: the registers declared add up to more than 16777216 qubits");
  CHECK(qrm::from_qasm("OPENQASM 3.0;\nqubit[1048576] a;\nqubit[1048576] b;\n").width() == 2097152);
}

TEST_CASE("large finite angles import as unitary gates and round-trip") {
  // phi + lambda rounds for huge angles (by 0.25 at 3e15) and overflows near 1e308: the matrices
  // are built from products of phases instead, and global phases are summed modulo 2 pi.
  const std::string text = header +
                           "U(1, 3e15, 0.3) q[0];\nu3(0.5, 1e308, 1e308) q[1];\nu2(-1e308, -1e308) q[0];\n"
                           "gphase(1e308);\ngphase(1e308);\nctrl @ U(0.7, 3e15, 3e15) q[0], q[1];\n";
  const qrm::program p = qrm::from_qasm(text);
  for (const auto& o : p.ops()) {
    const auto& g = std::get<qrm::op::gate1_op>(o).gate;
    // 1e-15: a handful of roundings of O(1) products; the rounded phase sum was off by 0.1.
    CHECK(qrm::detail::unitarity_error(g) < 1e-15);
  }
  // The exporter accepts it (it refuses non-unitary matrices) and the state comes back.
  qrm::rng g(3);
  const cvec initial = qrm_test::random_unit_state(2, g);
  const cvec want = qrm_test::run_from(p, initial);
  CHECK(std::isfinite(std::abs(want[0])));
  CHECK(max_diff(want, qrm_test::run_from(qrm::from_qasm(qrm::to_qasm(p)), initial), 4) < 1e-12);  // as above
  // The summed phase 2e308 is 2 * (1e308 mod 2 pi) modulo 2 pi, not inf.
  const qrm::program phase_only = qrm::from_qasm("OPENQASM 3.0;\nqubit q;\ngphase(1e308);\ngphase(1e308);\n");
  const double turn = 2 * std::acos(-1.0);
  const double expected = std::remainder(2 * std::remainder(1e308, turn), turn);
  const auto z = std::get<qrm::op::gate1_op>(phase_only.ops()[0]).gate.m[0][0];
  CHECK(std::abs(z - std::polar(1.0, expected)) < 1e-15);  // one rounding of the polar form
}
