// bench_backends: the same walk-shaped circuits on the dense and the compact backend.
//
// Each iteration builds a fresh state and runs the whole circuit (a run-time program recorded
// once). Times are CPU times (both backends run single-threaded), so a busy machine distorts
// them less than wall-clock time. Counters: `nonzeros` (amplitudes stored at the end), `peak_MiB` (the backend's own
// high-water mark: the dense vector, or the compact backend's buffers), `dense_MiB` (2^n *
// sizeof(Scalar)) and `mem_fraction` = peak / dense.
//
// Circuits:
//   open_walk   D position registers of P qubits, a 3-qubit direction register in uniform
//               superposition, then per step: a position-selected Grover coin on the direction
//               (on the cells of a fixed pseudo-random third of the reachable box),
//               direction-controlled add-a-constant on each position register, and a
//               position-selected Ry on a fresh sample qubit. 2D: 8 compass directions; 3D: the 8
//               diagonals (+-1, +-1, +-1). The start is the grid centre.
//   paper_8x8_walk   the library's A operator for the paper's 8x8 scene, as the CLI runs it
//   paper_8x8_typed  the same operator run from its gate templates, static vs dynamic widths
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <ctime>
#include <optional>
#include <qrm/qrm.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using qrm::control;
using qrm::qubit_index;

std::vector<qubit_index> range(std::size_t first, std::size_t count) {
  std::vector<qubit_index> r(count);
  for (std::size_t i = 0; i < count; ++i) r[i] = static_cast<qubit_index>(first + i);
  return r;
}

// Controls "register `bits` holds value v".
std::vector<control> equals(const std::vector<qubit_index>& bits, std::uint64_t v) {
  std::vector<control> cs;
  for (std::size_t i = 0; i < bits.size(); ++i) cs.push_back({bits[i], ((v >> i) & 1u) != 0});
  return cs;
}

double ry_angle(double p) {
  return 2.0 * std::asin(std::sqrt(p));
}

// Grover diffusion 2|s><s| - I on 3 qubits: real, orthogonal, every entry nonzero.
qrm::dense_matrix grover_coin() {
  qrm::dense_matrix m(8);
  for (std::size_t r = 0; r < 8; ++r)
    for (std::size_t c = 0; c < 8; ++c) m(r, c) = 2.0 / 8.0 - (r == c ? 1.0 : 0.0);
  return m;
}

std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdull;
  x ^= x >> 33;
  return x;
}

struct open_walk_shape {
  int dims, bits, steps;
  std::size_t qubits() const { return static_cast<std::size_t>(dims * bits + 3 + steps); }
};

