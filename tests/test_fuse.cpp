// Gate fusion (circuit/fuse.hpp): a fused program gives the unfused program's state to rounding
// on every backend and amplitude type and at every block width; blocks never exceed their
// width; a product multiplied by hand; the pass counts what it did.
#include <bit>
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <vector>

#include <qrm/circuit/decompose.hpp>
#include <qrm/circuit/fuse.hpp>
#include <qrm/backends/detail/dense_blocked.hpp>  // plan_runs, memory_bound_dim
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/paper_scenes.hpp>

#include "support/backends.hpp"
#include "support/random_programs.hpp"
#include "support/reference.hpp"

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

// `count` unitary gates on n qubits from small pools (16 single-qubit gates, 4 two-qubit
// matrices, complex): a gate alone, a gate under one control of either value, or a two-qubit matrix.
qrm::program small_gate_program(std::size_t n, int count, qrm::rng& g) {
  std::vector<qrm::gate1> pool;
  std::vector<qrm::dense_matrix> two;
  for (int i = 0; i < 16; ++i) pool.push_back(random_gate1_unitary(g, true));
  for (int i = 0; i < 4; ++i) two.push_back(random_unitary(2, g, true));
  qrm::program p(n);
  for (int i = 0; i < count; ++i) {
    const auto t = static_cast<qubit_index>(g.below(n));
    const auto other = static_cast<qubit_index>((t + 1 + g.below(n - 1)) % n);
    switch (g.below(3)) {
      case 0: p.apply_gate1(pool[g.below(pool.size())], t, {}); break;
      case 1: {
        const std::vector<control> cs = {{other, g.below(2) == 1}};
        p.apply_gate1(pool[g.below(pool.size())], t, cs);
        break;
      }
      default: {
        const std::vector<qubit_index> ts = {t, other};
        p.apply_unitary(two[g.below(two.size())], ts, {});
      }
    }
  }
  return p;
}

// A one-thread complex<float> state holding `amps`, computing at `level` in float or double arithmetic.
qrm::state_vector<std::complex<float>> float_state(std::size_t n, qrm::simd_level level, bool float_arithmetic,
                                                   const std::vector<std::complex<float>>& amps) {
  qrm::dense_options o;
  o.threads = 1;
  o.simd = level;
  o.math = float_arithmetic ? qrm::float_math::single_precision : qrm::float_math::double_precision;
  qrm::state_vector<std::complex<float>> b(n, o);
  b.set_amplitudes(amps);
  return b;
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

// Fusion within the runs the dense backend applies chunk by chunk (fusion_options::chunk_qubits):
// chunks of 6 of 10 qubits, every run chunked (chunk_min_passes 0), so the fused blocks run on
// renumbered chunks. Fused and unfused give the same state; each fused block keeps to one run's
// qubits, so the backend cuts the fused program into no more runs than the gates it came from
// (fused across the program, a block that turns a CX's control outside the run into a target
// can add one).
TEST_CASE_TEMPLATE("fusing within the dense backend's runs gives the unfused state and adds no run", S,
                   std::complex<double>, std::complex<float>, double) {
  using T = backend_traits<qrm::state_vector<S>>;
  qrm::rng g(31);
  const std::size_t n = 10;
  qrm::dense_options o;
  o.threads = 1;
  o.chunk_bytes = 64 * sizeof(S);
  o.chunk_min_passes = 0;
  const unsigned low = qrm::detail::chunk_low_qubits<S>();
  const std::uint64_t reserved = (std::uint64_t{1} << low) - 1;
  REQUIRE(qrm::dense_fusion_options<S>({2}, o).chunk_qubits == 6);
  REQUIRE(qrm::dense_fusion_options<S>({2}, o).chunk_low_qubits == low);
  qrm::dense_options unchunked = o;
  unchunked.chunk_bytes = 0;
  CHECK(qrm::dense_fusion_options<S>({2}, unchunked).chunk_qubits == 0);
  std::size_t runs_unfused = 0, runs_fused = 0, runs_across = 0;
  for (unsigned k = 1; k <= 6; ++k)
    for (int trial = 0; trial < 4; ++trial) {
      const qrm::program p = random_gate_program(n, 120, g, T::is_complex);
      qrm::fusion_report rep;
      const qrm::program f = qrm::fuse(p, qrm::dense_fusion_options<S>({k}, o), &rep);
      CAPTURE(k);
      CAPTURE(trial);
      CHECK(rep.chunk_qubits == 6);
      const auto plain = qrm::detail::group_runs(p.ops(), 6, reserved);
      const auto fused = qrm::detail::group_runs(f.ops(), 6, reserved);
      CHECK(fused.runs.size() <= plain.runs.size());
      runs_unfused += plain.runs.size();
      runs_fused += fused.runs.size();
      runs_across += qrm::detail::group_runs(qrm::fuse(p, {k}).ops(), 6, reserved).runs.size();
      qrm::state_vector<S> a(n, o), b(n, o);
      const auto start = random_unit_state(n, g);
      std::vector<S> rounded(start.size());
      for (std::size_t i = 0; i < start.size(); ++i) {
        if constexpr (T::is_complex)
          rounded[i] = static_cast<S>(start[i]);
        else
          rounded[i] = start[i].real();
      }
      a.set_amplitudes(rounded);
      b.set_amplitudes(rounded);
      qrm::run(a, p);
      qrm::run(b, f);
      double d = 0;
      for (std::size_t i = 0; i < rounded.size(); ++i)
        d = std::max(d, static_cast<double>(std::abs(a.amplitudes()[i] - b.amplitudes()[i])));
      CHECK(d <= T::tolerance);
    }
  MESSAGE(std::string(qrm::detail::scalar_name<S>()) << ": " << runs_unfused << " runs unfused, " << runs_fused
                                                     << " fused within them, " << runs_across << " fused across");
}

// The circuit fusion is for: the walk lowered to 1-qubit gates and CNOTs (paper_4x4, cell (1, 2),
// 2 steps, reachable pruning: 12 qubits with ancillas, 926 gates), run gate by gate and fused at
// every width from |0...0>. Bars: 1e-12 in complex<double>, 1e-5 in complex<float> (each of the
// ~900 unfused gates rounds the state to float once: ~900 x 6e-8 at worst).
TEST_CASE_TEMPLATE("the decomposed walk fused gives the unfused state", S, std::complex<double>, std::complex<float>) {
  const qrm::walk_model m(qrm::paper_4x4(), qrm::king_2d());
  qrm::walk_options o;
  o.steps = 2;
  o.prune = qrm::pruning::reachable;
  const qrm::program p = qrm::decompose(qrm::make_walk_program(m, m.light_map_start({1, 2, 0}), o).circuit).circuit;
  REQUIRE(p.size() > 500);
  const double bar = std::is_same_v<S, std::complex<double>> ? 1e-12 : 1e-5;
  qrm::state_vector<S> unfused(p.width());
  qrm::run(unfused, p);
  for (unsigned k = 2; k <= 6; ++k) {
    qrm::fusion_report rep;
    const qrm::program f = qrm::fuse(p, {k}, &rep);
    qrm::state_vector<S> fused(p.width());
    qrm::run(fused, f);
    double d = 0;
    for (std::size_t i = 0; i < unfused.amplitudes().size(); ++i)
      d = std::max(d, static_cast<double>(std::abs(fused.amplitudes()[i] - unfused.amplitudes()[i])));
    CAPTURE(k);
    CHECK(rep.ops_out < p.size() / 2);
    CHECK(d <= bar);
    MESSAGE(std::string(qrm::detail::scalar_name<S>()) << " width " << k << ": " << p.size() << " gates -> " << rep.ops_out
                                                       << " ops, largest |fused - unfused| " << d);
  }
}

TEST_CASE_TEMPLATE("every vector level of the matrix kernels gives the reference state", S, std::complex<double>,
                   std::complex<float>) {
  // Each level is forced in turn (a level this CPU lacks runs the best one below it, so on an
  // AVX-512 machine this covers the 512-bit, AVX2 and portable copies). Fused blocks of every
  // width put targets on qubit 0, qubit 1 and above, and states of 9 qubits leave 2..8 free.
  qrm::rng g(99);
  const std::size_t n = 9;
  const double tol = std::is_same_v<S, std::complex<double>> ? 1e-12 : 2e-5;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (unsigned k = 2; k <= 6; ++k) {
      const qrm::program f = qrm::fuse(random_gate_program(n, 60, g, true), {k});
      qrm::dense_options o;
      o.threads = 1;
      o.simd = level;
      qrm::state_vector<S> b(n, o);
      const auto start = random_unit_state(n, g);
      std::vector<S> rounded(start.size());
      for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = S(start[i]);
      b.set_amplitudes(rounded);
      reference_state ref(n);
      for (std::size_t i = 0; i < start.size(); ++i) ref.amp[i] = std::complex<double>(rounded[i]);
      qrm::run(b, f);
      f.emit(ref);
      std::vector<std::complex<double>> got(b.amplitudes().begin(), b.amplitudes().end());
      CAPTURE(static_cast<int>(level));
      CAPTURE(k);
      CHECK(max_diff(got, ref.amp) <= tol);
    }
}

TEST_CASE("complex<float> single-qubit gates on large states take the matrix kernel and match the reference") {
  // From 12 free qubits up, a complex<float> gate above target 0 runs through the k-qubit
  // matrix kernel (dense_kernels.hpp); 13 qubits with up to one control reach that path at
  // every target, on every vector level.
  qrm::rng g(5);
  const std::size_t n = 13;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512}) {
    qrm::dense_options o;
    o.threads = 1;
    o.simd = level;
    qrm::state_vector<std::complex<float>> b(n, o);
    const auto start = random_unit_state(n, g);
    std::vector<std::complex<float>> rounded(start.size());
    for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
    b.set_amplitudes(rounded);
    reference_state ref(n);
    for (std::size_t i = 0; i < start.size(); ++i) ref.amp[i] = std::complex<double>(rounded[i]);
    for (qubit_index t = 0; t < n; ++t)
      for (int controls = 0; controls < 2; ++controls) {
        const qrm::gate1 gate = random_gate1_unitary(g, true);
        std::vector<control> cs;
        if (controls) cs.push_back({static_cast<qubit_index>((t + 1 + g.below(n - 1)) % n), g.below(2) == 1});
        b.apply_gate1(gate, t, cs);
        ref.apply_gate1(gate, t, cs);
      }
    std::vector<std::complex<double>> got(b.amplitudes().begin(), b.amplitudes().end());
    CAPTURE(static_cast<int>(level));
    // 26 gates, each rounding amplitudes below 1 to float once: well inside 2e-5.
    CHECK(max_diff(got, ref.amp) <= 2e-5);
  }
}

