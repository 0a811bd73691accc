// Gate fusion (qrm::fuse) on circuits of small gates, one thread, fused against unfused in the
// same run: the decomposed A operator of the paper's 8x8 scene (the 1-qubit + CNOT form
// hardware would run: cell (3, 4), 3 steps, reachable pruning, 21 qubits with ancillas, 5125
// ops; the circuit `qrm circuit --scene paper_8x8 --x 3 --y 4 --qasm F --decomposed` writes) and the
// random suite of qrm simulate --random (22 qubits, 300 gates of H, Ry, CX, CCX, C^4 X).
// Args: circuit (0 walk, 1 random, 2 the walk on a 23-qubit state: two idle qubits on top, the
// size at which two threads are measured, 3 the random suite on 24 qubits: 128-256 MiB, beyond
// any cache), fusion width (0: unfused), simd (qrm::simd_level: 0 the best this CPU has, 2 AVX2,
// 3 AVX-512), threads, chunk (KiB of the chunks qrm::run applies runs of ops in, see
// dense_options::chunk_bytes; 0: op by op, as every run before chunks existed). complex<float> runs twice: in double
// arithmetic (the default) and in float arithmetic (qrm::float_math::single_precision, the
// precision Google qsim computes in); double runs the random suites. BM_fusion_scope fuses the
// walk and the 24-qubit suite across the program or within the runs the backend applies chunk by
// chunk (qrm::dense_fusion_options): run with --benchmark_enable_random_interleaving=true.
// BM_noisy_trajectories: the noisy oracle at gate level (qrm/noise) on the paper's 4x4 scene,
// cell (1, 1), one step (18 qubits decomposed: A 917 gates, Q 2051), 4 trajectories through
// Q^4 A on one thread, gate by gate (fuse 0) or fused (fuse 1, qrm::fused_noisy_circuit). Model:
// 0 depolarizing p2 = 1e-4, 1 depolarizing p2 = 1e-2 (errors in most blocks), 2 the
// superconducting preset (T1 so short that damping draws may jump in every run: each run is cut
// there and fused afresh), 3 the ion preset (T1 = 1000 s: damping fused as K0; dephasing errors
// folded in).
#include <benchmark/benchmark.h>

#include <complex>
#include <qrm/qrm.hpp>
#include <qrm/backends/detail/dense_batched.hpp>  // detail::resolve_simd
#include <vector>

#include "random_suite.hpp"

namespace {

const qrm::program& circuit(int which) {
  static const qrm::program walk = [] {
    const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
    qrm::walk_options o;
    o.steps = 3;
    o.prune = qrm::pruning::reachable;
    const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({3, 4, 0}), o);
    return qrm::decompose(w.circuit).circuit;
  }();
  static const qrm::program suite = qrm_cli::random_gate_suite(22, 300, 1);
  static const qrm::program suite24 = qrm_cli::random_gate_suite(24, 300, 1);
  static const qrm::program wide_walk = [] {
    qrm::program p(walk.width() + 2);
    for (const qrm::op::any& o : walk.ops()) p.push(o);
    return p;
  }();
  return which == 0 ? walk : which == 1 ? suite : which == 2 ? wide_walk : suite24;
}

// Each iteration: |0...0>, then `run` (the timed part includes the reset, a pass over the state).
template <class S>
void run_from_zero(benchmark::State& st, qrm::state_vector<S>& s, const qrm::program& run) {
  for (auto _ : st) {
    s.set_basis_state(0);
    qrm::run(s, run);
    benchmark::DoNotOptimize(s.amplitudes().data());
  }
}

template <class S, qrm::float_math Math = qrm::float_math::double_precision>
void BM_fusion(benchmark::State& st) {
  const qrm::program& p = circuit(static_cast<int>(st.range(0)));
  const auto width = static_cast<unsigned>(st.range(1));
  const qrm::program run = width ? qrm::fuse(p, {width}) : p;
  qrm::dense_options o;
  o.threads = static_cast<unsigned>(st.range(3));
  o.simd = static_cast<qrm::simd_level>(st.range(2));
  o.math = Math;
  o.chunk_bytes = static_cast<std::uint64_t>(st.range(4)) << 10;
  qrm::state_vector<S> s(p.width(), o);
  run_from_zero(st, s, run);
  st.counters["qubits"] = static_cast<double>(p.width());
  st.counters["ops"] = static_cast<double>(run.size());
  st.counters["threads"] = static_cast<double>(o.threads);
  st.counters["chunk_kib"] = static_cast<double>(st.range(4));
  st.SetLabel(qrm::simd_level_name(qrm::detail::resolve_simd(o.simd)));
}