qrm::program open_walk(const open_walk_shape& w) {
  const std::size_t d = static_cast<std::size_t>(w.dims), p = static_cast<std::size_t>(w.bits);
  qrm::program prog(w.qubits());
  std::vector<std::vector<qubit_index>> axis;
  for (std::size_t a = 0; a < d; ++a) axis.push_back(range(a * p, p));
  const auto position = range(0, d * p);
  const auto dir = range(d * p, 3);
  // Displacement of direction v along each axis.
  auto displacement = [&](std::uint64_t v) {
    std::array<int, 3> r{};
    if (d == 2) {
      static constexpr int dx[8] = {0, 1, 1, 1, 0, -1, -1, -1}, dy[8] = {-1, -1, 0, 1, 1, 1, 0, -1};
      r = {dx[v], dy[v], 0};
    } else {
      for (std::size_t a = 0; a < 3; ++a) r[a] = ((v >> a) & 1u) ? 1 : -1;
    }
    return r;
  };
  const std::uint64_t centre = std::uint64_t{1} << (p - 1);
  for (std::size_t a = 0; a < d; ++a) prog.apply_gate1(qrm::gate::x(), axis[a][p - 1], {});  // start at the centre
  for (qubit_index q : dir) prog.apply_gate1(qrm::gate::h(), q, {});
  // Cells within `radius` of the centre (as select values of the whole position register).
  auto box = [&](int radius, auto&& visit) {
    std::array<int, 3> off{};
    const int hi = d == 3 ? radius : 0;
    for (off[2] = -hi; off[2] <= hi; ++off[2])
      for (off[1] = -radius; off[1] <= radius; ++off[1])
        for (off[0] = -radius; off[0] <= radius; ++off[0]) {
          std::uint64_t v = 0;
          for (std::size_t a = 0; a < d; ++a)
            v |= ((centre + static_cast<std::uint64_t>(off[a])) & ((std::uint64_t{1} << p) - 1)) << (a * p);
          visit(v);
        }
  };
  const std::vector<qrm::dense_matrix> coins = {grover_coin()};
  for (int step = 0; step < w.steps; ++step) {
    std::vector<qrm::mux_unitary_entry> coin_cells;
    box(step, [&](std::uint64_t v) {
      if (mix(v) % 3 == 0) coin_cells.push_back({v, 0});
    });
    prog.apply_mux_unitary(coins, coin_cells, dir, position, {});
    for (std::uint64_t v = 0; v < 8; ++v) {
      const auto disp = displacement(v);
      for (std::size_t a = 0; a < d; ++a)
        if (disp[a] != 0) prog.apply_add(disp[a], axis[a], equals(dir, v));
    }
    std::vector<qrm::mux1_entry> sample;
    box(step + 1, [&](std::uint64_t v) {
      sample.push_back({v, qrm::gate::ry(ry_angle(0.05 + 0.9 * static_cast<double>(mix(v) % 1000) / 1000.0))});
    });
    prog.apply_mux1(sample, static_cast<qubit_index>(d * p + 3 + static_cast<std::size_t>(step)), position, {});
  }
  return prog;
}

template <class B>
std::size_t peak_bytes(const B& b) {
  if constexpr (requires { b.peak_memory_bytes(); })
    return b.peak_memory_bytes();
  else
    return b.size() * sizeof(typename B::scalar_type);
}
template <class B>
std::size_t stored(const B& b) {
  if constexpr (requires { b.nonzeros(); }) {
    return b.nonzeros();
  } else {
    std::size_t k = 0;
    for (const auto& a : b.amplitudes()) k += a != typename B::scalar_type{} ? 1 : 0;
    return k;
  }
}

template <class B>
B make(std::size_t n) {
  if constexpr (requires { B(n, qrm::dense_options{}); }) {
    qrm::dense_options o;
    o.threads = 1;  // the compact backend is single-threaded: compare like with like
    return B(n, o);
  } else {
    return B(n);
  }
}

// Runs prog on a fresh B per iteration; `out` is the qubit whose P(1) is reported (p_top).
template <class B>
void run_program(benchmark::State& st, const qrm::program& prog, std::optional<qubit_index> out = std::nullopt) {
  const std::size_t n = prog.width();
  const qubit_index read = out ? *out : static_cast<qubit_index>(n - 1);
  double probability_out = 0;
  std::size_t nonzeros = 0, peak = 0;
  for (auto _ : st) {
    B b = make<B>(n);
    qrm::run(b, prog);
    benchmark::DoNotOptimize(b);
    st.PauseTiming();
    nonzeros = stored(b);
    peak = peak_bytes(b);
    probability_out = b.probability(std::vector<control>{{read, true}});
    st.ResumeTiming();
  }
  const double dense_bytes = std::ldexp(static_cast<double>(sizeof(typename B::scalar_type)), static_cast<int>(n));
  st.counters["qubits"] = static_cast<double>(n);
  st.counters["ops"] = static_cast<double>(prog.size());
  st.counters["nonzeros"] = static_cast<double>(nonzeros);
  st.counters["peak_MiB"] = static_cast<double>(peak) / (1024.0 * 1024.0);
  st.counters["dense_MiB"] = dense_bytes / (1024.0 * 1024.0);
  st.counters["mem_fraction"] = static_cast<double>(peak) / dense_bytes;
  st.counters["p_top"] = probability_out;  // the same number on both backends (a sanity check)
}

template <class B>
void BM_open_walk(benchmark::State& st) {
  const open_walk_shape w{static_cast<int>(st.range(0)), static_cast<int>(st.range(1)), static_cast<int>(st.range(2))};
  run_program<B>(st, open_walk(w));
}