TEST_CASE("complex<float> gates keep the norm when one gate repeats 2 x 10^4 times") {
  // Grover iterations repeat the same gates, so roundings that depend on the state add up. The
  // kernels compute in double and round each amplitude once: a random walk of ~sqrt(2e4)
  // per-gate norm errors of ~4e-9 (4096 amplitudes of 1/64 rounded to 6e-8), ~5e-7; measured
  // 2.0e-7. A float-arithmetic kernel (tried 2026-12-03 for speed at target 0), even with each
  // coefficient split into two floats, drifted 8.8e-5 here; the bar 2e-6 tells the two apart.
  qrm::rng g(21);
  const std::size_t n = 12;
  const qrm::gate1 gate = random_gate1_unitary(g, true);
  const auto start = random_unit_state(n, g);
  std::vector<std::complex<float>> rounded(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
  double worst = 0;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (qubit_index t : {0u, 1u, 7u}) {
      qrm::dense_options o;
      o.threads = 1;
      o.simd = level;
      qrm::state_vector<std::complex<float>> b(n, o);
      b.set_amplitudes(rounded);
      double before = 0, after = 0;
      for (const auto& z : b.amplitudes()) before += std::norm(std::complex<double>(z));
      for (int i = 0; i < 20000; ++i) b.apply_gate1(gate, t, {});
      for (const auto& z : b.amplitudes()) after += std::norm(std::complex<double>(z));
      CAPTURE(static_cast<int>(level));
      CAPTURE(t);
      CHECK(std::abs(after - before) <= 2e-6);
      worst = std::max(worst, std::abs(after - before));
    }
  MESSAGE("complex<float>, one gate repeated 2e4 times, largest norm drift over levels and targets: " << worst);
}

TEST_CASE_TEMPLATE("norm drift over 10^5 random gates, fused", S, std::complex<float>, std::complex<double>) {
  // The kernel tests' drift case (kernel_cases.hpp: 1e5 gates of 1 and 2 qubits, controls of
  // either value) fused to blocks of 3 qubits, so the matrix kernel's rounding is what
  // accumulates. Bars as there: each op rounds every amplitude once (eps 6e-8 float, 1.1e-16
  // double), a random walk over ~4e4 fused ops: ~1e-5 and ~1e-13; 1e-4 and 1e-10 leave room
  // (measured: 4.7e-7 and 3.7e-13).
  qrm::rng g(15);
  const std::size_t n = 8;
  const qrm::program p = small_gate_program(n, 100000, g);
  qrm::fusion_report rep;
  const qrm::program f = qrm::fuse(p, {3}, &rep);
  qrm::dense_options o;
  o.threads = 1;
  qrm::state_vector<S> b(n, o);
  qrm::run(b, f);
  const double drift = std::abs(b.norm_squared() - 1.0);
  const double bar = std::is_same_v<S, std::complex<float>> ? 1e-4 : 1e-10;
  MESSAGE(std::string(qrm::detail::scalar_name<S>()) << ": norm drift after 1e5 gates fused into " << rep.ops_out << " ops: " << drift);
  CHECK(rep.fused_blocks > 10000);
  CHECK(drift <= bar);
}

TEST_CASE("complex<float> in float arithmetic (float_math::single_precision) matches the reference at every level") {
  // Blocks on qubits 3 and up leave the lowest three free: there the float kernels take eight
  // neighbouring bases per register (AVX-512) or four (AVX2); blocks on low qubits gather four
  // bases per register. Bar as for double arithmetic's float states (2e-5): 80 gates fused
  // into ~30 blocks, each output a float sum of at most 64 products of size <= 1, rounding
  // ~64 x 6e-8 per block at worst and far less on average.
  qrm::rng g(31);
  const std::size_t n = 11;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (unsigned k : {2u, 3u, 4u, 5u}) {
      const qrm::program f = qrm::fuse(random_gate_program(n, 80, g, true), {k});
      const auto start = random_unit_state(n, g);
      std::vector<std::complex<float>> rounded(start.size());
      for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
      std::vector<std::complex<double>> got[2];
      for (int single = 0; single < 2; ++single) {
        auto b = float_state(n, level, single != 0, rounded);
        qrm::run(b, f);
        got[single].assign(b.amplitudes().begin(), b.amplitudes().end());
      }
      reference_state ref(n);
      for (std::size_t i = 0; i < start.size(); ++i) ref.amp[i] = std::complex<double>(rounded[i]);
      f.emit(ref);
      CAPTURE(static_cast<int>(level));
      CAPTURE(k);
      CHECK(max_diff(got[1], ref.amp) <= 2e-5);
      // The float kernels ran (they round differently from double arithmetic) wherever the CPU
      // has them; the portable level always computes in double.
      const bool vector_cpu = qrm::detail::resolve_simd(level) != qrm::simd_level::generic;
      CHECK((got[0] != got[1]) == vector_cpu);
    }
}

namespace {

// m applied to a random state against the reference, at every vector level: in complex<double>
// (bar 1e-12) and in complex<float> with double and float arithmetic (2e-5, against the
// reference run from the same state rounded to float). Returns the levels run (3).
int check_at_every_level(const qrm::dense_matrix& m, const std::vector<qubit_index>& ts,
                         const std::vector<qrm::control>& cs, std::size_t n, qrm::rng& g) {
  const auto start = random_unit_state(n, g);
  reference_state ref(n);
  ref.amp = start;
  ref.apply_unitary(m, ts, cs);
  std::vector<std::complex<float>> rounded(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
  reference_state ref_f(n);
  for (std::size_t i = 0; i < start.size(); ++i) ref_f.amp[i] = std::complex<double>(rounded[i]);
  ref_f.apply_unitary(m, ts, cs);
  int runs = 0;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512}) {
    CAPTURE(ts[0]);
    CAPTURE(static_cast<int>(level));
    qrm::dense_options o;
    o.threads = 1;
    o.simd = level;
    qrm::state_vector<std::complex<double>> d(n, o);
    d.set_amplitudes(start);
    d.apply_unitary(m, ts, cs);
    CHECK(max_diff(std::vector<std::complex<double>>(d.amplitudes().begin(), d.amplitudes().end()), ref.amp) <= 1e-12);
    for (bool single : {false, true}) {
      auto f = float_state(n, level, single, rounded);
      f.apply_unitary(m, ts, cs);
      const std::vector<std::complex<double>> got(f.amplitudes().begin(), f.amplitudes().end());
      CHECK(max_diff(got, ref_f.amp) <= 2e-5);
    }
    ++runs;
  }
  return runs;
}

}  // namespace

