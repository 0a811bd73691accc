// qrm/render/quantum.hpp: rendering with the quantum circuit.
//
//   estimate_lightmap   the paper's Fig. 4: for every cell and channel of a 2D scene, the faithful
//                       A operator is simulated and its P(out = 1) estimated with an amplitude
//                       estimator (the paper: FAE, maxiter 5, rescaling). With grover_mode::simulated
//                       every Grover iteration is applied to the state; with
//                       grover_mode::analytic, a = P(out=1) is read once and P after k iterations
//                       is sin^2((2k+1) theta): the same measurement statistics, far cheaper.
//                       With a noise model, each (cell, channel) gets a noisy_oracle (noise/):
//                       quantum trajectories of the noisy circuit, seeded from the cell's stream.
//   render_quantum      a 3D image from the actual 3D walk circuit of each pixel's first hit,
//                       simulated for real (the paper found this infeasible with a general
//                       simulator and emulated it instead).
//   amplitude_path_estimator  the hook that makes render_emulated (the paper's emulator) estimate
//                       mean(f) / (S * scale) with an amplitude estimator, as the paper did.
//
// Both simulate on a backend family (backends/backend.hpp), the compact backend unless told
// otherwise: walk states are sparse. Results are per (cell or start, channel) with a random stream
// of their own, so they are bit-identical for any thread count and for any tiling.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "../backends/backend.hpp"
#include "../backends/compact.hpp"
#include "../walk/classical.hpp"
#include "../support/parallel.hpp"
#include "../estimation/estimator.hpp"
#include "../estimation/oracle.hpp"
#include "../estimation/problem.hpp"
#include "../noise/oracle.hpp"
#include "../walk/lightmap.hpp"
#include "../walk/circuit.hpp"
#include "tiles.hpp"
#include "classical.hpp"

