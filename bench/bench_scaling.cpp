// bench_scaling: the A operator over the points of qrm::scaling_sweep() (the same points as
// `qrm scaling`, which fits the exponents), and whole walks on the dense backend against the
// memory bandwidth.
//
//   scaling/<dims>d/p<p>/s<s>/d<d>/<variant>/<pruning>
//       time: building the program (make_walk_program). Counters: width, logical_depth,
//       gate_count, depth_<layer> (each layer's ops on their own: init, coin, history, shift,
//       sample, path), depth_closed_form (unpruned points), and where the sweep decomposes
//       (qrm::scaling_sweep): decomposed_depth, cnot_count, ancillas.
//   apply_dense/<same>, apply_compact/<same>
//       time: running A from |0...0> (the dense state is reset outside the timing). Dense:
//       state_vector<double> (2D, real coins) or <complex<double>> (3D), one thread, only up to
//       24 qubits (256 MiB of complex); compact: compact_state of the same scalar. Counter p_out =
//       P(out = 1), the same on both backends.
//   walk_bandwidth/p<p>/s<s>/<variant>/<pruning>/<part>
//       the paper-like 2D walk (box_2d, unpruned unless named) on state_vector<double>, one
//       thread, 18 to 26 qubits; <part> = whole (all of A), step (the ops of step 0: coin,
//       [history], shift, Le, rho), coin, shift or sample (that layer of step 0). Each iteration
//       applies the ops to the state as it is (the kernels' cost does not depend on the values).
//       Counters: passes = memory passes the ops need by the model below, GB/s = passes x 2 x
//       2^n x 8 bytes per CPU second, bw_fraction = GB/s / memcpy bandwidth and inplace_fraction
//       = GB/s / in-place pass bandwidth (both bytes read + written per CPU second, measured at
//       the start of the run: reference_bandwidths).
//   walk_bandwidth/ry_target/<t>
//       one Ry on qubit t of a 25-qubit state of doubles: the kernel's speed against the
//       distance 2^t between the paired amplitudes (the walk's Le, rho and direction qubits sit
//       at t = 1..12).
//
// Memory-pass model (dense backend: each kernel visits only the amplitudes where its controls
// hold, reading and writing each once): a gate with c controls, a controlled add or a controlled
// k-qubit unitary touches 2^-c of the state; a multiplexed op with e entries over m select qubits
// (and c controls) touches e 2^-(m+c); a diagonal gate (or multiplexer entry) with a 1 in its
// top-left corner touches half of that (only the |1> half moves: Ry(0), the unpruned circuit's
// entry for a zero value, is one). A multiplexed unitary's identity entries (air's coin) are
// still multiplied through: a full share each.
//
// Times are CPU times (the machine may be shared). A CI subset: --benchmark_filter='scaling/2d/p(4|8|16)/'.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <complex>
#include <cstring>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/walk/cost.hpp>
#include "scaling_study.hpp"  // examples/qrm: the study's sweep points