TEST_CASE("8x8 matrices with at most 4 non-zeros per row (fixed-width rows) match the reference at every level") {
  // Such matrices (most of the fused decomposed walk's blocks) run with 2 or 4 entries per row
  // instead of 8 (dense_batched.hpp): at row-list columns (ell_width) or, when every entry sits
  // at column row ^ d for d in one of xor_offset_sets, at columns fixed at compile time. Cases:
  // rows of 1..4 entries at random columns, and each offset set in full (row 0 with a zero
  // entry inside the set); real and complex; targets low / spread / high, with and without a
  // control; every level, double arithmetic (complex<double>, complex<float>) and float
  // arithmetic (complex<float>). Bars as for dense matrices: each output sums at most 4 products.
  qrm::rng g(32);
  const std::size_t n = 11;
  auto value = [&](bool complex_values) { return qrm::complex{2 * g.uniform() - 1, complex_values ? 2 * g.uniform() - 1 : 0.0}; };
  struct sparse_case {
    qrm::dense_matrix m;
    unsigned width, offsets;  // expected ell_width and xor_offset_set
    unsigned blocks = 0;      // expected order_blocks set (checked where offsets_known is false)
    bool offsets_known = true;
  };
  std::vector<sparse_case> cases;
  for (bool complex_values : {false, true}) {
    for (unsigned width : {1u, 2u, 3u, 4u}) {
      qrm::dense_matrix m(8);
      for (std::size_t e = 0; e < width; ++e) m(0, 7 - 2 * e) = value(complex_values);  // offsets 7, 5, 3, 1
      for (std::size_t r = 1; r < 8; ++r) {
        const std::size_t entries = 1 + static_cast<std::size_t>(g.uniform() * width);  // 1..width
        for (std::size_t e = 0; e < entries; ++e) m(r, static_cast<std::size_t>(g.uniform() * 8)) = value(complex_values);
      }
      cases.push_back({m, width <= 2 ? 2u : 4u, 0u});  // offset 7 lies in no set
    }
    for (unsigned set : qrm::detail::xor_offset_sets) {
      const auto w = static_cast<unsigned>(std::popcount(set));
      qrm::dense_matrix m(8);
      for (std::size_t r = 0; r < 8; ++r)
        for (unsigned e = 0; e < w; ++e) m(r, r ^ qrm::detail::nth_bit(set, e)) = value(complex_values);
      m(0, qrm::detail::nth_bit(set, w - 1)) = 0;
      cases.push_back({m, w, set});
    }
    // Direct sums of square blocks (sizes below) with rows and columns each in a scrambled order,
    // as fused permutations times rotations are: order_blocks puts them in the pair set {0, 1}
    // (blocks of at most 2) or the quadruple set {0, 1, 4, 5} (at most 4, packed into two groups
    // of 4 without splitting a block), or finds no order (3 + 3 + 2 does not pack; the last case
    // is not a direct sum of square blocks: 3 rows share 2 columns).
    const std::vector<std::pair<std::vector<unsigned>, unsigned>> block_cases = {
        {{2, 2, 2, 2}, 0x03}, {{1, 2, 1, 2, 2}, 0x03}, {{4, 4}, 0x33}, {{2, 4, 2}, 0x33},
        {{3, 1, 2, 2}, 0x33}, {{3, 3, 2}, 0},          {{}, 0}};
    for (const auto& [sizes, expected] : block_cases) {
      std::array<std::size_t, 8> row_of{0, 1, 2, 3, 4, 5, 6, 7}, col_of = row_of;
      for (std::size_t i = 7; i > 0; --i) {  // Fisher-Yates, both orders
        std::swap(row_of[i], row_of[static_cast<std::size_t>(g.uniform() * static_cast<double>(i + 1))]);
        std::swap(col_of[i], col_of[static_cast<std::size_t>(g.uniform() * static_cast<double>(i + 1))]);
      }
      qrm::dense_matrix m(8);
      unsigned widest = 0;
      if (sizes.empty()) {
        for (std::size_t r = 0; r < 3; ++r)
          for (std::size_t c = 0; c < 2; ++c) m(row_of[r], col_of[c]) = value(complex_values);
        for (std::size_t r = 3; r < 8; ++r)
          for (std::size_t c = 2; c < 8; c += 2) m(row_of[r], col_of[c + (r % 2)]) = value(complex_values);
        widest = 3;
      }
      std::size_t at = 0;
      for (unsigned size : sizes) {
        for (std::size_t r = at; r < at + size; ++r)
          for (std::size_t c = at; c < at + size; ++c) m(row_of[r], col_of[c]) = value(complex_values);
        at += size;
        widest = std::max(widest, size);
      }
      cases.push_back({m, widest <= 2 ? 2u : 4u, 0u, expected, false});
    }
  }
  int runs = 0;
  const std::vector<std::vector<qubit_index>> placements = {{0, 1, 2}, {3, 4, 5}, {0, 5, 9}, {10, 2, 7}, {8, 9, 10}};
  for (const sparse_case& c : cases) {
    const qrm::detail::csr_matrix rows = qrm::detail::csr_matrix::of(c.m);
    CHECK(qrm::detail::ell_width(rows) == c.width);
    if (c.offsets_known)
      CHECK(qrm::detail::xor_offset_set(rows) == c.offsets);
    else
      CHECK(qrm::detail::order_blocks(rows).set == c.blocks);
    for (const auto& ts : placements)
      for (const std::vector<qrm::control>& cs : {std::vector<qrm::control>{}, std::vector<qrm::control>{{6, true}}}) {
        CAPTURE(c.width);
        CAPTURE(c.offsets);
        CAPTURE(c.blocks);
        CAPTURE(c.m.is_real());
        runs += check_at_every_level(c.m, ts, cs, n, g);
      }
  }
  CHECK(runs == (16 + 14) * 5 * 2 * 3);
}