// The library's own A operator for the paper's 8x8 scene (qrm::make_walk_program with the
// scene of qrm/walk/paper_scenes.hpp, the paper's 8 directions and the light-map start in cell (1, 1),
// red channel, 3 steps): the circuit qrm lightmap runs. Args: history (0/1), pruning (0 none,
// 2 reachable). p_top = P(out = 1), the same on both backends.
template <class B>
void BM_paper_8x8_walk(benchmark::State& st) {
  const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  qrm::walk_options o;
  o.steps = 3;
  o.variant = st.range(0) != 0 ? qrm::walk_variant::history : qrm::walk_variant::faithful;
  o.prune = static_cast<qrm::pruning>(st.range(1));
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({1, 1, 0}), o);
  run_program<B>(st, w.circuit, w.out);
}

// The same A operator run straight from its gate templates (no program): with static widths
// (ray_marching_circuit<2, 3, 3, 3>, constant offsets) or dynamic ones (the widths the CLI reads
// from a scene file). Both keep every qubit of the layout (no idle-qubit removal), so they are
// compared with each other, not with BM_paper_8x8_walk. Args: static (0/1), history (0/1),
// pruning (0 none, 2 reachable).
template <class B, bool Static, qrm::walk_variant V>
void paper_8x8_typed(benchmark::State& st) {
  const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  const qrm::walk_start start = m.light_map_start({1, 1, 0});
  const auto prune = static_cast<qrm::pruning>(st.range(2));
  using static_walk = qrm::ray_marching_circuit<2, 3, 3, 3, V>;
  using dynamic_walk = qrm::walk_circuit<qrm::dynamic_walk_shape<2>>;
  const auto a = [&] {
    if constexpr (Static) return static_walk(m, start, 0, prune);
    else return dynamic_walk(m, start, qrm::walk_options{3, V, prune, 0});
  }();
  const std::size_t n = a.num_qubits();
  double p = 0;
  for (auto _ : st) {
    B b = make<B>(n);
    qrm::run(b, a);
    benchmark::DoNotOptimize(b);
    st.PauseTiming();
    p = b.probability(std::vector<control>{{a.out_qubit(), true}});
    st.ResumeTiming();
  }
  st.counters["qubits"] = static_cast<double>(n);
  st.counters["p_top"] = p;
}
template <class B>
void BM_paper_8x8_typed(benchmark::State& st) {
  const bool is_static = st.range(0) != 0, history = st.range(1) != 0;
  if (is_static)
    history ? paper_8x8_typed<B, true, qrm::walk_variant::history>(st)
            : paper_8x8_typed<B, true, qrm::walk_variant::faithful>(st);
  else
    history ? paper_8x8_typed<B, false, qrm::walk_variant::history>(st)
            : paper_8x8_typed<B, false, qrm::walk_variant::faithful>(st);
}

