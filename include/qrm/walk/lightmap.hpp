// qrm/walk/lightmap.hpp: exact light maps: for every cell and channel, P(out = 1) of the faithful
// and the history circuits read from the simulated state, and the classical path sum / S on
// the same scale, so the three columns compare directly.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "../backends/backend.hpp"
#include "../backends/compact.hpp"
#include "../backends/dense.hpp"
#include "classical.hpp"
#include "../support/parallel.hpp"
#include "circuit.hpp"

namespace qrm {

struct lightmap_cell {
  unsigned x = 0, y = 0, z = 0;
  int channel = 0;
  double faithful = 0;   // P(out = 1), faithful circuit
  double history = 0;    // P(out = 1), history circuit (paths kept orthogonal)
  double classical = 0;  // branching path sum / (S * emission scale): P(out = 1) of classical transport
  double emission_scale = 1;
  // Radiance = value * S * emission_scale.
};

struct lightmap_options {
  unsigned steps = 3;
  pruning prune = pruning::reachable;
  unsigned threads = 0;  // cells run in parallel (0: hardware threads); results do not depend on it
  bool faithful = true, history = true;
};

// walk_probability<F>(w): P(out = 1) of the walk program w run on backend family F (backend.hpp):
// real amplitudes when every gate is real, one thread per state (cells already run in parallel).
// The compact backend is far faster for walk circuits, whose support is a tiny fraction of 2^width.
// walk_run_of<F>(w) also says how many amplitudes the final state holds (backends that count
// them, as the compact one; 0 otherwise).
struct walk_run {
  double probability = 0;
  std::size_t nonzeros = 0;
};
template <backend_family F>
walk_run walk_run_of(const walk_program& w) {
  return F::visit(w.circuit.width(), w.circuit.is_real(), [&](auto type) {
    using B = typename decltype(type)::type;
    static_assert(backend<B>, "backend_family: visit must pass a qrm::backend");
    B s = F::template make<B>(w.circuit.width());
    walk_run r;
    r.probability = probability_out(s, w);
    if constexpr (requires { s.nonzeros(); }) r.nonzeros = s.nonzeros();
    return r;
  });
}
template <backend_family F>
double walk_probability(const walk_program& w) {
  return walk_run_of<F>(w).probability;
}

// exact_lightmap<F>(model, options): every cell (x, y[, z]) and channel, in the order y, x, channel
// (z outermost in 3D), the circuits run on backend family F. Identical channels (grey scenes) are
// computed once.
template <backend_family F = dense_backend>
std::vector<lightmap_cell> exact_lightmap(const walk_model& m, const lightmap_options& opt) {
  const scene& sc = m.scene_data();
  const std::array<int, 3> source = sc.channel_sources();  // channel c copies channel source[c]
  const std::size_t cells = sc.voxel_count();
  std::vector<lightmap_cell> out(cells * 3);
  detail::parallel_jobs(cells * 3, opt.threads, [&](std::size_t job) {
    const std::size_t cell = job / 3;
    const int c = static_cast<int>(job % 3);
    const auto xyz = sc.coords(cell);
    lightmap_cell& r = out[job];
    r.x = xyz[0];
    r.y = xyz[1];
    r.z = xyz[2];
    r.channel = c;
    r.emission_scale = sc.emission_scale(c);
    if (source[static_cast<std::size_t>(c)] != c) return;  // filled in below
    const walk_start start = m.light_map_start(xyz);
    walk_options o;
    o.steps = opt.steps;
    o.prune = opt.prune;
    o.channel = c;
    r.classical = path_sum(m, start, opt.steps, c) / (static_cast<double>(opt.steps) * r.emission_scale);
    if (opt.faithful) r.faithful = walk_probability<F>(make_walk_program(m, start, o));
    if (opt.history) {
      o.variant = walk_variant::history;
      r.history = walk_probability<F>(make_walk_program(m, start, o));
    }
  });
  for (std::size_t cell = 0; cell < cells; ++cell)
    for (int c = 0; c < 3; ++c)
      if (source[static_cast<std::size_t>(c)] != c) {
        lightmap_cell copy = out[cell * 3 + static_cast<std::size_t>(source[static_cast<std::size_t>(c)])];
        copy.channel = c;
        out[cell * 3 + static_cast<std::size_t>(c)] = copy;
      }
  return out;  // job order: voxel index (x fastest, then y, then z), then channel
}

}  // namespace qrm