TEST_CASE("16x16 to 64x64 matrices with at most 8 non-zeros per row (fixed-width rows) match the reference") {
  // Fused blocks of 4 to 6 qubits run with 2, 4 or 8 entries per row at listed columns
  // (ell_width), rows padded with zeros, instead of row lists. Cases: rows of 1..8 entries at
  // random columns (the widest row sets the form; 9 entries in one row: no fixed width), real
  // and complex; targets low (no neighbouring bases: row lists), spread and high, with and
  // without a control; every level, double and float arithmetic. Bars as for the 8x8 forms.
  qrm::rng g(33);
  const std::size_t n = 12;
  auto value = [&](bool complex_values) { return qrm::complex{2 * g.uniform() - 1, complex_values ? 2 * g.uniform() - 1 : 0.0}; };
  int runs = 0;
  for (std::size_t dim : {std::size_t{16}, std::size_t{32}, std::size_t{64}})
    for (bool complex_values : {false, true})
      for (unsigned widest : {1u, 2u, 3u, 4u, 6u, 8u, 9u}) {
        qrm::dense_matrix m(dim);
        for (std::size_t e = 0; e < widest; ++e) m(0, dim - 1 - e) = value(complex_values);
        for (std::size_t r = 1; r < dim; ++r) {
          const std::size_t entries = 1 + static_cast<std::size_t>(g.uniform() * std::min(widest, 8u));  // 1..widest
          for (std::size_t e = 0; e < entries; ++e)
            m(r, static_cast<std::size_t>(g.uniform() * static_cast<double>(dim))) = value(complex_values);
        }
        const unsigned expected = widest <= 2 ? 2 : widest <= 4 ? 4 : widest <= 8 ? 8 : 0;
        CAPTURE(dim);
        CAPTURE(widest);
        CAPTURE(complex_values);
        CHECK(qrm::detail::ell_width(qrm::detail::csr_matrix::of(m)) == expected);
        const std::size_t k = std::bit_width(dim) - 1;
        const std::vector<std::vector<qubit_index>> placements = {
            {0, 1, 2, 3, 4, 5}, {1, 3, 5, 7, 9, 11}, {11, 10, 9, 8, 7, 5}};
        for (const auto& all : placements) {
          const std::vector<qubit_index> ts(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k));
          for (const std::vector<qrm::control>& cs : {std::vector<qrm::control>{}, std::vector<qrm::control>{{6, false}}}) {
            runs += check_at_every_level(m, ts, cs, n, g);
          }
        }
      }
  CHECK(runs == 3 * 2 * 7 * 3 * 2 * 3);
}