// One op on a state with every amplitude nonzero (n = 20, real): the compact backend's worst
// case. The ratio of the two times is the fill (nonzeros / 2^n) below which compact is faster.
// Qubits as in a walk: position 0-5 (x 0-2, y 3-5), direction 6-8, samples above.
enum op_kind : int { ry_occupied, mux_ry_position, add_controlled, coin_position, diagonal_controlled };
template <class B>
void BM_full_state_op(benchmark::State& st) {
  const std::size_t n = 20;
  B b = make<B>(n);
  for (qubit_index q = 0; q < n; ++q) b.apply_gate1(qrm::gate::ry(0.3 + 0.1 * q), q, {});  // generic, all nonzero
  const auto position = range(0, 6), dir = range(6, 3), x = range(0, 3);
  std::vector<qrm::mux1_entry> ry_cells;
  for (std::uint64_t v = 0; v < 64; ++v) ry_cells.push_back({v, qrm::gate::ry(0.01 * static_cast<double>(v + 1))});
  const std::vector<qrm::dense_matrix> coin = {grover_coin()};
  std::vector<qrm::mux_unitary_entry> coin_cells;
  for (std::uint64_t v = 0; v < 64; ++v) coin_cells.push_back({v, 0});
  const auto dir_is_3 = equals(dir, 3);
  const std::vector<control> two = {{18, true}, {19, false}};
  const auto kind = static_cast<op_kind>(st.range(0));
  const std::clock_t start = std::clock();
  for (auto _ : st) {
    switch (kind) {
      case ry_occupied:
        b.apply_gate1(qrm::gate::ry(0.2), 12, {});
        break;
      case mux_ry_position:
        b.apply_mux1(ry_cells, 12, position, {});
        break;
      case add_controlled:
        b.apply_add(1, x, dir_is_3);
        break;
      case coin_position:
        b.apply_mux_unitary(coin, coin_cells, dir, position, {});
        break;
      case diagonal_controlled:
        b.apply_gate1(qrm::gate::z(), 10, two);
        break;
    }
  }
  static const char* names[] = {"ry on qubit 12", "mux ry, select = position", "add 1 to x, when dir = 3",
                                "8x8 coin, select = position", "z on 10, 2 controls"};
  st.SetLabel(names[kind]);
  st.counters["nonzeros"] = static_cast<double>(stored(b));
  // CPU time of this (single-threaded) process: the machine may be shared.
  const double seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  st.counters["cpu_ns_per_amp"] =
      seconds * 1e9 / (static_cast<double>(st.iterations()) * static_cast<double>(std::size_t{1} << n));
}

using dense_d = qrm::state_vector<double>;
using compact_d = qrm::compact_state<double>;
using dense_c = qrm::state_vector<std::complex<double>>;
using compact_c = qrm::compact_state<std::complex<double>>;

}  // namespace

// 2D open walks small enough for the dense vector: 20, 23 and 26 qubits.
BENCHMARK(BM_open_walk<dense_d>)
    ->ArgNames({"dims", "bits", "steps"})
    ->Args({2, 7, 3})
    ->Args({2, 8, 4})
    ->Args({2, 9, 5})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_open_walk<compact_d>)
    ->ArgNames({"dims", "bits", "steps"})
    ->Args({2, 7, 3})
    ->Args({2, 8, 4})
    ->Args({2, 9, 5})
    ->Unit(benchmark::kMillisecond);
// 3D, 1024^3 cells: 30 position qubits + 3 direction + one sample per step: 39 and 42 qubits
// (dense: 4 and 32 TiB of doubles); 9 steps reach 1.7 million nonzeros (under 2^22).
BENCHMARK(BM_open_walk<compact_d>)
    ->ArgNames({"dims", "bits", "steps"})
    ->Args({3, 10, 6})
    ->Args({3, 10, 9})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_open_walk<compact_c>)
    ->ArgNames({"dims", "bits", "steps"})
    ->Args({3, 10, 6})
    ->Unit(benchmark::kMillisecond);
// The library's 8x8 walk circuit (make_walk_program): faithful 17 qubits, history 23 (unpruned;
// reachable pruning drops idle qubits).
BENCHMARK(BM_paper_8x8_walk<dense_d>)
    ->ArgNames({"history", "prune"})
    ->ArgsProduct({{0, 1}, {0, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_paper_8x8_walk<compact_d>)
    ->ArgNames({"history", "prune"})
    ->ArgsProduct({{0, 1}, {0, 2}})
    ->Unit(benchmark::kMillisecond);

// The typed 8x8 walk, static vs dynamic widths: faithful 17 qubits, history 23.
BENCHMARK(BM_paper_8x8_typed<dense_d>)
    ->ArgNames({"static", "history", "prune"})
    ->ArgsProduct({{0, 1}, {0, 1}, {0, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_paper_8x8_typed<compact_d>)
    ->ArgNames({"static", "history", "prune"})
    ->ArgsProduct({{0, 1}, {0, 1}, {0, 2}})
    ->Unit(benchmark::kMillisecond);

// Single ops on a full 20-qubit state.
BENCHMARK(BM_full_state_op<dense_d>)->ArgName("op")->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_full_state_op<compact_d>)->ArgName("op")->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
