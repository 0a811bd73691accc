// Gate fusion (circuit/fuse.hpp): a fused program gives the unfused program's state to rounding
// on every backend and amplitude type and at every block width; blocks never exceed their
// width; a product multiplied by hand; the pass counts what it did.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include <qrm/circuit/fuse.hpp>

#include "support/backends.hpp"
#include "support/random_programs.hpp"

using namespace qrm_test;
using qrm::control;
using qrm::qubit_index;

namespace {

// Mostly small gates (what fusion is for), with adds and multiplexed ops between them as
// barriers; real programs only for backends that store real amplitudes.
qrm::program random_gate_program(std::size_t n, std::size_t count, qrm::rng& g, bool complex_values) {
  qrm::program p(n);
  while (p.size() < count) {
    const std::uint64_t r = g.below(20);
    const op_kind kind = r < 12 ? op_kind::gate1 : r < 17 ? op_kind::unitary : r == 17 ? op_kind::add
                                                          : r == 18 ? op_kind::mux1 : op_kind::mux_unitary;
    qrm::op::any o = random_op(kind, n, g);
    if (!complex_values && !qrm::op_is_real(o)) continue;
    p.push(std::move(o));
  }
  return p;
}

// The same op: kind, qubits, controls and (for gates and unitaries) matrix. Adds and
// multiplexed ops are never fused, so kind and qubits identify them here.
bool same_op(const qrm::op::any& a, const qrm::op::any& b) {
  if (a.index() != b.index() || qrm::op_qubits(a) != qrm::op_qubits(b)) return false;
  if (a.index() == 0) {
    const auto& x = *std::get_if<qrm::op::gate1_op>(&a);
    const auto& y = *std::get_if<qrm::op::gate1_op>(&b);
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c)
        if (x.gate.m[r][c] != y.gate.m[r][c]) return false;
    return x.controls == y.controls;
  }
  if (a.index() == 1)
    return std::get_if<qrm::op::unitary_op>(&a)->matrix == std::get_if<qrm::op::unitary_op>(&b)->matrix;
  return true;
}

template <class B>
std::vector<std::complex<double>> run_on(const qrm::program& p, const std::vector<std::complex<double>>& start) {
  using T = backend_traits<B>;
  B b = T::make(p.width());
  T::load(b, start);
  qrm::run(b, p);
  return T::dump(b);
}

}  // namespace

TEST_CASE_TEMPLATE("fused programs give the unfused state on every backend and block width", B, qrm::state_vector<double>,
                   qrm::state_vector<float>, qrm::state_vector<std::complex<double>>,
                   qrm::state_vector<std::complex<float>>, qrm::compact_state<std::complex<double>>,
                   qrm::compact_state<float>) {
  using T = backend_traits<B>;
  qrm::rng g(2026);
  const std::size_t n = 8;
  double worst = 0;
  for (unsigned k = 1; k <= 6; ++k)
    for (int trial = 0; trial < 6; ++trial) {
      const qrm::program p = random_gate_program(n, 80, g, T::is_complex);
      qrm::fusion_report rep;
      const qrm::program f = qrm::fuse(p, {k}, &rep);
      // The start is rounded to the backend's type once, so both runs start from the same state.
      B start_b = T::make(n);
      T::load(start_b, random_unit_state(n, g));
      const auto start = T::dump(start_b);
      const double d = max_diff(run_on<B>(p, start), run_on<B>(f, start));
      worst = std::max(worst, d);
      CAPTURE(k);
      CAPTURE(trial);
      // Both runs round every amplitude once per op on values below 1, fused or not; the bars
      // are the kernel tests' (1e-12 double, 2e-5 float).
      CHECK(d <= T::tolerance);
      CHECK(rep.ops_in == p.size());
      CHECK(rep.ops_out == f.size());
      CHECK(f.size() <= p.size());
    }
  MESSAGE(std::string(T::name()) << ": largest |fused - unfused| " << worst);
}

