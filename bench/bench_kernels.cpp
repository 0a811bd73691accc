// bench_kernels: the dense backend's kernels at n = 20..26 qubits, one and two threads.
//
// Counter `bw_fraction`: bytes that must move (read + write of the amplitudes the kernel
// touches) per second, divided by the memcpy bandwidth (read + write) measured at the start of
// the same run on a buffer as large as the largest state; `stream_fraction` the same against an
// in-place stream (each float scaled where it lies), the bound for an in-place kernel.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstring>
#include <map>
#include <memory>
#include <vector>

#include <qrm/qrm.hpp>
#include <qrm/backends/detail/dense_blocked.hpp>  // the kernels it times one by one

namespace {

using cd = std::complex<double>;
constexpr int kMinQubits = 20, kMaxQubits = 26;

// memcpy bandwidth (bytes read + written per second), best of several copies of 2^26 * 16 B.
double memcpy_bandwidth() {
  static const double bw = [] {
    const std::size_t bytes = (std::size_t{1} << kMaxQubits) * sizeof(cd);
    std::vector<char> a(bytes, 1), b(bytes, 2);
    double best = 1e300;
    for (int r = 0; r < 6; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      std::memcpy(b.data(), a.data(), bytes);
      benchmark::DoNotOptimize(b.data());
      const auto t1 = std::chrono::steady_clock::now();
      best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
    }
    return 2.0 * static_cast<double>(bytes) / best;
  }();
  return bw;
}

// One state per (scalar, n) kept alive across benchmarks (allocating 1 GiB per run would
// dominate); only the latest size is kept to bound memory.
template <class S>
qrm::state_vector<S>& state(int n, unsigned threads) {
  static std::unique_ptr<qrm::state_vector<S>> s;
  if (!s || s->num_qubits() != static_cast<std::size_t>(n)) {
    s.reset();
    qrm::dense_options o;
    o.threads = threads;
    s = std::make_unique<qrm::state_vector<S>>(n, o);
    qrm::run(*s, qrm::program());  // nothing: the state is |0...0>, every kernel still touches its subspace
  }
  s->set_threads(threads);
  return *s;
}

// In-place stream bandwidth (bytes read + written per second): every float of a 2^26
// complex<float> buffer scaled in place, best of several passes. A kernel that reads and writes
// each amplitude once can at best match it.
double inplace_stream_bandwidth() {
  static const double bw = [] {
    std::vector<float> a(std::size_t{2} << kMaxQubits, 1.0f);
    double best = 1e300;
    for (int r = 0; r < 6; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      for (float& x : a) x *= 0.999f;
      benchmark::DoNotOptimize(a.data());
      const auto t1 = std::chrono::steady_clock::now();
      best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
    }
    return 2.0 * static_cast<double>(a.size() * sizeof(float)) / best;
  }();
  return bw;
}

void report(benchmark::State& st, double bytes_per_iteration) {
  st.counters["bw_fraction"] = benchmark::Counter(bytes_per_iteration / memcpy_bandwidth(),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  st.counters["stream_fraction"] = benchmark::Counter(bytes_per_iteration / inplace_stream_bandwidth(),
                                                      benchmark::Counter::kIsIterationInvariantRate);
  st.counters["GB/s"] = benchmark::Counter(bytes_per_iteration / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["memcpy_GB/s"] = memcpy_bandwidth() / 1e9;
}

template <class S>
void touch_bytes_label(benchmark::State& st, int n) {
  st.SetLabel(std::string(qrm::detail::scalar_name<S>()) + " n=" + std::to_string(n));
}

// A real 2x2 rotation on qubit `target` (args: n, target selector 0=low 1=middle 2=high, threads).
template <class S>
void BM_gate1(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto target = static_cast<qrm::qubit_index>(st.range(1) == 0 ? 0 : st.range(1) == 1 ? n / 2 : n - 1);
  auto& s = state<S>(n, static_cast<unsigned>(st.range(2)));
  const qrm::gate1 g = qrm::gate::ry(0.3);
  for (auto _ : st) s.apply_gate1(g, target, {});
  report(st, 2.0 * std::ldexp(sizeof(S), n));
  touch_bytes_label<S>(st, n);
}

// A generic complex 2x2 gate on qubit `target` (args as BM_gate1).
template <class S>
void BM_gate1_generic(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto target = static_cast<qrm::qubit_index>(st.range(1) == 0 ? 0 : st.range(1) == 1 ? n / 2 : n - 1);
  auto& s = state<S>(n, static_cast<unsigned>(st.range(2)));
  const qrm::gate1 g = qrm::gate::u(cd(0.6, 0.0), cd(0.0, 0.8), cd(0.0, 0.8), cd(0.6, 0.0));
  for (auto _ : st) s.apply_gate1(g, target, {});
  report(st, 2.0 * std::ldexp(sizeof(S), n));
  touch_bytes_label<S>(st, n);
}

// The same on complex<float> in float arithmetic (qrm::float_math::single_precision; targets
// 0..2 run dense_pairs.hpp's in-register kernel): args n, target (0, n/2, n-1), threads.
void BM_gate1_generic_float_math(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto target = static_cast<qrm::qubit_index>(st.range(1) == 0 ? 0 : st.range(1) == 1 ? n / 2 : n - 1);
  static std::unique_ptr<qrm::state_vector<std::complex<float>>> s;
  if (!s || s->num_qubits() != static_cast<std::size_t>(n)) {
    s.reset();
    qrm::dense_options o;
    o.math = qrm::float_math::single_precision;
    s = std::make_unique<qrm::state_vector<std::complex<float>>>(n, o);
  }
  s->set_threads(static_cast<unsigned>(st.range(2)));
  const qrm::gate1 g = qrm::gate::u(cd(0.6, 0.0), cd(0.0, 0.8), cd(0.0, 0.8), cd(0.6, 0.0));
  for (auto _ : st) s->apply_gate1(g, target, {});
  report(st, 2.0 * std::ldexp(sizeof(std::complex<float>), n));
  touch_bytes_label<std::complex<float>>(st, n);
}

// A complex (non-real) 2x2 gate: the full complex multiply.
void BM_gate1_complex(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  auto& s = state<cd>(n, static_cast<unsigned>(st.range(1)));
  const qrm::gate1 g = qrm::gate::u(cd(0.6, 0.0), cd(0.0, 0.8), cd(0.0, 0.8), cd(0.6, 0.0));
  for (auto _ : st) s.apply_gate1(g, static_cast<qrm::qubit_index>(n / 2), {});
  report(st, 2.0 * std::ldexp(sizeof(cd), n));
}

// C^k X (args: n, k, placement, threads). placement 0: controls on the top k qubits, target 0,
// so the touched amplitudes are one contiguous block; placement 1: controls on qubits 0..k-1,
// target n-1, so every touched amplitude sits in its own cache line 2^k amplitudes apart (the
// worst case: bounded by memory latency, not bandwidth); placement 2: controls on qubits 1..k,
// target k + 3 (the Toffolis of a random circuit: controls inside each cache line, so every line
// is read; bound by bandwidth, a full pass); placement 3: controls on qubits 3, 7, 11, ...,
// target n - 2, on a state that stays in cache (n = 16: a chunk of run_in_chunks), runs of
// 128 bytes.
template <class S>
void BM_mcx(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const int k = static_cast<int>(st.range(1));
  const bool strided = st.range(2) == 1;
  auto& s = state<S>(n, static_cast<unsigned>(st.range(3)));
  std::vector<qrm::control> cs;
  const int placement = static_cast<int>(st.range(2));
  for (int i = 0; i < k; ++i)
    cs.push_back({static_cast<qrm::qubit_index>(placement == 3 ? 3 + 4 * i : placement == 2 ? i + 1 : strided ? i : n - 1 - i), true});
  const auto target = static_cast<qrm::qubit_index>(placement == 3 ? n - 2 : placement == 2 ? k + 3 : strided ? n - 1 : 0);
  for (auto _ : st) s.apply_gate1(qrm::gate::x(), target, cs);
  report(st, 2.0 * std::ldexp(sizeof(S), n - k));
  touch_bytes_label<S>(st, n);
}

// Ry on qubit 0 controlled by the top qubit.
void BM_controlled_ry(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  auto& s = state<cd>(n, static_cast<unsigned>(st.range(1)));
  const qrm::control c{static_cast<qrm::qubit_index>(n - 1), true};
  const qrm::gate1 g = qrm::gate::ry(0.3);
  for (auto _ : st) s.apply_gate1(g, 0, std::span<const qrm::control>(&c, 1));
  report(st, 2.0 * std::ldexp(sizeof(cd), n - 1));
}

// Multiplexed Ry on qubit 0, selected by the top 6 qubits, every select value present
// (the Sample layer of an 8x8 scene with every voxel non-zero).
void BM_mux_ry(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  auto& s = state<cd>(n, static_cast<unsigned>(st.range(1)));
  std::vector<qrm::qubit_index> sel;
  for (int i = 0; i < 6; ++i) sel.push_back(static_cast<qrm::qubit_index>(n - 6 + i));
  std::vector<qrm::mux1_entry> es;
  for (std::uint64_t v = 0; v < 64; ++v) es.push_back({v, qrm::gate::ry(0.01 * static_cast<double>(v + 1))});
  for (auto _ : st) s.apply_mux1(es, 0, sel, {});
  report(st, 2.0 * std::ldexp(sizeof(cd), n));
}

// Increment of a 3-qubit register in the middle of the state (the 2D Shift's building block).
void BM_increment(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  auto& s = state<cd>(n, static_cast<unsigned>(st.range(1)));
  const std::vector<qrm::qubit_index> bits = {static_cast<qrm::qubit_index>(n / 2), static_cast<qrm::qubit_index>(n / 2 + 1),
                                              static_cast<qrm::qubit_index>(n / 2 + 2)};
  for (auto _ : st) s.apply_add(1, bits, {});
  report(st, 2.0 * std::ldexp(sizeof(cd), n));
}

void sizes_and_threads(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2})
    for (int n = kMinQubits; n <= kMaxQubits; n += 2) b->Args({n, threads});
}

}  // namespace