namespace qrm::render {

enum class grover_mode : unsigned char { simulated, analytic };

struct quantum_options {
  unsigned steps = 3;
  estimator_settings estimator;  // default: FAE, maxiter 5, rescaling (the paper's choice)
  grover_mode grover = grover_mode::simulated;
  // Noise (2D light maps): the estimator asks a noisy_oracle with these options (its seed and
  // threads are set per cell: a draw from the cell's stream, one thread) instead of the ideal one.
  std::optional<noise_model> noise;
  noisy_oracle_options noisy;
  std::uint64_t seed = 1;
  unsigned threads = 0;                    // 0: the hardware's; results do not depend on it
  tile part{};                             // only these cells / pixels
  // progress(finished, total): after each job, from any thread: `finished` more of `total` jobs
  // are done (for a progress bar; total is known only to the renderer).
  std::function<void(std::size_t, std::size_t)> progress;
};

// One cell (or walk start) and channel: the estimate of the faithful circuit's P(out = 1), the
// exact value read from the simulated state, and the classical path sum on the same scale.
struct quantum_estimate {
  std::size_t index = 0;  // cell (2D) or start (3D)
  int channel = 0;
  bool computed = false;  // false outside the rendered tile
  double estimate = 0;
  std::array<double, 2> interval{0, 0};
  double exact = 0;      // P(out = 1) of the faithful circuit
  double classical = 0;  // path sum / (S * scale)
  double radiance_scale = 1;  // S * emission scale: radiance = value * radiance_scale
  std::uint64_t a_calls = 0, grover_calls = 0;
  std::string warning;
  // The simulation of the walk circuit: its qubits after pruning, the final state's nonzero
  // amplitudes (compact backend), and the seconds it took (building and running A once).
  std::size_t qubits = 0, nonzeros = 0;
  double simulate_seconds = 0;
};

namespace detail {

// P(out = 1) of a walk program and an estimate of it, for one (start, channel), on backend family F.
template <backend_family F>
quantum_estimate estimate_walk(const walk_model& m, const walk_start& start, int channel, const quantum_options& o,
                               rng& g) {
  walk_options wo;
  wo.steps = o.steps;
  wo.channel = channel;
  const auto t0 = std::chrono::steady_clock::now();
  const walk_program w = make_walk_program(m, start, wo);
  quantum_estimate q;
  q.channel = channel;
  q.computed = true;
  q.radiance_scale = static_cast<double>(o.steps) * w.tables.emission_scale;
  // No path term can fire (pruning found none: no emitter reachable through non-zero
  // reflectances): P(out = 1) is exactly 0, and so is the answer, without an estimator.
  if (std::none_of(w.tables.term_kept.begin(), w.tables.term_kept.end(), [](bool k) { return k; })) return q;
  q.classical = path_sum(m, start, o.steps, channel) / q.radiance_scale;
  const estimation_problem problem{w.circuit, {control{w.out, true}}};
  // Every oracle reaches the estimator as an any_oracle: one instantiation of the estimators
  // instead of one per oracle type (ideal, simulated real or complex, noisy).
  auto finish = [&](any_oracle oracle) {
    const estimation_result r = estimate_amplitude(oracle, o.estimator, g);
    q.estimate = r.estimate;
    q.interval = r.confidence_interval;
    q.a_calls = r.a_calls;
    q.grover_calls = r.grover_calls;
    q.warning = r.warning;
  };
  const walk_run run = walk_run_of<F>(w);
  q.exact = run.probability;
  q.qubits = w.circuit.width();
  q.nonzeros = run.nonzeros;
  q.simulate_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.noise && o.noisy.level == noise_level::global) {
    finish(any_oracle(global_noise_oracle(problem, *o.noise, q.exact, o.noisy.decompose)));
  } else if (o.noise) {
    noisy_oracle_options no = o.noisy;
    no.seed = g();
    no.threads = 1;  // cells run in parallel already
    finish(any_oracle(noisy_oracle(problem, *o.noise, no)));
  } else if (o.grover == grover_mode::simulated) {
    // real for the 2D circuits; 3D coins may be complex
    with_simulated_oracle<F>(problem, [&](auto& oracle) { finish(any_oracle(std::move(oracle))); });
  } else {
    finish(any_oracle(analytic_oracle(q.exact)));
  }
  return q;
}

// Runs job(start index, channel) for every start of [begin, end) and every distinct channel,
// copies repeated channels, and returns the results indexed start * 3 + channel.
template <class Job>
std::vector<quantum_estimate> per_start_and_channel(const scene& sc, std::size_t starts, pixel_range range,
                                                    const quantum_options& o, Job job) {
  const auto source = sc.channel_sources();
  std::vector<quantum_estimate> out(starts * 3);
  const std::size_t jobs = (range.end - range.begin) * 3;
  qrm::detail::parallel_jobs(jobs, o.threads, [&](std::size_t j) {
    const std::size_t start = range.begin + j / 3;
    const int c = static_cast<int>(j % 3);
    if (source[static_cast<std::size_t>(c)] == c) {
      rng g = rng::stream(o.seed, start * 3 + static_cast<std::size_t>(c));
      out[start * 3 + static_cast<std::size_t>(c)] = job(start, c, g);
      out[start * 3 + static_cast<std::size_t>(c)].index = start;
    }
    if (o.progress) o.progress(1, jobs);
  });
  for (std::size_t s = range.begin; s < range.end; ++s)
    for (int c = 0; c < 3; ++c)
      if (source[static_cast<std::size_t>(c)] != c) {
        quantum_estimate copy = out[s * 3 + static_cast<std::size_t>(source[static_cast<std::size_t>(c)])];
        copy.channel = c;
        out[s * 3 + static_cast<std::size_t>(c)] = copy;
      }
  return out;
}

}  // namespace detail

// estimate_lightmap<F>(model, options): every cell of a 2D scene (index x + N y) and channel,
// indexed cell * 3 + channel; the start is the light-map start (cell centre, all directions in
// air, into the surface otherwise), as the paper's Fig. 4.
template <backend_family F = compact_backend>
std::vector<quantum_estimate> estimate_lightmap(const walk_model& m, const quantum_options& o) {
  const scene& sc = m.scene_data();
  const pixel_range range = tile_pixels(sc.voxel_count(), o.part);
  return detail::per_start_and_channel(sc, sc.voxel_count(), range, o, [&](std::size_t cell, int c, rng& g) {
    return detail::estimate_walk<F>(m, m.light_map_start(sc.coords(cell)), c, o, g);
  });
}

// lightmap_images: the light map as images (radiance, one pixel per cell): the estimate, the
// exact faithful value, the classical transport.
struct lightmap_images {
  image estimated, exact, classical;
};