namespace {

using cd = std::complex<double>;
constexpr std::size_t kMaxDenseApplyQubits = 24;
constexpr int kMaxBandwidthQubits = 26;

// Reference bandwidths in bytes read + written per CPU second, best of 6 runs over the largest
// state walk_bandwidth uses (2^26 doubles, 512 MiB): memcpy (two buffers), and an in-place pass
// that reads, scales and writes back every double (what a dense kernel's pass does). CPU time,
// like the benchmarks' times: on this VM, wall time also counts time the vCPU is stolen or given
// to other processes (measured: memcpy 23 GB/s by wall clock, 36 GB/s by CPU time).
struct bandwidths {
  double memcpy_bytes_per_s = 0, inplace_bytes_per_s = 0;
};
const bandwidths& reference_bandwidths() {
  static const bandwidths bw = [] {
    const std::size_t count = std::size_t{1} << kMaxBandwidthQubits, bytes = count * sizeof(double);
    std::vector<double> a(count, 1.0), b(count, 2.0);
    double best_copy = 1e300, best_inplace = 1e300;
    for (int r = 0; r < 6; ++r) {
      std::clock_t t0 = std::clock();
      std::memcpy(b.data(), a.data(), bytes);
      benchmark::DoNotOptimize(b.data());
      std::clock_t t1 = std::clock();
      best_copy = std::min(best_copy, static_cast<double>(t1 - t0) / CLOCKS_PER_SEC);
      t0 = std::clock();
      for (double& x : a) x *= 0.999;
      benchmark::DoNotOptimize(a.data());
      t1 = std::clock();
      best_inplace = std::min(best_inplace, static_cast<double>(t1 - t0) / CLOCKS_PER_SEC);
    }
    return bandwidths{2.0 * static_cast<double>(bytes) / best_copy, 2.0 * static_cast<double>(bytes) / best_inplace};
  }();
  return bw;
}

// Fraction of the state one op reads and writes (the model in the header comment).
double passes(const qrm::op::any& o) {
  return qrm::visit_op(o, [](const auto& x) {
    using T = std::decay_t<decltype(x)>;
    double f = std::ldexp(1.0, -static_cast<int>(x.controls.size()));
    auto half_if_phase = [](const qrm::gate1& g) {
      return g.is_diagonal() && g.m[0][0] == qrm::complex{1.0} ? 0.5 : 1.0;
    };
    if constexpr (std::is_same_v<T, qrm::op::gate1_op>) {
      f *= half_if_phase(x.gate);
    } else if constexpr (std::is_same_v<T, qrm::op::mux1_op>) {
      double entries = 0;  // Ry(0) entries (zero values, unpruned) are diagonal: half a pass each
      for (const qrm::mux1_entry& e : x.entries) entries += half_if_phase(e.gate);
      f *= entries * std::ldexp(1.0, -static_cast<int>(x.select.size()));
    } else if constexpr (std::is_same_v<T, qrm::op::mux_unitary_op>) {
      f *= static_cast<double>(x.entries.size()) * std::ldexp(1.0, -static_cast<int>(x.select.size()));
    }
    return f;
  });
}

// The circuits of the sweep, built once per point.
struct point {
  qrm::scaling_case c;
  qrm::walk_model model;
  qrm::walk_start start;
  qrm::walk_options options;
};

std::string point_name(const qrm::scaling_case& c) {
  std::string n = std::to_string(c.dims) + "d/p" + std::to_string(c.size) + "/s" + std::to_string(c.steps) + "/d" +
                  std::to_string(c.directions) + "/";
  n += c.variant == qrm::walk_variant::faithful ? "faithful/" : "history/";
  n += qrm::pruning_name(c.prune);
  return n;
}

point make_point(const qrm::scaling_case& c) {
  point p{c, qrm::scaling_model(c.dims, c.size, c.directions), {}, {}};
  p.start = qrm::scaling_start_of(p.model, qrm::scaling_start::near_light);
  p.options.steps = c.steps;
  p.options.variant = c.variant;
  p.options.prune = c.prune;
  return p;
}

// Metrics are computed once per point (decomposition can take seconds; Google Benchmark calls a
// benchmark function several times).
const qrm::scaling_result& metrics_of(const qrm::scaling_case& c) {
  static std::map<std::string, qrm::scaling_result> cache;
  const std::string k = point_name(c);
  auto it = cache.find(k);
  if (it == cache.end()) it = cache.emplace(k, qrm::measure_scaling_case(c)).first;
  return it->second;
}

void BM_scaling(benchmark::State& st, qrm::scaling_case c) {
  const point p = make_point(c);
  const qrm::scaling_result& r = metrics_of(c);
  for (auto _ : st) {
    qrm::walk_program w = qrm::make_walk_program(p.model, p.start, p.options);
    benchmark::DoNotOptimize(w);
  }
  auto put = [&](const char* name, std::size_t v) { st.counters[name] = static_cast<double>(v); };
  put("width", r.width);
  put("logical_depth", r.logical.logical_depth);
  put("gate_count", r.logical.gate_count);
  for (qrm::walk_layer l : qrm::all_walk_layers)
    st.counters[std::string("depth_") + qrm::walk_layer_name(l)] = static_cast<double>(r.layers[l]);
  if (c.prune == qrm::pruning::none) put("depth_closed_form", r.unpruned_depth_formula);
  if (r.decomposed) {
    put("decomposed_depth", r.decomposed->depth);
    put("cnot_count", r.decomposed->cnot_count);
    put("ancillas", r.decomposed->ancillas);
  }
}

template <class B>
B make_backend(std::size_t n) {
  if constexpr (requires { B(n, qrm::dense_options{}); }) {
    qrm::dense_options o;
    o.threads = 1;
    return B(n, o);
  } else {
    return B(n);
  }
}

template <class B>
void BM_apply(benchmark::State& st, qrm::scaling_case c) {
  const point p = make_point(c);
  const qrm::walk_program w = qrm::make_walk_program(p.model, p.start, p.options);
  const qrm::control out{w.out, true};
  double p_out = 0;
  if constexpr (std::is_same_v<B, qrm::state_vector<typename B::scalar_type>>) {
    B b = make_backend<B>(w.circuit.width());  // one state, reset outside the timing
    for (auto _ : st) {
      st.PauseTiming();
      b.set_basis_state(0);
      st.ResumeTiming();
      qrm::run(b, w.circuit);
    }
    p_out = b.probability(std::span<const qrm::control>(&out, 1));
  } else {
    for (auto _ : st) {
      B b = make_backend<B>(w.circuit.width());
      qrm::run(b, w.circuit);
      benchmark::DoNotOptimize(b);
    }
    B b = make_backend<B>(w.circuit.width());
    qrm::run(b, w.circuit);
    p_out = b.probability(std::span<const qrm::control>(&out, 1));
  }
  st.counters["width"] = static_cast<double>(w.circuit.width());
  st.counters["p_out"] = p_out;
}

// ---- whole walks against the memory bandwidth --------------------------------------------------

enum class walk_part { whole, step, coin, shift, sample };
const char* part_name(walk_part p) {
  switch (p) {
    case walk_part::whole:
      return "whole";
    case walk_part::step:
      return "step";
    case walk_part::coin:
      return "coin";
    case walk_part::shift:
      return "shift";
    case walk_part::sample:
      return "sample";
  }
  return "?";
}

// The ops of `part`: all of A, or step 0 (from the first coin to the second, or to the Path),
// or one layer of step 0.
qrm::program part_of(const qrm::program& a, walk_part part) {
  if (part == walk_part::whole) return a;
  qrm::program out(a.width());
  int step = -1;
  for (std::size_t i = 0; i < a.ops().size(); ++i) {
    const qrm::op::any& o = a.ops()[i];
    const qrm::walk_layer l = qrm::recorded_walk_layer(a, i);
    if (l == qrm::walk_layer::coin) ++step;
    if (step != 0 || l == qrm::walk_layer::path || l == qrm::walk_layer::init) continue;
    const bool keep = part == walk_part::step || (part == walk_part::coin && l == qrm::walk_layer::coin) ||
                      (part == walk_part::shift && l == qrm::walk_layer::shift) ||
                      (part == walk_part::sample && l == qrm::walk_layer::sample);
    if (keep) out.push(o);
  }
  return out;
}

// One dense state per width, kept across benchmarks (allocating 512 MiB per run would dominate).
qrm::state_vector<double>& shared_state(std::size_t n) {
  static std::unique_ptr<qrm::state_vector<double>> s;
  if (!s || s->num_qubits() != n) {
    s.reset();
    qrm::dense_options o;
    o.threads = 1;
    s = std::make_unique<qrm::state_vector<double>>(n, o);
  }
  return *s;
}

void BM_walk_bandwidth(benchmark::State& st, unsigned p, unsigned steps, qrm::walk_variant v, qrm::pruning pr,
                       walk_part part) {
  const qrm::walk_model m = qrm::scaling_model(2, p, 8);
  qrm::walk_options o;
  o.steps = steps;
  o.variant = v;
  o.prune = pr;
  // The unpruned program keeps every qubit, so its layout is the full one; pruned programs
  // drop idle qubits (fewer amplitudes).
  const qrm::walk_program w = qrm::make_walk_program(m, qrm::scaling_start_of(m, qrm::scaling_start::near_light), o);
  const qrm::program ops = part_of(w.circuit, part);
  const std::size_t n = w.circuit.width();
  auto& s = shared_state(n);
  s.set_basis_state(0);
  double pass_count = 0;
  for (const qrm::op::any& x : ops.ops()) pass_count += passes(x);
  for (auto _ : st) qrm::run(s, ops);
  const double bytes = pass_count * 2.0 * std::ldexp(static_cast<double>(sizeof(double)), static_cast<int>(n));
  st.counters["qubits"] = static_cast<double>(n);
  st.counters["ops"] = static_cast<double>(ops.size());
  st.counters["passes"] = pass_count;
  const bandwidths& bw = reference_bandwidths();
  st.counters["bw_fraction"] =
      benchmark::Counter(bytes / bw.memcpy_bytes_per_s, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["inplace_fraction"] =
      benchmark::Counter(bytes / bw.inplace_bytes_per_s, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["GB/s"] = benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["memcpy_GB/s"] = bw.memcpy_bytes_per_s / 1e9;
  st.counters["inplace_GB/s"] = bw.inplace_bytes_per_s / 1e9;
}

// One real Ry on qubit t of a 25-qubit state of doubles (the walk's kernels at their qubits):
// how the dense kernel's speed depends on the distance 2^t between the amplitudes it pairs.
void BM_ry_target(benchmark::State& st, unsigned t) {
  constexpr std::size_t n = 25;
  auto& s = shared_state(n);
  const qrm::gate1 g = qrm::gate::ry(0.3);
  for (auto _ : st) s.apply_gate1(g, t, {});
  const double bytes = 2.0 * std::ldexp(static_cast<double>(sizeof(double)), static_cast<int>(n));
  const bandwidths& bw = reference_bandwidths();
  st.counters["bw_fraction"] =
      benchmark::Counter(bytes / bw.memcpy_bytes_per_s, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["GB/s"] = benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

void register_all() {
  // Every distinct circuit of the sweep once (the sweeps share some points).
  std::map<std::string, qrm::scaling_case> points;
  for (const qrm::scaling_case& c : qrm::scaling_sweep()) points.emplace(point_name(c), c);
  for (const auto& [name, c] : points)
    benchmark::RegisterBenchmark(("scaling/" + name).c_str(), BM_scaling, c)
        ->MinTime(0.05)
        ->Unit(benchmark::kMillisecond);
  for (const auto& [name, c] : points) {
    // The formula's (unpruned) width bounds every pruning level's: no circuit is built here.
    const auto position_bits = static_cast<unsigned>(std::countr_zero(c.size));
    const std::size_t width =
        qrm::walk_width_formula(c.dims, position_bits, c.dims == 3 ? 3 : 0,
                                static_cast<unsigned>(qrm::bits_for(c.directions)), c.steps, c.variant);
    if (width <= kMaxDenseApplyQubits) {
      if (c.dims == 2)
        benchmark::RegisterBenchmark(("apply_dense/" + name).c_str(), BM_apply<qrm::state_vector<double>>, c)
            ->MinTime(0.05)
            ->Unit(benchmark::kMillisecond);
      else
        benchmark::RegisterBenchmark(("apply_dense/" + name).c_str(), BM_apply<qrm::state_vector<cd>>, c)
            ->MinTime(0.05)
            ->Unit(benchmark::kMillisecond);
    }
    // Labels: 64-bit up to 64 qubits, two words above (3D history walks reach 69).
    using wide = qrm::wide_label<2>;
    const std::string compact_name = "apply_compact/" + name;
    benchmark::internal::Benchmark* b =
        c.dims == 2
            ? (width <= 64
                   ? benchmark::RegisterBenchmark(compact_name.c_str(), BM_apply<qrm::compact_state<double>>, c)
                   : benchmark::RegisterBenchmark(compact_name.c_str(), BM_apply<qrm::compact_state<double, wide>>, c))
            : (width <= 64
                   ? benchmark::RegisterBenchmark(compact_name.c_str(), BM_apply<qrm::compact_state<cd>>, c)
                   : benchmark::RegisterBenchmark(compact_name.c_str(), BM_apply<qrm::compact_state<cd, wide>>, c));
    b->MinTime(0.05)->Unit(benchmark::kMillisecond);
  }
  struct walk {
    unsigned p, s;
    qrm::walk_variant v;
  };
  using qrm::walk_variant;
  // 18, 21, 23, 25, 25 (history) and 26 qubits.
  const walk walks[] = {{32, 2, walk_variant::faithful}, {32, 3, walk_variant::faithful},
                        {64, 3, walk_variant::faithful}, {128, 3, walk_variant::faithful},
                        {16, 3, walk_variant::history},  {512, 2, walk_variant::faithful}};
  for (const walk& w : walks) {
    const std::string base = "walk_bandwidth/p" + std::to_string(w.p) + "/s" + std::to_string(w.s) + "/" +
                             (w.v == walk_variant::faithful ? "faithful" : "history");
    for (walk_part part : {walk_part::whole, walk_part::step, walk_part::coin, walk_part::shift, walk_part::sample})
      benchmark::RegisterBenchmark((base + "/none/" + part_name(part)).c_str(), BM_walk_bandwidth, w.p, w.s, w.v,
                                   qrm::pruning::none, part)
          ->MinTime(0.2)
          ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((base + "/reachable/whole").c_str(), BM_walk_bandwidth, w.p, w.s, w.v,
                                 qrm::pruning::reachable, walk_part::whole)
        ->MinTime(0.2)
        ->Unit(benchmark::kMillisecond);
  }
  for (unsigned t : {0u, 2u, 4u, 5u, 6u, 7u, 8u, 10u, 12u, 14u, 16u, 20u, 24u})
    benchmark::RegisterBenchmark(("walk_bandwidth/ry_target/" + std::to_string(t)).c_str(), BM_ry_target, t)
        ->MinTime(0.2)
        ->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