TEST_CASE("a fused block drops the rounding residue of its product, and only that") {
  // Phases that cancel and rotations by pi leave parts near 1e-17 where the product is exactly
  // 0 (fuse.hpp, drop_rounding_residue); kept, they make the block complex and dense to the
  // kernels. CX, P(t), Ry(pi), P(-t), CX on two qubits is real with one non-zero per row; an
  // Ry by 1e-13 (entries of 5e-14, far above the residue) survives.
  const double t = 0.3;
  qrm::program p(2);
  p.push(qrm::op::gate1_op{qrm::gate::x(), 1, {{0, true}}});
  p.push(qrm::op::gate1_op{qrm::gate::phase(t), 0, {}});
  p.push(qrm::op::gate1_op{qrm::gate::ry(std::acos(-1.0)), 1, {}});
  p.push(qrm::op::gate1_op{qrm::gate::phase(-t), 0, {}});
  p.push(qrm::op::gate1_op{qrm::gate::x(), 1, {{0, true}}});
  const qrm::program fused = qrm::fuse(p, {2});
  REQUIRE(fused.size() == 1);
  const auto& block = std::get<qrm::op::unitary_op>(fused.ops()[0]).matrix;
  CHECK(block.is_real());
  for (std::size_t r = 0; r < 4; ++r) {
    std::size_t nonzero = 0;
    for (std::size_t c = 0; c < 4; ++c) nonzero += block(r, c) != qrm::complex{};
    CHECK(nonzero == 1);
  }
  qrm::program q(2);
  q.push(qrm::op::gate1_op{qrm::gate::ry(1e-13), 0, {}});
  q.push(qrm::op::gate1_op{qrm::gate::x(), 1, {{0, true}}});
  const qrm::program fused_q = qrm::fuse(q, {2});
  REQUIRE(fused_q.size() == 1);
  const auto& kept = std::get<qrm::op::unitary_op>(fused_q.ops()[0]).matrix;
  std::size_t tiny = 0;
  for (const qrm::complex& z : kept.data) tiny += z != qrm::complex{} && std::abs(z) < 1e-12;
  CHECK(tiny == 4);  // the rotation's two off-diagonal entries, once for each value of qubit 1
}

TEST_CASE("4x4 and 8x8 matrices with targets among the lanes of one register match the reference") {
  // At AVX-512 a register holds amplitudes 0..7 of a run in float arithmetic (0..3 in double,
  // 0..7 of a real double state), so targets on qubits 0..2 (0..1) are permutations of its lanes
  // (dense_lanes.hpp), compiled per set of such targets and for real and complex matrices: every non-empty subset of
  // {0, 1, 2} that fits the width, completed with targets from {4, 7, 9}, in scrambled order; dense and half-empty
  // matrices, real and complex; no control, a control above the lanes, and one inside them
  // (which takes the gathered bases instead). Bars: 2e-5 in float arithmetic as for the other
  // float blocks; complex<float> in double arithmetic rounds only when it stores (2^-24 of each
  // amplitude, bar 1e-6); complex<double> and real double 1e-12.
  qrm::rng g(33);
  const unsigned n = 11;
  int runs = 0;
  for (unsigned width : {2u, 3u})
  for (unsigned low = 1; low < 8; ++low)
    for (bool complex_values : {false, true})
      for (bool half_empty : {false, true}) {
        if (static_cast<unsigned>(std::popcount(low)) > width) continue;
        std::vector<qubit_index> ts;
        for (qubit_index q = 0; q < 3; ++q)
          if ((low >> q) & 1u) ts.push_back(q);
        for (qubit_index q : {9u, 4u, 7u})
          if (ts.size() < width) ts.push_back(q);
        std::rotate(ts.begin(), ts.begin() + 1, ts.end());  // not in increasing order
        const std::size_t dim = std::size_t{1} << width;
        qrm::dense_matrix m(dim);
        for (std::size_t r = 0; r < dim; ++r)
          for (std::size_t c = 0; c < dim; ++c)
            if (!half_empty || g.uniform() < 0.5) m(r, c) = {2 * g.uniform() - 1, complex_values ? 2 * g.uniform() - 1 : 0.0};
        const qubit_index inside = (low & 2u) ? 10 : 1;  // a control among the lanes when qubit 1 is free
        for (const std::vector<qrm::control>& cs :
             {std::vector<qrm::control>{}, std::vector<qrm::control>{{10, true}}, std::vector<qrm::control>{{inside, false}}}) {
          const auto start = random_unit_state(n, g);
          std::vector<std::complex<float>> rounded(start.size());
          for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
          reference_state ref(n);
          for (std::size_t i = 0; i < start.size(); ++i) ref.amp[i] = std::complex<double>(rounded[i]);
          ref.apply_unitary(m, ts, cs);
          auto b = float_state(n, qrm::simd_level::avx512, true, rounded);
          b.apply_unitary(m, ts, cs);
          const std::vector<std::complex<double>> got(b.amplitudes().begin(), b.amplitudes().end());
          CAPTURE(width);
          CAPTURE(low);
          CAPTURE(complex_values);
          CAPTURE(half_empty);
          CAPTURE(cs.size());
          CHECK(max_diff(got, ref.amp) <= 2e-5);
          auto in_double = float_state(n, qrm::simd_level::avx512, false, rounded);
          in_double.apply_unitary(m, ts, cs);
          CHECK(max_diff(std::vector<std::complex<double>>(in_double.amplitudes().begin(), in_double.amplitudes().end()),
                         ref.amp) <= 1e-6);
          qrm::dense_options o;
          o.threads = 1;
          o.simd = qrm::simd_level::avx512;
          qrm::state_vector<std::complex<double>> d(n, o);
          d.set_amplitudes(start);
          reference_state ref_d(n);
          ref_d.amp = start;
          ref_d.apply_unitary(m, ts, cs);
          d.apply_unitary(m, ts, cs);
          CHECK(max_diff(std::vector<std::complex<double>>(d.amplitudes().begin(), d.amplitudes().end()), ref_d.amp) <=
                1e-12);
          if (!complex_values) {  // real amplitudes: eight doubles per register, qubits 0..2 as lanes
            std::vector<double> real_start(start.size());
            for (std::size_t i = 0; i < start.size(); ++i) real_start[i] = start[i].real();
            qrm::state_vector<double> r(n, o);
            r.set_amplitudes(real_start);
            reference_state ref_r(n);
            for (std::size_t i = 0; i < start.size(); ++i) ref_r.amp[i] = real_start[i];
            ref_r.apply_unitary(m, ts, cs);
            r.apply_unitary(m, ts, cs);
            double worst = 0;
            for (std::size_t i = 0; i < start.size(); ++i) worst = std::max(worst, std::abs(r.amplitudes()[i] - ref_r.amp[i]));
            CHECK(worst <= 1e-12);
          }
          ++runs;
        }
      }
  CHECK(runs == (6 + 7) * 2 * 2 * 3);  // width 2: the six subsets of one or two lane qubits
}