template <int = 0>
inline lightmap_images lightmap_as_images(const scene& sc, std::span<const quantum_estimate> cells) {
  if (sc.dims() != 2) throw std::invalid_argument("lightmap_as_images: a 2D scene is needed");
  lightmap_images im{image(sc.size(), sc.size()), image(sc.size(), sc.size()), image(sc.size(), sc.size())};
  for (const quantum_estimate& q : cells) {
    if (!q.computed) continue;
    const auto xy = sc.coords(q.index);
    auto put = [&](image& img, double v) { img.at(xy[0], xy[1]).channel(q.channel) = static_cast<float>(v * q.radiance_scale); };
    put(im.estimated, q.estimate);
    put(im.exact, q.exact);
    put(im.classical, q.classical);
  }
  return im;
}

// The result of render_quantum: the image, and per distinct walk start the estimates.
struct quantum_image {
  image estimated;  // Le + rho * estimate * S * scale
  image exact;      // Le + rho * exact P(out = 1) * S * scale (the faithful circuit, from the state)
  std::vector<quantum_estimate> starts;  // per distinct (voxel, direction) start and channel
  std::size_t distinct_starts = 0;
};

// render_quantum<F>(model, camera, options): every pixel from its own 3D walk circuit.
template <backend_family F = compact_backend>
quantum_image render_quantum(const walk_model& m, const camera& cam, const quantum_options& o) {
  const auto px = pixel_starts(m, cam, o.part, o.threads);
  const pixel_range r = tile_pixels(static_cast<std::size_t>(cam.width()) * cam.height(), o.part);
  const auto groups = qrm::detail::group_render_starts(px);
  quantum_image out{image(cam.width(), cam.height()), image(cam.width(), cam.height()), {}, groups.keys.size()};
  // Random streams are keyed by the start's (voxel, direction), not by its position in this
  // tile's list, so a pixel gets the same estimate whatever tiling renders it.
  const std::size_t dirs = m.direction_count();
  out.starts = detail::per_start_and_channel(
      m.scene_data(), groups.keys.size(), {0, groups.keys.size()}, o, [&](std::size_t k, int c, rng&) {
        const auto& key = groups.keys[k];
        rng keyed = rng::stream(o.seed, (key.first * dirs + static_cast<std::size_t>(key.second)) * 3 +
                                            static_cast<std::size_t>(c));
        return detail::estimate_walk<F>(m, qrm::detail::render_start_of(m.scene_data(), key), c, o, keyed);
      });
  for (std::size_t k = 0; k < px.size(); ++k) {
    if (!px[k].hit) continue;
    const voxel& v = m.scene_data()[px[k].voxel];
    rgb3 est{}, ex{};
    for (int c = 0; c < 3; ++c) {
      const quantum_estimate& q = out.starts[groups.key_of_pixel[k] * 3 + static_cast<std::size_t>(c)];
      est[static_cast<std::size_t>(c)] = q.estimate * q.radiance_scale;
      ex[static_cast<std::size_t>(c)] = q.exact * q.radiance_scale;
    }
    qrm::detail::shade_pixel(out.estimated, r.begin + k, v, est);
    qrm::detail::shade_pixel(out.exact, r.begin + k, v, ex);
  }
  return out;
}

// amplitude_path_estimator(settings): for render_emulated: the K sampled contributions give
// a = mean(f) / (S * scale) (the Path gate's P(out = 1) on the K-path state); the estimator's
// answer is scaled back. An analytic oracle: the emulator's state is classical anyway.
template <int = 0>
inline path_estimator amplitude_path_estimator(estimator_settings settings) {
  return [settings](const std::vector<double>& f, unsigned steps, double emission_scale, rng& g) {
    double mean = 0;
    for (double v : f) mean += v;
    mean /= static_cast<double>(std::max<std::size_t>(1, f.size()));
    if (mean == 0) return 0.0;  // the K-path state has no term that can fire: P(out = 1) = 0
    const double scale = static_cast<double>(steps) * emission_scale;
    any_oracle oracle(analytic_oracle(std::clamp(mean / scale, 0.0, 1.0)));
    return estimate_amplitude(oracle, settings, g).estimate * scale;
  };
}

}  // namespace qrm::render
