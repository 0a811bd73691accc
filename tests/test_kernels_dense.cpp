// The kernel tests (kernel_cases.hpp) on the dense backend, every amplitude type, plus the
// dense backend's threading.
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <qrm/backends/detail/dense_blocked.hpp>  // the kernels' internals some cases check

#include "kernel_cases.hpp"
#include "support/random_programs.hpp"

#define QRM_DENSE_BACKENDS                                                                            \
  qrm::state_vector<double>, qrm::state_vector<float>, qrm::state_vector<std::complex<double>>, \
      qrm::state_vector<std::complex<float>>
TEST_CASE_TEMPLATE_INVOKE(gate1_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(unitary_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(add_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(mux_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(norm_drift, QRM_DENSE_BACKENDS);
// Only the dense backend uses threads (the compact one is single-threaded; its determinism is
// tested in test_compact.cpp).
TEST_CASE_TEMPLATE_INVOKE(thread_determinism, qrm::state_vector<double>, qrm::state_vector<std::complex<double>>);
TEST_CASE_TEMPLATE_INVOKE(chunked_subspaces, qrm::state_vector<double>, qrm::state_vector<std::complex<float>>);

// A 1-qubit gate on a state of 12 or more free qubits may run on the matrix kernels instead of
// the pair loop (kernel_gate1: complex<float> above target 0, complex<double> from target 4), a
// path the 4-qubit placements above never take: every target of 14 qubits, without controls and
// under one or two (either value), real and complex gates, against the reference.
TEST_CASE_TEMPLATE("single-qubit gates on 14 qubits match the reference at every target", B, QRM_DENSE_BACKENDS) {
  using T = backend_traits<B>;
  qrm::rng g(12);
  const std::size_t n = 14;
  std::vector<qrm::gate1> gates = {qrm::gate::h(), qrm::gate::ry(0.7), random_gate1_nonunitary(g, false)};
  if constexpr (T::is_complex) gates.push_back(random_gate1_nonunitary(g, true));
  for (qubit_index t = 0; t < n; ++t) {
    const auto a = static_cast<qubit_index>((t + 3) % n), b = static_cast<qubit_index>((t + 9) % n);
    const std::vector<std::vector<control>> control_sets = {{}, {{a, true}}, {{a, false}, {b, true}}};
    for (const auto& cs : control_sets)
      for (const auto& gate : gates) {
        const double d = compare_with_reference<B>(n, g, [&](auto& s) { s.apply_gate1(gate, t, cs); });
        INFO("kind " << qrm::gate1_name(gate.kind) << " target " << t << " controls " << cs.size());
        CHECK(d <= T::tolerance);
      }
  }
}

// Complex 1-qubit gates on qubits 0-3 take a kernel per scalar, vector level and arithmetic
// (complex<float>, dense_pairs.hpp: float lanes at AVX2 / AVX-512, widened pairs in double
// arithmetic at AVX2; both scalars: lanes at AVX-512 on qubits 0-1, the matrix kernel above, the
// pair loop at the generic level), each only where no control splits its vector: every level
// asked for, both arithmetics, one and two threads, controls below, between and above, against
// the reference (float rounding: 2e-5). 14 qubits, so that the matrix kernel's path is taken
// under two controls.
TEST_CASE_TEMPLATE("complex 1-qubit gates on qubits 0-3 match the reference at every level and arithmetic", S,
                   std::complex<float>, std::complex<double>) {
  using T = backend_traits<qrm::state_vector<S>>;
  qrm::rng g(13);
  const std::size_t n = 14;
  const std::vector<qrm::gate1> gates = {qrm::gate::h(), qrm::gate::ry(0.7), random_gate1_nonunitary(g, true)};
  const std::vector<std::vector<control>> control_sets = {{}, {{0, true}}, {{1, false}}, {{2, true}}, {{3, true}, {13, false}}};
  std::size_t cases = 0;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (const qrm::float_math math : {qrm::float_math::double_precision, qrm::float_math::single_precision})
      for (unsigned threads : {1u, 2u})
        for (qubit_index t = 0; t < 4; ++t)
          for (const auto& cs : control_sets) {
            if (!cs.empty() && cs[0].qubit == t) continue;
            for (const auto& gate : gates) {
              qrm::dense_options o;
              o.threads = threads;
              o.simd = level;
              o.math = math;
              qrm::state_vector<S> b(n, o);
              b.set_min_parallel(1);
              T::load(b, random_state(n, g, true));
              reference_state ref(n);
              ref.amp = T::dump(b);
              ref.apply_gate1(gate, t, cs);
              b.apply_gate1(gate, t, cs);
              INFO("level " << std::string(qrm::simd_level_name(level)) << " float arithmetic "
                            << (math == qrm::float_math::single_precision) << " threads " << threads << " target " << t
                            << " controls " << cs.size() << " kind " << qrm::gate1_name(gate.kind));
              CHECK(max_diff(ref.amp, T::dump(b)) <= T::tolerance);
              ++cases;
            }
          }
  CHECK(cases == 3 * 2 * 2 * (4 * 4) * 3);
}

// Partners 2^28 bytes apart or more (target 25 of a 26-qubit complex<float> state) take the
// grouped form of the matrix kernel (detail::aliased_streams), a path no smaller state takes: a
// complex 2x2 gate on qubit 25 and a 4x4 matrix on (25, 5) with a control above qubit 3 (grouped)
// or below it (not), in float and double arithmetic, one and two threads, against the matrix
// applied here at 2^18 random amplitudes and the first and last 2^12 (a whole state's reference
// took 28 s). Float rounding of values below 4 in a 4-term sum: 1e-5 is 10 times the error
// expected.
TEST_CASE("matrices and X on qubits 2^28 bytes apart match the reference") {
  using cf = std::complex<float>;
  const unsigned n = 26;
  REQUIRE(qrm::detail::aliased_streams<cf>(2, std::uint64_t{1} << 25, 0));
  REQUIRE(qrm::detail::aliased_streams<cf>(4, (std::uint64_t{1} << 25) | 32, std::uint64_t{1} << 12));
  REQUIRE(!qrm::detail::aliased_streams<cf>(4, (std::uint64_t{1} << 25) | 32, 4));  // a control on qubit 2
  qrm::rng g(31);
  std::vector<cf> start(std::size_t{1} << n);
  for (std::size_t i = 0; i < start.size(); ++i) start[i] = cf(static_cast<float>(i % 1999) / 1000.0f - 1.0f, static_cast<float>(i % 997) / 500.0f - 1.0f);
  qrm::dense_matrix u2(4);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) u2(i, j) = std::complex<double>(g.uniform() - 0.5, g.uniform() - 0.5);
  const qrm::gate1 u1 = random_gate1_nonunitary(g, true);
  const qrm::dense_matrix m1 = qrm::dense_matrix::of(u1);
  struct case_t {
    const char* name;
    const qrm::dense_matrix* m;
    std::vector<qubit_index> targets;
    std::vector<control> controls;
  };
  const std::vector<case_t> cases = {{"2x2 on 25", &m1, {25}, {}},
                                     {"4x4 on (25, 5), control 12", &u2, {25, 5}, {{12, true}}},
                                     {"4x4 on (25, 5), control 2", &u2, {25, 5}, {{2, false}}}};
  std::vector<std::uint64_t> sample;
  for (std::uint64_t i = 0; i < 4096; ++i) sample.push_back(i), sample.push_back(start.size() - 1 - i);
  for (int i = 0; i < (1 << 18); ++i) sample.push_back(static_cast<std::uint64_t>(g.uniform() * static_cast<double>(start.size())));
  std::vector<qrm::state_vector<cf>> states;  // one per arithmetic, reused: each costs 512 MiB
  for (const qrm::float_math math : {qrm::float_math::double_precision, qrm::float_math::single_precision}) {
    qrm::dense_options o;
    o.math = math;
    states.emplace_back(n, o);
  }
  for (const case_t& c : cases) {
    // The amplitude at i after the matrix: row r (i's target bits) of m times the members of i's base.
    const auto expected = [&](std::uint64_t i) {
      const auto member = [&](std::size_t r) {
        std::uint64_t j = i;
        for (std::size_t b = 0; b < c.targets.size(); ++b)
          j = ((r >> b) & 1u) ? j | (std::uint64_t{1} << c.targets[b]) : j & ~(std::uint64_t{1} << c.targets[b]);
        return j;
      };
      if (!std::all_of(c.controls.begin(), c.controls.end(), [&](const control& k) { return ((i >> k.qubit) & 1u) == k.value; }))
        return start[i];
      std::size_t row = 0;
      for (std::size_t b = 0; b < c.targets.size(); ++b) row |= ((i >> c.targets[b]) & 1u) << b;
      std::complex<double> out = 0;
      for (std::size_t k = 0; k < c.m->dim; ++k) out += (*c.m)(row, k) * std::complex<double>(start[member(k)]);
      return cf(out);
    };
    for (qrm::state_vector<cf>& s : states)
      for (const unsigned threads : {1u, 2u}) {
        s.set_threads(threads);
        s.set_amplitudes(start);
        if (c.m->dim == 2)
          s.apply_gate1(u1, c.targets[0], c.controls);
        else
          s.apply_unitary(*c.m, c.targets, c.controls);
        double worst = 0;
        for (const std::uint64_t i : sample) worst = std::max(worst, static_cast<double>(std::norm(s.amplitudes()[i] - expected(i))));
        const std::string what = std::string(c.name) + (&s == &states[0] ? ", double" : ", float") +
                                 " arithmetic, threads " + std::to_string(threads);
        INFO(what);
        CHECK(std::sqrt(worst) <= 1e-5);
      }
  }
  // X on qubit 25 (runs 256 MiB apart: detail::swap_runs_masked's grouped form) and on qubit 13
  // (a state streamed from memory: its prefetching loop), without controls, with one on qubit 12
  // and two inside a cache line (a lane mask): the exact permutation.
  const std::vector<std::vector<control>> control_sets = {{}, {{12, true}}, {{1, true}, {2, false}}};
  for (const unsigned target : {25u, 13u})
    for (const std::vector<control>& cs : control_sets)
      for (const unsigned threads : {1u, 2u}) {
        qrm::state_vector<cf>& s = states[0];
        s.set_threads(threads);
        s.set_amplitudes(start);
        s.apply_gate1(qrm::gate::x(), target, cs);
        std::size_t wrong = 0;
        for (const std::uint64_t i : sample) {
          const bool on = std::all_of(cs.begin(), cs.end(), [&](const control& k) { return ((i >> k.qubit) & 1u) == k.value; });
          wrong += s.amplitudes()[i] != (on ? start[i ^ (std::uint64_t{1} << target)] : start[i]);
        }
        INFO("X on " << target << ", controls " << cs.size() << ", threads " << threads);
        CHECK(wrong == 0);
      }
}

// X is a byte move (detail/dense_swap.hpp): blocks of 2^t amplitudes narrower than a vector are
// swapped by one shuffle inside the register, wider ones as whole vectors, at each vector width;
// controls on the lowest qubits below the target become a lane mask. Every target (blocks of 4
// bytes to 128 KiB), targets below, between and above controls (set and clear, inside and beyond
// the masked lanes), one and two threads with chunks, each scalar: the state must be the exact
// index permutation.
TEST_CASE_TEMPLATE("X swaps blocks of every width exactly at every vector level", S, double, float,
                   std::complex<double>, std::complex<float>) {
  const unsigned n = 14;
  std::vector<S> start(std::size_t{1} << n);
  for (std::size_t i = 0; i < start.size(); ++i) {
    if constexpr (std::is_floating_point_v<S>)
      start[i] = static_cast<S>(i + 1);
    else
      start[i] = S(static_cast<float>(i + 1), -static_cast<float>(i) - 0.5f);
  }
  const std::vector<std::vector<qrm::control>> control_sets = {
      {}, {{13, true}, {12, false}, {11, true}}, {{13, true}, {12, true}, {11, true}, {10, false}, {9, true}, {8, true}},
      {{4, true}}, {{0, true}, {2, false}}, {{1, true}, {3, true}, {12, false}}, {{6, false}}};
  std::size_t cases = 0;
  for (qrm::simd_level level : {qrm::simd_level::generic, qrm::simd_level::avx2, qrm::simd_level::avx512})
    for (unsigned threads : {1u, 2u})
      for (const auto& cs : control_sets)
        for (qrm::qubit_index t = 0; t < n; ++t) {
          if (std::any_of(cs.begin(), cs.end(), [&](const qrm::control& c) { return c.qubit == t; })) continue;
          qrm::dense_options o;
          o.threads = threads;
          o.simd = level;
          qrm::state_vector<S> s(n, o);
          s.set_min_parallel(1);
          s.set_amplitudes(start);
          s.apply_gate1(qrm::gate::x(), t, cs);
          std::size_t wrong = 0;
          for (std::uint64_t i = 0; i < start.size(); ++i) {
            const bool on = std::all_of(cs.begin(), cs.end(), [&](const qrm::control& c) { return ((i >> c.qubit) & 1u) == c.value; });
            const S expect = on ? start[i ^ (std::uint64_t{1} << t)] : start[i];
            wrong += s.amplitudes()[i] != expect;
          }
          INFO("level " << std::string(qrm::simd_level_name(level)) << " threads " << threads << " controls " << cs.size() << " target " << t);
          CHECK(wrong == 0);
          ++cases;
        }
  CHECK(cases == 3 * 2 * (14 + 11 + 8 + 13 + 12 + 11 + 13));
}

// A run is chunked when its ops would make dense_options::chunk_min_passes passes over memory
// on their own (detail::memory_passes): an uncontrolled op one pass, halved per control above the
// lowest `low` qubits, a matrix wider than memory_bound_dim none. Runs on qubits 0..3 of a
// 20-qubit state, chunks of 2^10 amplitudes (low = 4): which of them the default rule chunks.
TEST_CASE("runs are chunked when their ops would make at least chunk_min_passes passes over memory") {
  using qrm::op::any;
  const qrm::qubit_index n = 20;
  auto h = [](qrm::qubit_index t, std::vector<qrm::control> cs = {}) { return any{qrm::op::gate1_op{qrm::gate::h(), t, cs}}; };
  auto chunked = [&](const std::vector<any>& ops, std::size_t widest_memory_bound = 4) {
    const auto runs = qrm::detail::plan_runs(ops, n, 10, 4, qrm::detail::min_chunked_passes, widest_memory_bound).runs;
    return runs.size() == 1 && runs[0].local != 0;
  };
  CHECK(qrm::detail::min_chunked_passes == 2);
  CHECK(chunked({h(0), h(1)}));
  CHECK_FALSE(chunked({h(0)}));
  // Controls on qubits 12 and 13 (above the chunk's low qubits): a quarter pass each.
  const std::vector<qrm::control> high = {{12, true}, {13, false}};
  CHECK_FALSE(chunked({h(0, high), h(1, high), h(2, high), h(3, high), h(0, high), h(1, high), h(2, high)}));  // 1.75
  CHECK(chunked({h(0, high), h(1, high), h(2, high), h(3, high), h(0)}));                                        // 2
  // A control on qubit 2, inside the low qubits, leaves the op its whole pass.
  CHECK(chunked({h(0, {{2, true}}), h(1, {{2, true}})}));
  // 8x8 matrices wait on arithmetic unless memory_bound_dim says they wait on memory.
  qrm::dense_matrix m(8);
  for (std::size_t r = 0; r < 8; ++r) m(r, r) = 1;
  const any block{qrm::op::unitary_op{m, {0, 1, 2}, {}}};
  CHECK_FALSE(chunked(std::vector<any>(10, block)));
  CHECK(chunked(std::vector<any>(2, block), 8));
  CHECK(qrm::detail::plan_runs(std::vector<any>(10, block), n, 10, 4, 0).runs.size() == 1);  // threshold 0: chunked
  // Which scalars and arithmetic make an 8x8 block wait on memory (one FMA per 8 bytes or less).
  qrm::detail::exec_policy ex;
  CHECK(qrm::detail::memory_bound_dim<std::complex<double>>(ex) == 8);
  CHECK(qrm::detail::memory_bound_dim<double>(ex) == 8);
  CHECK(qrm::detail::memory_bound_dim<std::complex<float>>(ex) == 4);
  ex.math = qrm::float_math::single_precision;
  CHECK(qrm::detail::memory_bound_dim<std::complex<float>>(ex) == 8);
  // A count that is no number of passes is refused, not read as "chunk everything".
  qrm::state_vector<double> psi(4);
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    CHECK_THROWS_WITH_AS(psi.set_chunk_min_passes(bad), doctest::Contains("chunk_min_passes must be a finite number"),
                         std::invalid_argument);
  qrm::dense_options o;
  o.chunk_min_passes = -2;
  CHECK_THROWS_AS(qrm::state_vector<double>(4, o), std::invalid_argument);
  CHECK_NOTHROW(psi.set_chunk_min_passes(0));
}

// A run takes later ops that fit its chunk ahead of the ops it passes over, when they commute:
// neither moves a qubit the other touches; a qubit that is only a control of both does not order
// them. Chunks of 2^10 amplitudes, qubits 0-3 in every chunk. In program order these 14 ops make
// three runs (the first closes at H(12), the second at H(9) controlled by 14); here two, and the
// state is the one the ops give applied one by one in program order.
TEST_CASE("a run takes commuting ops from further on, never one that must wait") {
  using qrm::op::any;
  auto h = [](qrm::qubit_index t, std::vector<qrm::control> cs = {}) { return any{qrm::op::gate1_op{qrm::gate::h(), t, cs}}; };
  auto x = [](qrm::qubit_index t, std::vector<qrm::control> cs) { return any{qrm::op::gate1_op{qrm::gate::x(), t, cs}}; };
  const std::vector<any> ops = {h(4), h(5), h(6), h(7), h(8), h(9),
                                h(12),              // 6: qubit 12 does not fit the first run
                                h(5),               // 7: commutes with h(12): joins
                                x(6, {{12, true}}),  // 8: controlled by the qubit h(12) moves: waits
                                h(7, {{13, true}}),  // 9: joins
                                h(6),               // 10: moves the qubit op 8 moves: waits
                                x(14, {{15, true}}),  // 11: qubit 14 does not fit: passed over
                                h(4, {{15, false}}),  // 12: 15 only a control of both: joins
                                h(9, {{14, true}})};  // 13: controlled by the qubit op 11 moves: waits
  const qrm::qubit_index n = 16;
  const auto plan = qrm::detail::plan_runs(ops, n, 10, 4, qrm::detail::min_chunked_passes, 4);
  CHECK(plan.order == std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 7, 9, 12, 6, 8, 10, 11, 13});
  REQUIRE(plan.runs.size() == 2);
  CHECK(plan.runs[0].first == 0);
  CHECK(plan.runs[0].last == 9);
  CHECK(plan.runs[0].local == 0x3ffu);
  CHECK(plan.runs[1].last == 14);
  CHECK(plan.runs[1].local == 0x527fu);  // qubits 0-3 and 4-6, 9, 12, 14
  // The reordered, chunked run gives the in-order state.
  qrm::rng g(5);
  const auto start = random_state(n, g, true);
  qrm::program p(n);
  for (const any& o : ops) p.push(o);
  using B = qrm::state_vector<std::complex<double>>;
  B chunked(n), in_order(n);
  chunked.set_chunk_bytes(sizeof(std::complex<double>) << 10);
  in_order.set_chunk_bytes(0);
  backend_traits<B>::load(chunked, start);
  backend_traits<B>::load(in_order, start);
  qrm::run(chunked, p);
  for (const any& o : ops) qrm::emit_op(o, in_order);
  CHECK(max_diff(backend_traits<B>::dump(chunked), backend_traits<B>::dump(in_order)) <= 1e-14);
}

// qrm::run on the dense backend applies runs of ops whose moving qubits fit a chunk chunk by
// chunk (detail/dense_blocked.hpp): qubits renumbered, controls outside the chunk resolved per
// chunk, chunks copied when they are not the lowest qubits. Random programs of every op kind
// (controls anywhere) against the reference simulator, at chunks of 2^4..2^10 amplitudes and off,
// one and two threads; every run that fits is chunked (chunk_min_passes 0: the default leaves
// the short runs of these programs op by op), and chunks of 2^7 and more must actually gather a
// quarter of the ops into runs.
TEST_CASE_TEMPLATE("programs run chunk by chunk match the reference at every chunk size and thread count", S, double,
                   float, std::complex<double>, std::complex<float>) {
  using B = qrm::state_vector<S>;
  using T = backend_traits<B>;
  qrm::rng g(31);
  const std::size_t n = 11;
  for (int trial = 0; trial < 3; ++trial) {
    qrm::program p(n);
    while (p.size() < 150) {
      const std::uint64_t r = g.below(20);
      const op_kind kind = r < 12 ? op_kind::gate1 : r < 16 ? op_kind::unitary : r == 16 ? op_kind::add
                                                   : r == 17 ? op_kind::mux1 : r == 18 ? op_kind::mux_ry
                                                                                       : op_kind::mux_unitary;
      qrm::op::any o = random_op(kind, n, g);
      if (!T::is_complex && !qrm::op_is_real(o)) continue;
      p.push(std::move(o));
    }
    const auto start = random_state(n, g, T::is_complex);
    for (const unsigned chunk_log2 : {0u, 4u, 5u, 7u, 9u, 10u}) {
      if (chunk_log2 >= 7) {  // smaller chunks hold little beside the lowest qubits every chunk keeps
        std::size_t grouped = 0;
        for (const auto& run : qrm::detail::plan_runs(p.ops(), n, chunk_log2, qrm::detail::chunk_low_qubits<S>(), 0).runs)
          if (run.local) grouped += run.last - run.first;
        CHECK(grouped >= p.size() / 4);
      }
      for (const unsigned threads : {1u, 2u}) {
        B b = T::make(n, threads);
        b.set_min_parallel(1);
        b.set_chunk_bytes(chunk_log2 ? sizeof(S) << chunk_log2 : 0);
        b.set_chunk_min_passes(0);
        T::load(b, start);
        reference_state ref(n);
        ref.amp = T::dump(b);
        p.emit(ref);
        qrm::run(b, p);
        INFO("trial " << trial << " chunk 2^" << chunk_log2 << " threads " << threads);
        CHECK(max_diff(ref.amp, T::dump(b)) <= T::tolerance);
      }
    }
  }
}

TEST_CASE("probability sums runs of every length, the eight-wide loop and its tail alike") {
  // Runs of 1 to 2^5 amplitudes (a condition on qubit k cuts the state into runs of 2^k), each
  // checked against a plain sum of |a_i|^2 over the indices the condition selects.
  using S = std::complex<double>;
  const unsigned n = 6;
  qrm::state_vector<S> s(n);
  for (unsigned q = 0; q < n; ++q) s.apply_gate1(qrm::gate::ry(0.3 + 0.4 * q), q, {});
  s.apply_gate1(qrm::gate::rz(0.9), 2, {});
  const auto amps = s.amplitudes();
  for (unsigned k = 0; k < n; ++k)
    for (const bool value : {false, true}) {
      const qrm::control c{k, value};
      double expected = 0;
      for (std::size_t i = 0; i < amps.size(); ++i)
        if (((i >> k) & 1u) == static_cast<std::size_t>(value)) expected += std::norm(amps[i]);
      CAPTURE(k);
      CAPTURE(value);
      CHECK(std::abs(s.probability(std::span<const qrm::control>(&c, 1)) - expected) < 1e-15);
    }
  CHECK(std::abs(s.norm_squared() - 1.0) < 1e-14);
}
