// bench_render3d: 3D images on the walk's discretization (render/render_classical.hpp): the
// Cornell box at 128 x 128 pixels, golden spiral with 15 directions and 3 fractional bits.
// Arguments: voxels per side N, steps s, threads. Each iteration renders the whole image,
// including the per-pixel DDA and walk starts; the walk model is built once outside the loop.
// Counter `starts`: distinct (voxel, direction) walk starts, i.e. path sums or enumerations.
#include <benchmark/benchmark.h>

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

BENCHMARK(BM_exact)->Apply(render_args);
BENCHMARK(BM_monte_carlo_32)->Apply(render_args);
BENCHMARK(BM_emulated_32)->Apply(render_args);

}  // namespace

BENCHMARK_MAIN();
