// bench_render3d: 3D images on the walk's discretization (render/render_classical.hpp): the
// Cornell box at 128 x 128 pixels, golden spiral with 15 directions and 3 fractional bits.
// Arguments: voxels per side N, steps s, threads. Each iteration renders the whole image,
// including the per-pixel DDA and walk starts; the walk model is built once outside the loop.
// Counter `starts`: distinct (voxel, direction) walk starts, i.e. path sums or enumerations.
//
//   BM_walk_starts/N/steps/march (0 voxel, 1 surface): the fully quantum renderer's unit of work:
//   every distinct walk start of a 16x16 image of the N^3 Cornell box (14 cube directions, 2
//   sub-voxel bits), its walk program built (pruning reachable) and run on the compact backend,
//   one start after another, one thread. Counters: starts, lit_starts (P(out = 1) > 0),
//   unpruned_width, width_mean and width_max (after pruning), nonzeros_mean and nonzeros_max
//   (the final state's support), seconds_per_start.
#include <benchmark/benchmark.h>

#include <chrono>
#include <qrm/backends/compact.hpp>
#include <qrm/walk/circuit.hpp>
#include <set>
#include <vector>

#include <map>
#include <memory>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <tuple>

namespace {

constexpr unsigned kPixels = 128;

const qrm::walk_model& cornell_model(unsigned n) {
  static std::map<unsigned, std::unique_ptr<qrm::walk_model>> cache;
  auto& m = cache[n];
  if (!m) m = std::make_unique<qrm::walk_model>(qrm::render::cornell_box(n), qrm::golden_spiral(15, 3));
  return *m;
}

struct setup {
  const qrm::walk_model& model;
  qrm::render::camera cam;
  qrm::render::render_options opt;
};
setup make_setup(const benchmark::State& state) {
  const auto n = static_cast<unsigned>(state.range(0));
  qrm::render::render_options o;
  o.steps = static_cast<unsigned>(state.range(1));
  o.threads = static_cast<unsigned>(state.range(2));
  return {cornell_model(n), qrm::render::box_scene_camera(n, kPixels, kPixels), o};
}
void count_starts(benchmark::State& state, const setup& s) {
  const auto px = qrm::render::pixel_starts(s.model, s.cam, {}, 1);
  state.counters["starts"] = static_cast<double>(qrm::detail::group_render_starts(px).keys.size());
}

void BM_exact(benchmark::State& state) {
  const setup s = make_setup(state);
  for (auto _ : state) benchmark::DoNotOptimize(qrm::render::render_exact(s.model, s.cam, s.opt).pixels().data());
  count_starts(state, s);
}

void BM_monte_carlo_32(benchmark::State& state) {
  const setup s = make_setup(state);
  for (auto _ : state)
    benchmark::DoNotOptimize(qrm::render::render_monte_carlo(s.model, s.cam, 32, 1, s.opt).mean.pixels().data());
  count_starts(state, s);
}

void BM_emulated_32(benchmark::State& state) {
  const setup s = make_setup(state);
  qrm::render::emulation_options e;
  e.paths_per_pixel = 32;
  for (auto _ : state)
    benchmark::DoNotOptimize(qrm::render::render_emulated(s.model, s.cam, e, s.opt).sampled.pixels().data());
  count_starts(state, s);
}

void render_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "steps", "threads"});
  for (int threads : {1, 2}) b->Args({32, 3, threads});
  b->Args({16, 6, 2});
  b->Unit(benchmark::kMillisecond);
}

void BM_walk_starts(benchmark::State& state) {
  const auto n = static_cast<unsigned>(state.range(0)), steps = static_cast<unsigned>(state.range(1));
  const qrm::march_mode march = state.range(2) ? qrm::march_mode::surface : qrm::march_mode::voxel;
  const qrm::walk_model m(qrm::render::cornell_box(n), qrm::cube_directions(14, 2), march);
  std::set<std::pair<std::size_t, int>> seen;
  std::vector<qrm::walk_start> starts;
  for (const auto& p : qrm::render::pixel_starts(m, qrm::render::box_scene_camera(n, 16, 16), {}, 1))
    if (p.hit && seen.insert({p.voxel, p.start.direction}).second) starts.push_back(p.start);
  qrm::walk_options o;
  o.steps = steps;
  double lit = 0, width_sum = 0, width_max = 0, full = 0, nz_sum = 0, nz_max = 0;
  for (auto _ : state) {
    lit = width_sum = width_max = nz_sum = nz_max = 0;
    for (const auto& st : starts) {
      const qrm::walk_program w = qrm::make_walk_program(m, st, o);
      qrm::compact_state<std::complex<double>, qrm::wide_label<2>> b(w.circuit.width());
      qrm::run(b, w.circuit);
      const qrm::control c{w.out, true};
      lit += b.probability(std::span<const qrm::control>(&c, 1)) > 0;
      full = static_cast<double>(w.full_width);
      width_sum += static_cast<double>(w.circuit.width());
      width_max = std::max(width_max, static_cast<double>(w.circuit.width()));
      nz_sum += static_cast<double>(b.nonzeros());
      nz_max = std::max(nz_max, static_cast<double>(b.nonzeros()));
    }
  }
  const double k = static_cast<double>(starts.size());
  state.counters["starts"] = k;
  state.counters["lit_starts"] = lit;
  state.counters["unpruned_width"] = full;
  state.counters["width_mean"] = width_sum / k;
  state.counters["width_max"] = width_max;
  state.counters["nonzeros_mean"] = nz_sum / k;
  state.counters["nonzeros_max"] = nz_max;
  state.counters["seconds_per_start"] = benchmark::Counter(k, benchmark::Counter::kIsIterationInvariantRate |
                                                                  benchmark::Counter::kInvert);
}
BENCHMARK(BM_walk_starts)
    ->ArgNames({"N", "steps", "surface"})
    ->ArgsProduct({{16, 32, 64}, {4, 6}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK(BM_exact)->Apply(render_args);
BENCHMARK(BM_monte_carlo_32)->Apply(render_args);
BENCHMARK(BM_emulated_32)->Apply(render_args);

}  // namespace

BENCHMARK_MAIN();