BENCHMARK(BM_gate1<cd>)->ArgNames({"n", "target", "threads"})->ArgsProduct({{20, 22, 24, 26}, {0, 1, 2}, {1, 2}})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_gate1<std::complex<float>>)->ArgNames({"n", "target", "threads"})->ArgsProduct({{26}, {0, 1, 2}, {1, 2}})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_gate1_generic<std::complex<float>>)->ArgNames({"n", "target", "threads"})->ArgsProduct({{26}, {0, 1, 2}, {1, 2}})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_gate1_generic_float_math)->ArgNames({"n", "target", "threads"})->ArgsProduct({{26}, {0, 1, 2}, {1}})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_gate1<double>)->ArgNames({"n", "target", "threads"})->ArgsProduct({{26}, {0, 1, 2}, {1, 2}})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_gate1_complex)->ArgNames({"n", "threads"})->Apply(sizes_and_threads)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_mcx<cd>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{20, 22, 24, 26}, {1, 4, 8, 12}, {0, 1}, {1, 2}})->UseRealTime()->Unit(benchmark::kMicrosecond);
// The same permutation on the other scalars: an X moves amplitudes without arithmetic, so its cost
// should follow the bytes moved, whatever the element type.
BENCHMARK(BM_mcx<std::complex<float>>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{26}, {8, 12}, {0, 1}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<double>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{26}, {8, 12}, {0, 1}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<cd>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{24}, {1, 2}, {2}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<std::complex<float>>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{24}, {1, 2}, {2}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<double>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{24}, {1, 2}, {2}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<cd>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{16}, {0, 1, 2, 3}, {3}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_mcx<std::complex<float>>)->ArgNames({"n", "k", "placement", "threads"})->ArgsProduct({{16}, {0, 1, 2, 3}, {3}, {1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_controlled_ry)->ArgNames({"n", "threads"})->Apply(sizes_and_threads)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_mux_ry)->ArgNames({"n", "threads"})->Apply(sizes_and_threads)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_increment)->ArgNames({"n", "threads"})->Apply(sizes_and_threads)->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