TEST_CASE("complex<float> in float arithmetic: single-qubit gates on targets 0..2 match the reference") {
  // Targets 0..2 take dense_pairs.hpp's in-register kernel where the controls leave whole
  // vectors (none below qubit 3, or 2 with AVX2); a control on qubits 0..2 falls back to the
  // pair loop or the matrix kernel. 60 gates, each rounding in float: bar 2e-5 as above.
  qrm::rng g(41);
  const std::size_t n = 12;
  const auto start = random_unit_state(n, g);
  std::vector<std::complex<float>> rounded(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) rounded[i] = std::complex<float>(start[i]);
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512}) {
    std::vector<std::complex<double>> got[2];
    reference_state ref(n);
    for (std::size_t i = 0; i < start.size(); ++i) ref.amp[i] = std::complex<double>(rounded[i]);
    qrm::rng gates(7);
    for (int single = 0; single < 2; ++single) {
      auto b = float_state(n, level, single != 0, rounded);
      qrm::rng pick(8);
      for (int i = 0; i < 60; ++i) {
        const auto t = static_cast<qubit_index>(pick.below(3));
        const qrm::gate1 gate = random_gate1_unitary(pick, true);
        std::vector<control> cs;
        for (std::uint64_t c = pick.below(3); c-- > 0;) {
          const auto q = static_cast<qubit_index>(pick.below(n));
          if (q != t && std::none_of(cs.begin(), cs.end(), [&](const control& x) { return x.qubit == q; }))
            cs.push_back({q, pick.below(2) == 1});
        }
        b.apply_gate1(gate, t, cs);
        if (single) ref.apply_gate1(gate, t, cs);
      }
      got[single].assign(b.amplitudes().begin(), b.amplitudes().end());
    }
    CAPTURE(static_cast<int>(level));
    CHECK(max_diff(got[1], ref.amp) <= 2e-5);
    const bool vector_cpu = qrm::detail::resolve_simd(level) != qrm::simd_level::generic;
    CHECK((got[0] != got[1]) == vector_cpu);
  }
}

TEST_CASE("float arithmetic: norm drift over 10^5 random gates fused stays within 1e-4") {
  // As the fused drift test above (8 qubits, blocks of 3), in float arithmetic: each op rounds
  // inside its sums as well as at the end, ~4e4 ops of independent roundings; bar 1e-4, the
  // unfused kernels' bound (kernel_cases.hpp).
  qrm::rng g(17);
  const std::size_t n = 8;
  const qrm::program p = small_gate_program(n, 100000, g);
  qrm::fusion_report rep;
  const qrm::program f = qrm::fuse(p, {3}, &rep);
  qrm::dense_options o;
  o.threads = 1;
  o.math = qrm::float_math::single_precision;
  qrm::state_vector<std::complex<float>> b(n, o);
  qrm::run(b, f);
  const double drift = std::abs(b.norm_squared() - 1.0);
  MESSAGE("complex<float>, float arithmetic: norm drift after 1e5 gates fused into " << rep.ops_out << " ops: " << drift);
  CHECK(drift <= 1e-4);
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
    // Every output op is either an input op, unchanged, or written for a fused block: a matrix or
    // gate whose controls (qubits the block never flips) lie on qubits 3 and above.
    std::size_t unchanged = 0;
    for (const qrm::op::any& o : f.ops()) {
      if (std::any_of(p.ops().begin(), p.ops().end(), [&](const qrm::op::any& i) { return same_op(i, o); })) {
        ++unchanged;
        continue;
      }
      CHECK(qrm::op_qubits(o).size() <= k);
      CHECK((o.index() == 0 || o.index() == 1));
      qrm::visit_op(o, [](const auto& x) {
        for (const control& c : x.controls) CHECK(c.qubit >= 3);
      });
    }
    CHECK(f.size() <= unchanged + rep.block_ops);  // a block's piece may equal an input op
    CHECK(rep.block_ops >= rep.fused_blocks);
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

TEST_CASE("a block that never flips a qubit above 2 is written under it as a control, identities dropped") {
  // H0, CX(c -> 0), H0 is one block on {0, c}. It never flips c: under c = 0 it is H H = I
  // (dropped), under c = 1 it is H X H = Z, by hand. With c = 4 that is one controlled Z; with
  // c = 2 (a qubit inside a cache line, where a control saves no memory) the block stays whole.
  for (const qubit_index c : {4u, 2u}) {
    qrm::program p(5);
    p.apply_gate1(qrm::gate::h(), 0, {});
    const control cc[] = {{c, true}};
    p.apply_gate1(qrm::gate::x(), 0, cc);
    p.apply_gate1(qrm::gate::h(), 0, {});
    qrm::fusion_report rep;
    const qrm::program f = qrm::fuse(p, {2}, &rep);
    CAPTURE(c);
    REQUIRE(f.size() == 1);
    CHECK(rep.fused_blocks == 1);
    CHECK(rep.block_ops == 1);
    if (c == 4) {
      REQUIRE(f.ops()[0].index() == 0);
      const auto& g = *std::get_if<qrm::op::gate1_op>(&f.ops()[0]);
      CHECK(g.target == 0);
      REQUIRE(g.controls.size() == 1);
      CHECK(g.controls[0].qubit == 4);
      CHECK(g.controls[0].value);
      const double z[2][2] = {{1, 0}, {0, -1}};
      for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j) CHECK(std::abs(g.gate.m[i][j] - z[i][j]) < 1e-15);
    } else {
      REQUIRE(f.ops()[0].index() == 1);
      const auto& u = *std::get_if<qrm::op::unitary_op>(&f.ops()[0]);
      CHECK(u.targets == std::vector<qubit_index>{0, 2});
      CHECK(u.controls.empty());
    }
  }
}

TEST_CASE("values of the never-flipped qubits whose products are equal share one piece under fewer controls") {
  // phase(0.4) on 5, Ry(0.7) on 3 under q4 = 1, phase(-0.4) on 5: one block on {3, 4, 5} at width
  // 3 that flips only qubit 3. By hand, under q4 = 0 it is the identity, under q4 = 1 it is Ry(0.7)
  // whatever q5 (the phases cancel, to rounding): one op, Ry(0.7) on 3 under q4 = 1, where a piece
  // per value of (q4, q5) wrote two.
  qrm::program p(6);
  p.apply_gate1(qrm::gate::phase(0.4), 5, {});
  const control c4[] = {{4, true}};
  p.apply_gate1(qrm::gate::ry(0.7), 3, c4);
  p.apply_gate1(qrm::gate::phase(-0.4), 5, {});
  qrm::fusion_report rep;
  const qrm::program f = qrm::fuse(p, {3}, &rep);
  CHECK(rep.fused_blocks == 1);
  CHECK(rep.block_ops == 1);
  REQUIRE(f.size() == 1);
  REQUIRE(f.ops()[0].index() == 0);
  const auto& g = *std::get_if<qrm::op::gate1_op>(&f.ops()[0]);
  CHECK(g.target == 3);
  REQUIRE(g.controls.size() == 1);
  CHECK(g.controls[0].qubit == 4);
  CHECK(g.controls[0].value);
  const double c = std::cos(0.35), s = std::sin(0.35);
  const double ry[2][2] = {{c, -s}, {s, c}};
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t j = 0; j < 2; ++j) CHECK(std::abs(g.gate.m[i][j] - ry[i][j]) < 1e-15);
}