TEST_CASE("a fused block never exceeds its width, and whatever passes through is unchanged") {
  qrm::rng g(7);
  for (unsigned k = 1; k <= 6; ++k) {
    const qrm::program p = random_gate_program(9, 200, g, true);
    qrm::fusion_report rep;
    const qrm::program f = qrm::fuse(p, {k}, &rep);
    std::size_t by_width = 0;
    for (std::size_t w = 0; w < rep.blocks_by_width.size(); ++w) {
      by_width += rep.blocks_by_width[w];
      if (w > k) CHECK(rep.blocks_by_width[w] == 0);
    }
    CHECK(by_width == rep.fused_blocks);
    if (k >= 2) CHECK(rep.fused_blocks > 0);
    // Every output op is either an input op, unchanged, or a controls-free fused block.
    std::size_t unchanged = 0;
    for (const qrm::op::any& o : f.ops()) {
      if (std::any_of(p.ops().begin(), p.ops().end(), [&](const qrm::op::any& i) { return same_op(i, o); })) {
        ++unchanged;
        continue;
      }
      CHECK(qrm::op_qubits(o).size() <= k);
      CHECK((o.index() == 0 || o.index() == 1));
      qrm::visit_op(o, [](const auto& x) { CHECK(x.controls.empty()); });
    }
    CHECK(unchanged + rep.fused_blocks == f.size());
  }
}

TEST_CASE("H then CNOT fuse into the Bell matrix, multiplied by hand") {
  qrm::program p(2);
  p.apply_gate1(qrm::gate::h(), 0, {});
  const control c0[] = {{0, true}};
  p.apply_gate1(qrm::gate::x(), 1, c0);
  qrm::fusion_report rep;
  const qrm::program f = qrm::fuse(p, {2}, &rep);
  REQUIRE(f.size() == 1);
  REQUIRE(f.ops()[0].index() == 1);
  const auto& u = *std::get_if<qrm::op::unitary_op>(&f.ops()[0]);
  CHECK(u.targets == std::vector<qubit_index>{0, 1});
  CHECK(u.controls.empty());
  // Column j is the image of |j> (bit 0 = qubit 0): |00> -> (|00> + |11>)/sqrt2,
  // |01> -> (|00> - |11>)/sqrt2, |10> -> (|10> + |01>)/sqrt2, |11> -> (|10> - |01>)/sqrt2.
  const double r = 1 / std::sqrt(2.0);
  const double expected[4][4] = {{r, r, 0, 0}, {0, 0, r, -r}, {0, 0, r, r}, {r, -r, 0, 0}};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) CHECK(std::abs(u.matrix(i, j) - expected[i][j]) < 1e-15);
  CHECK(rep.fused_blocks == 1);
  CHECK(rep.blocks_by_width[2] == 1);
}

TEST_CASE("blocks close when a gate would widen them past the limit") {
  // H0, H1, CX(0 -> 1), H2, CX(1 -> 2): with width 2 the first three fuse into one block on
  // {0, 1}; CX(1 -> 2) would make it {0, 1, 2}, so {0, 1} and {2} close and CX(1 -> 2) is alone.
  qrm::program p(3);
  p.apply_gate1(qrm::gate::h(), 0, {});
  p.apply_gate1(qrm::gate::h(), 1, {});
  const control c0[] = {{0, true}}, c1[] = {{1, true}};
  p.apply_gate1(qrm::gate::x(), 1, c0);
  p.apply_gate1(qrm::gate::h(), 2, {});
  p.apply_gate1(qrm::gate::x(), 2, c1);
  qrm::fusion_report rep;
  const qrm::program f2 = qrm::fuse(p, {2}, &rep);
  REQUIRE(f2.size() == 3);
  CHECK(f2.ops()[0].index() == 1);
  CHECK(qrm::op_qubits(f2.ops()[0]) == std::vector<qubit_index>{0, 1});
  CHECK(qrm::op_qubits(f2.ops()[1]) == std::vector<qubit_index>{2});
  CHECK(qrm::op_qubits(f2.ops()[2]) == std::vector<qubit_index>{2, 1});  // target, then control
  CHECK(rep.fused_blocks == 1);
  CHECK(qrm::fuse(p, {3}).size() == 1);
  CHECK(qrm::fuse(p, {1}).size() == 5);  // nothing shares a single qubit but H alone: no block of two
}

TEST_CASE("fusion refuses a width outside 1..6") {
  const qrm::program p(2);
  CHECK_THROWS_WITH_AS(qrm::fuse(p, {0}), "fuse: max_qubits must be 1..6, got 0", std::invalid_argument);
  CHECK_THROWS_WITH_AS(qrm::fuse(p, {7}), "fuse: max_qubits must be 1..6, got 7", std::invalid_argument);
}