// Fused across the program (scope 0) or within the runs the backend applies chunk by chunk
// (scope 1, qrm::dense_fusion_options), at width `fuse`, chunks of 1 MiB, one thread.
template <class S, qrm::float_math Math = qrm::float_math::double_precision>
void BM_fusion_scope(benchmark::State& st) {
  const qrm::program& p = circuit(static_cast<int>(st.range(0)));
  qrm::dense_options o;
  o.threads = 1;
  o.math = Math;
  const qrm::fusion_options width{static_cast<unsigned>(st.range(1))};
  const qrm::program run = qrm::fuse(p, st.range(2) ? qrm::dense_fusion_options<S>(width, o) : width);
  qrm::state_vector<S> s(p.width(), o);
  run_from_zero(st, s, run);
  st.counters["ops"] = static_cast<double>(run.size());
  st.counters["within_runs"] = static_cast<double>(st.range(2));
}

void BM_noisy_trajectories(benchmark::State& st) {
  const qrm::walk_model m(qrm::paper_4x4(), qrm::king_2d());
  qrm::walk_options wo;
  wo.steps = 1;
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({1, 1, 0}), wo);
  const qrm::estimation_problem problem{w.circuit, {qrm::control{w.out, true}}};
  const qrm::noise_model model = st.range(1) == 0   ? qrm::depolarizing_noise(1e-5, 1e-4)
                                 : st.range(1) == 1 ? qrm::depolarizing_noise(1e-3, 1e-2)
                                 : st.range(1) == 2 ? qrm::noise_preset("superconducting")
                                                    : qrm::noise_preset("ion");
  qrm::noisy_oracle_options o;
  o.level = qrm::noise_level::gates;
  o.trajectories = 4;
  o.threads = 1;
  o.fuse = st.range(0) != 0;
  for (auto _ : st) {
    qrm::noisy_oracle oracle(problem, model, o);  // fusing A and Q is part of the cost
    oracle.prepare(4);
    benchmark::DoNotOptimize(oracle.probability(4));
  }
}

// BM_fusion_scope's cases: the walk and the 24-qubit suite, widths 2 and 3, both scopes.
void scope_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"circuit", "fuse", "scope"})
      ->ArgsProduct({{0, 3}, {2, 3}, {0, 1}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond)
      ->Iterations(1)
      ->Repetitions(5);
}

}  // namespace

BENCHMARK(BM_noisy_trajectories)
    ->ArgNames({"fuse", "model"})
    ->ArgsProduct({{0, 1}, {0, 1, 2, 3}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3);
BENCHMARK(BM_fusion_scope<std::complex<double>>)->Apply(scope_args);
BENCHMARK(BM_fusion_scope<std::complex<float>, qrm::float_math::single_precision>)->Apply(scope_args);
BENCHMARK(BM_fusion<std::complex<double>>)
    ->ArgNames({"circuit", "fuse", "simd", "threads", "chunk"})
    ->ArgsProduct({{0, 1}, {0, 2, 3, 4, 5}, {0}, {1}, {0}})
    ->ArgsProduct({{0, 1}, {3, 4}, {2}, {1}, {0}})
    ->ArgsProduct({{2}, {3}, {0}, {1, 2}, {0}})
    ->ArgsProduct({{0, 1, 3}, {0, 3}, {0}, {1}, {1024}})
    ->ArgsProduct({{3}, {0, 3}, {0}, {1}, {0}})
    ->ArgsProduct({{2}, {3}, {0}, {1, 2}, {1024}})
    ->ArgsProduct({{3}, {3}, {0}, {2}, {0, 1024}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3);
BENCHMARK(BM_fusion<std::complex<float>>)
    ->ArgNames({"circuit", "fuse", "simd", "threads", "chunk"})
    ->ArgsProduct({{0, 1}, {0, 3, 4}, {0}, {1}, {0}})
    ->ArgsProduct({{2}, {3}, {0}, {1, 2}, {0}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3);
// Real amplitudes (the random suites are real): a fused matrix off qubit 0 runs on the complex<double>
// kernels with the state read as complex pairs, an 8x8 one on qubit 0 as lanes of eight doubles
// (AVX-512), the others by row lists.
BENCHMARK(BM_fusion<double>)
    ->ArgNames({"circuit", "fuse", "simd", "threads", "chunk"})
    ->ArgsProduct({{1, 3}, {0, 3}, {0}, {1}, {1024}})
    ->ArgsProduct({{3}, {0, 3}, {0}, {1}, {0}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3);
BENCHMARK(BM_fusion<std::complex<float>, qrm::float_math::single_precision>)
    ->ArgNames({"circuit", "fuse", "simd", "threads", "chunk"})
    ->ArgsProduct({{0, 1}, {3, 4, 5}, {0}, {1}, {0}})
    ->ArgsProduct({{0, 1}, {3}, {2}, {1}, {0}})
    ->ArgsProduct({{2}, {3}, {0}, {1, 2}, {0}})
    ->ArgsProduct({{0, 1, 3}, {3}, {0}, {1}, {1024}})
    ->ArgsProduct({{3}, {3}, {0}, {1}, {0}})
    ->ArgsProduct({{2}, {3}, {0}, {1, 2}, {1024}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3);

BENCHMARK_MAIN();