TEST_CASE("a gate that would widen its blocks past the limit closes the smaller ones and joins the rest") {
  // H0, H1, CX(0 -> 1), H2, CX(1 -> 2) at width 2: the first three fuse into one block on {0, 1};
  // H2 finds no block with room and opens {2}; CX(1 -> 2) cannot have both blocks ({0, 1, 2}),
  // so it keeps the one that still fits with it ({2}, giving {1, 2}) and {0, 1} closes first.
  qrm::program p(3);
  p.apply_gate1(qrm::gate::h(), 0, {});
  p.apply_gate1(qrm::gate::h(), 1, {});
  const control c0[] = {{0, true}}, c1[] = {{1, true}};
  p.apply_gate1(qrm::gate::x(), 1, c0);
  p.apply_gate1(qrm::gate::h(), 2, {});
  p.apply_gate1(qrm::gate::x(), 2, c1);
  qrm::fusion_report rep;
  const qrm::program f2 = qrm::fuse(p, {2}, &rep);
  REQUIRE(f2.size() == 2);
  CHECK(f2.ops()[0].index() == 1);
  CHECK(qrm::op_qubits(f2.ops()[0]) == std::vector<qubit_index>{0, 1});
  CHECK(f2.ops()[1].index() == 1);
  CHECK(qrm::op_qubits(f2.ops()[1]) == std::vector<qubit_index>{1, 2});
  CHECK(rep.fused_blocks == 2);
  CHECK(qrm::fuse(p, {3}).size() == 1);
  CHECK(qrm::fuse(p, {1}).size() == 5);  // nothing shares a single qubit but H alone: no block of two
}

TEST_CASE("gates on disjoint qubits share a block as a tensor product when it has room") {
  qrm::program p(2);
  p.apply_gate1(qrm::gate::h(), 0, {});
  p.apply_gate1(qrm::gate::x(), 1, {});
  qrm::fusion_report rep;
  const qrm::program f = qrm::fuse(p, {2}, &rep);
  REQUIRE(f.size() == 1);
  REQUIRE(f.ops()[0].index() == 1);
  const auto& u = *std::get_if<qrm::op::unitary_op>(&f.ops()[0]);
  CHECK(u.targets == std::vector<qubit_index>{0, 1});
  // X (qubit 1) (x) H (qubit 0), bit 0 of the index = qubit 0, multiplied by hand.
  const double r = 1 / std::sqrt(2.0);
  const double expected[4][4] = {{0, 0, r, r}, {0, 0, r, -r}, {r, r, 0, 0}, {r, -r, 0, 0}};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) CHECK(std::abs(u.matrix(i, j) - expected[i][j]) < 1e-15);
  qrm::fusion_options apart;
  apart.max_qubits = 2;
  apart.merge_disjoint = false;
  CHECK(qrm::fuse(p, apart).size() == 2);
  CHECK(qrm::fuse(p, {1}).size() == 2);  // no room at width 1
}

TEST_CASE("fusion refuses a width outside 1..6") {
  const qrm::program p(2);
  CHECK_THROWS_WITH_AS(qrm::fuse(p, {0}), "fuse: max_qubits must be 1..6, got 0", std::invalid_argument);
  CHECK_THROWS_WITH_AS(qrm::fuse(p, {7}), "fuse: max_qubits must be 1..6, got 7", std::invalid_argument);
}

TEST_CASE("estimated_passes follows its cost model, op by op") {
  // The model (fuse.hpp): 1-qubit gates 2^-controls passes (at least 1/8); a k-qubit matrix
  // max(1, 0.4 + 0.03 d + 0.28 w) for d = 2^k and w its widest row, 0.3 d - 0.1 when dense and
  // 4 < d <= 16, twice that with a target on qubits 0-2. Each case alone, then summed.
  qrm::rng g(41);
  qrm::dense_matrix dense8(8), perm8(8), pairs64(64);
  for (std::size_t r = 0; r < 8; ++r) {
    for (std::size_t c = 0; c < 8; ++c) dense8(r, c) = qrm::complex{g.uniform() + 0.1, 0.0};
    perm8(r, (r + 3) % 8) = 1;
  }
  for (std::size_t r = 0; r < 64; ++r) pairs64(r, r) = pairs64(r, r ^ 5) = 0.5;
  const std::vector<std::pair<qrm::op::any, double>> cases = {
      {qrm::op::gate1_op{qrm::gate::h(), 5, {}}, 1.0},
      {qrm::op::gate1_op{qrm::gate::x(), 1, {{0, true}}}, 0.5},
      {qrm::op::gate1_op{qrm::gate::x(), 2, {{0, true}, {1, true}}}, 0.25},
      {qrm::op::gate1_op{qrm::gate::x(), 8, {{0, true}, {1, true}, {2, true}, {3, true}}}, 0.125},
      {qrm::op::unitary_op{dense8, {3, 4, 5}, {}}, 0.3 * 8 - 0.1},
      {qrm::op::unitary_op{dense8, {0, 4, 5}, {}}, 2 * (0.3 * 8 - 0.1)},
      {qrm::op::unitary_op{perm8, {3, 4, 5}, {}}, 1.0},
      {qrm::op::unitary_op{pairs64, {3, 4, 5, 6, 7, 8}, {}}, 0.4 + 0.03 * 64 + 0.28 * 2},
      {qrm::op::unitary_op{pairs64, {3, 4, 5, 6, 7, 8}, {{0, false}}}, (0.4 + 0.03 * 64 + 0.28 * 2) / 2},
      {qrm::op::add_op{1, {3, 4, 5}, {}}, 1.0},
  };
  qrm::program all(9);
  double sum = 0;
  for (const auto& c : cases) {
    const double passes = c.second;
    qrm::program one(9);
    one.push(c.first);
    all.push(c.first);
    sum += passes;
    CAPTURE(passes);
    CHECK(qrm::estimated_passes(one) == doctest::Approx(passes).epsilon(1e-12));
  }
  CHECK(qrm::estimated_passes(all) == doctest::Approx(sum).epsilon(1e-12));
}

TEST_CASE("fuse_cheapest keeps the width the cost model rates cheapest, and the state") {
  // Candidates 2..6. The decomposed walk's blocks are sparse (permutations and rotations), so a
  // wide block replaces many gates at a small cost; dense random 1-qubit gates and CNOTs make
  // dense blocks whose cost grows faster than the gates they replace, so 2 wins. Either way the result is
  // fuse(p, {chosen}) and runs to the unfused state.
  const qrm::walk_model m(qrm::paper_4x4(), qrm::king_2d());
  qrm::walk_options o;
  o.steps = 2;
  o.prune = qrm::pruning::reachable;
  const qrm::program walk = qrm::decompose(qrm::make_walk_program(m, m.light_map_start({1, 2, 0}), o).circuit).circuit;
  qrm::rng g(42);
  qrm::program dense(12);
  for (int i = 0; i < 400; ++i) {
    const auto a = static_cast<qubit_index>(g.below(12)), b = static_cast<qubit_index>((a + 1 + g.below(11)) % 12);
    if (i % 3 == 2)
      dense.push(qrm::op::gate1_op{qrm::gate::x(), b, {{a, true}}});
    else
      dense.apply_gate1(random_gate1_unitary(g, false), a, {});
  }
  for (const qrm::program* p : std::array<const qrm::program*, 2>{&walk, &dense}) {
    qrm::fusion_report chosen;
    const qrm::program f = qrm::fuse_cheapest(*p, &chosen);
    CAPTURE(chosen.max_qubits);
    CHECK(chosen.estimated_passes == qrm::estimated_passes(f));
    for (unsigned k = 2; k <= 6; ++k) {
      qrm::fusion_report rep;
      const qrm::program fk = qrm::fuse(*p, {k}, &rep);
      CHECK(chosen.estimated_passes <= rep.estimated_passes);
      if (k == chosen.max_qubits) CHECK(fk.size() == f.size());
    }
    CHECK((p == &walk ? chosen.max_qubits > 3 : chosen.max_qubits == 2));
    MESSAGE(std::string(p == &walk ? "decomposed walk" : "dense random") << ": width " << chosen.max_qubits << ", "
            << chosen.ops_out << " ops, estimated " << chosen.estimated_passes << " passes");
    qrm::state_vector<std::complex<double>> a(p->width()), b(p->width());
    qrm::run(a, *p);
    qrm::run(b, f);
    double d = 0;
    for (std::size_t i = 0; i < a.amplitudes().size(); ++i) d = std::max(d, std::abs(a.amplitudes()[i] - b.amplitudes()[i]));
    CHECK(d <= 1e-12);
  }
}

namespace {
// A fusion_trace describes `fused` (made from p): every output op belongs to exactly one input
// op written alone (the same kind on the same qubits) or to one block, whose qubits hold its ops'.
void check_trace(const qrm::program& p, const qrm::program& fused, const qrm::fusion_trace& t) {
  REQUIRE(t.output_of.size() == p.size());
  REQUIRE(t.block_of.size() == p.size());
  std::vector<int> covered(fused.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    CAPTURE(i);
    CHECK((t.output_of[i] == qrm::fusion_trace::none) != (t.block_of[i] == qrm::fusion_trace::none));
    if (t.output_of[i] == qrm::fusion_trace::none) continue;
    REQUIRE(t.output_of[i] < fused.size());
    ++covered[t.output_of[i]];
    CHECK(fused.ops()[t.output_of[i]].index() == p.ops()[i].index());
    CHECK(qrm::op_qubits(fused.ops()[t.output_of[i]]) == qrm::op_qubits(p.ops()[i]));
  }
  for (std::size_t b = 0; b < t.blocks.size(); ++b) {
    const qrm::fusion_trace::block& blk = t.blocks[b];
    REQUIRE(blk.last_output <= fused.size());
    for (std::size_t o = blk.first_output; o < blk.last_output; ++o) ++covered[o];
    for (std::size_t i : blk.ops) {
      CHECK(t.block_of[i] == b);
      for (qrm::qubit_index q : qrm::op_qubits(p.ops()[i]))
        CHECK(std::find(blk.qubits.begin(), blk.qubits.end(), q) != blk.qubits.end());
    }
  }
  CHECK(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
}
}  // namespace

TEST_CASE("fuse_cheapest with chunk qubits keeps the cheaper of fusing within runs and across, and the state") {
  // Candidates: widths 2-3 both ways, 4-6 across the program (see fuse_cheapest).
  qrm::rng g(8);
  qrm::dense_options o;
  o.chunk_bytes = 64 * sizeof(std::complex<double>);  // chunks of 6 qubits
  o.chunk_min_passes = 0;
  const qrm::fusion_options within = qrm::dense_fusion_options<std::complex<double>>({}, o);
  std::size_t chose_runs = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const qrm::program p = random_gate_program(10, 150, g, true);
    qrm::fusion_report chosen;
    qrm::fusion_trace trace;
    const qrm::program f = qrm::fuse_cheapest(p, within, &chosen, true, &trace);
    CHECK(chosen.estimated_passes == qrm::estimated_passes(f));
    check_trace(p, f, trace);
    for (unsigned k = 2; k <= 6; ++k)
      for (const unsigned scope : {6u, 0u}) {
        if (scope != 0 && k > 3) continue;  // blocks of 4+ qubits wait on arithmetic: fused across only
        qrm::fusion_options fo = within;
        fo.max_qubits = k;
        fo.chunk_qubits = scope;
        qrm::fusion_report rep;
        (void)qrm::fuse(p, fo, &rep);
        CAPTURE(k);
        CAPTURE(scope);
        CHECK(chosen.estimated_passes <= rep.estimated_passes);
      }
    chose_runs += chosen.chunk_qubits == 6;
    for (unsigned k = 2; k <= 4; ++k) {  // one width: the cheaper scope at 2-3, across at 4
      qrm::fusion_options fo = within;
      fo.max_qubits = k;
      qrm::fusion_report one, runs, across;
      qrm::fusion_trace one_trace;
      check_trace(p, qrm::fuse_cheaper_scope(p, fo, &one, &one_trace), one_trace);
      (void)qrm::fuse(p, fo, &runs);
      fo.chunk_qubits = 0;
      (void)qrm::fuse(p, fo, &across);
      CAPTURE(k);
      CHECK(one.estimated_passes == (k <= 3 ? std::min(runs.estimated_passes, across.estimated_passes)
                                            : across.estimated_passes));
      if (k == 4) CHECK(one.chunk_qubits == 0);
    }
    qrm::fusion_report forced;
    (void)qrm::fuse_cheapest(p, within, &forced, false);
    CHECK(forced.chunk_qubits == 6);
    qrm::state_vector<std::complex<double>> a(10, o), b(10, o);
    qrm::run(a, p);
    qrm::run(b, f);
    double d = 0;
    for (std::size_t i = 0; i < a.amplitudes().size(); ++i) d = std::max(d, std::abs(a.amplitudes()[i] - b.amplitudes()[i]));
    CHECK(d <= 1e-12);
  }
  MESSAGE("fused within runs in " << chose_runs << " of 6 programs");
}
