// qrm/render/classical.hpp: images of 3D scenes on the walk's own discretization (same
// directions, voxels and coins as the quantum walk): the exact path sum per pixel, Monte Carlo
// path tracing, and the paper's emulator (every branching path enumerated, a few sampled).
//
// A pixel: the camera ray's first hit (render/dda.hpp) starts a walk at the hit voxel's centre,
// moving in the model's direction nearest the ray among those the voxel's coin treats as
// incoming (so the coin scatters the walker out of the surface; a Lambertian, specular or glossy
// voxel's incoming directions are split_hemisphere(...).incoming; a boundary or medium voxel
// uses the nearest direction of all: a camera ray entering fog starts its walk in the first fog
// voxel, going on along the ray).
// Its radiance, per channel, is
//     L = Le(hit) + rho(hit) * E[f],
// E[f] the walk's path sum for `steps` steps (qrm::path_sum). The walk's f does not include the
// start voxel's own emission and reflectance (the 2D light maps follow the paper and leave them
// out); an image needs them, or a visible light would look black and a red wall grey, so the
// pixel adds them. Rays that hit nothing are black.
//
// Determinism: every pixel's random numbers come from rng::stream(seed, pixel index) with the
// pixel index y * width + x of the whole image, and every value is computed the same way
// whichever thread or tile computes it, so images are bit-identical for any thread count and
// merge_tiles of the parts equals the image rendered whole.
//
// Speed: pixels that start from the same (voxel, direction) share one path sum or enumeration;
// all three channels come from one pass (the transition probabilities are channel-independent),
// so grey scenes cost no more than one channel.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "../support/random.hpp"
#include "../walk/model.hpp"
#include "camera.hpp"
#include "dda.hpp"
#include "tiles.hpp"
#include "../support/parallel.hpp"

namespace qrm::detail {

// The walk's transitions as flat tables: out of direction d at a voxel with coin c, the list of
// (new direction, probability |U[r][d]|^2) in the order walk_model::scatter gives them, so
// sums and random choices over it match qrm::path_sum and qrm::monte_carlo operation for
// operation.
class transition_table {
 public:
  struct transition {
    std::uint32_t direction;
    double probability;
  };
  template <int = 0>
  explicit transition_table(const walk_model& m) : model_(&m), d_(m.direction_count()) {
    const std::size_t coins = m.coins().size();
    offset_.assign((coins + 1) * d_ + 1, 0);
    // Slot 0..D-1: air (identity); then coin c at (c + 1) * D.
    for (std::size_t d = 0; d < d_; ++d) {
      list_.push_back({static_cast<std::uint32_t>(d), std::norm(complex(1.0))});
      offset_[d + 1] = list_.size();
    }
    for (std::size_t c = 0; c < coins; ++c) {
      const dense_matrix& u = m.coins()[c];
      for (std::size_t d = 0; d < d_; ++d) {
        for (std::size_t row = 0; row < u.dim; ++row)
          if (u(row, d) != complex{}) list_.push_back({static_cast<std::uint32_t>(row), std::norm(u(row, d))});
        offset_[(c + 1) * d_ + d + 1] = list_.size();
      }
    }
  }
  template <int = 0>
  std::span<const transition> out(std::size_t voxel, std::uint32_t d) const {
    const std::size_t slot = static_cast<std::size_t>(model_->coin_of(voxel) + 1) * d_ + d;
    return {list_.data() + offset_[slot], offset_[slot + 1] - offset_[slot]};
  }
  const walk_model& model() const { return *model_; }

 private:
  const walk_model* model_;
  std::size_t d_;
  std::vector<transition> list_;
  std::vector<std::size_t> offset_;
};

}  // namespace qrm::detail

namespace qrm::render {

using rgb3 = std::array<double, 3>;

// hit_walk_start(model, hit, ray_direction): the walk's start for a camera ray's first hit (see
// the file comment for the direction).
template <int = 0>
inline walk_start hit_walk_start(const walk_model& m, const voxel_hit& h, const vec3& ray_direction) {
  if (!h.hit) throw std::invalid_argument("hit_walk_start: the ray hit nothing");
  const vec3 d = normalized(ray_direction);
  walk_start s;
  s.voxel = h.voxel;
  const voxel& v = m.scene_data()[h.index];
  if (v.kind == material::lambertian || v.kind == material::specular || v.kind == material::glossy) {
    const lambertian_split sp = split_hemisphere(m.directions(), v.normal);
    double best = -2;
    for (std::size_t k : sp.incoming) {
      const double c = dot(m.directions().vectors[k], d);
      if (c > best) {
        best = c;
        s.direction = static_cast<int>(k);
      }
    }
    if (!sp.incoming.empty()) return s;
  }
  s.direction = static_cast<int>(m.nearest_direction(d));
  return s;
}

// One pixel's first hit and walk start.
struct pixel_start {
  bool hit = false;
  std::size_t voxel = 0;  // scene index of the hit voxel
  walk_start start;
};

}  // namespace qrm::render

namespace qrm::detail {
template <int = 0>
inline void check_render_model(const walk_model& m, const char* what) {
  if (m.dims() != 3) throw std::invalid_argument(std::string(what) + ": the walk model's scene is not 3D");
}
template <int = 0>
inline unsigned threads_or_hardware(unsigned t) {
  return t ? t : std::max(1u, std::thread::hardware_concurrency());
}
}  // namespace qrm::detail

namespace qrm::render {

// pixel_starts(model, camera, part, threads): the first hit and walk start of every pixel of a
// tile; entry k is pixel tile_pixels(...).begin + k.
template <int = 0>
inline std::vector<pixel_start> pixel_starts(const walk_model& m, const camera& cam, tile part = {},
                                             unsigned threads = 0) {
  qrm::detail::check_render_model(m, "pixel_starts");
  const pixel_range r = tile_pixels(static_cast<std::size_t>(cam.width()) * cam.height(), part);
  std::vector<pixel_start> out(r.end - r.begin);
  qrm::detail::parallel_jobs(out.size(), threads, [&](std::size_t k) {
    const std::size_t p = r.begin + k;
    const camera_ray ray = cam.ray(static_cast<unsigned>(p % cam.width()), static_cast<unsigned>(p / cam.width()));
    const voxel_hit h = first_hit(m.scene_data(), ray.origin, ray.direction);
    if (!h.hit) return;
    out[k].hit = true;
    out[k].voxel = h.index;
    out[k].start = hit_walk_start(m, h, ray.direction);
  });
  return out;
}

// path_sum_rgb(tables, start, steps): qrm::path_sum for all three channels in one forward pass;
// each channel's value is bit-identical to qrm::path_sum's: the walker states are kept in a
// vector sorted by state (qrm::path_sum's std::map order) and contributions to one state are
// added in the order the map would receive them (a stable sort keeps generation order).
template <int = 0>
rgb3 path_sum_rgb(const qrm::detail::transition_table& t, const walk_start& start, unsigned steps) {
  const walk_model& m = t.model();
  struct entry {
    walk_state w;
    rgb3 p;
  };
  auto by_state = [](const entry& a, const entry& b) { return a.w < b.w; };
  // Adds up the entries of equal states, in order, starting from zero as std::map's operator[].
  auto reduce = [](const std::vector<entry>& in, std::vector<entry>& out) {
    out.clear();
    for (std::size_t k = 0; k < in.size();) {
      entry acc{in[k].w, {0, 0, 0}};
      for (; k < in.size() && in[k].w == acc.w; ++k)
        for (std::size_t c = 0; c < 3; ++c) acc.p[c] += in[k].p[c];
      out.push_back(acc);
    }
  };
  std::vector<entry> weight, next;
  for (const auto& [w, a] : m.initial_states(start)) {
    const double q = std::norm(a);
    next.push_back({w, {q, q, q}});
  }
  std::stable_sort(next.begin(), next.end(), by_state);
  reduce(next, weight);
  rgb3 expected{0, 0, 0};
  for (unsigned i = 0; i < steps; ++i) {
    next.clear();
    for (const entry& e : weight)
      for (const auto& tr : t.out(m.voxel_of(e.w.pos), e.w.dir))
        next.push_back({{m.moved(e.w.pos, tr.direction), tr.direction},
                        {e.p[0] * tr.probability, e.p[1] * tr.probability, e.p[2] * tr.probability}});
    std::stable_sort(next.begin(), next.end(), by_state);
    reduce(next, weight);
    for (entry& e : weight) {
      const voxel& vx = m.scene_data()[m.voxel_of(e.w.pos)];
      for (std::size_t c = 0; c < 3; ++c) {
        expected[c] += e.p[c] * vx.emission[static_cast<int>(c)];
        e.p[c] *= vx.reflectance[static_cast<int>(c)];
      }
    }
  }
  return expected;
}

// radiance_table: E[f] of every (voxel, direction) walk start at once, by dynamic programming
// backwards over the steps to go: with V_0 = 0,
//     V_i(v, d) = sum over the coin's (d', p) at v:  p * (Le(w) + rho(w) * V_{i-1}(w, d')),
// w the voxel the walker moves to from v's centre in direction d'. Polynomial: steps x states x
// transitions, never paths. It applies when the walker sits at voxel centres between steps
// (the surface march, or whole-voxel displacements), so that (voxel, direction) is the whole
// walker state; states are the non-air voxels and every voxel a move from them reaches.
// V_s(v, d) equals qrm::path_sum for the start (v, d) up to rounding (a different summation
// order; tested to 1e-12).
class radiance_table {
 public:
  // applies(model): whether the walker's states are (voxel, direction) pairs.
  static bool applies(const walk_model& m) { return m.march() == march_mode::surface || m.fractional_bits() == 0; }

  template <int = 0>
  radiance_table(const qrm::detail::transition_table& t, unsigned steps, unsigned threads = 0)
      : d_(t.model().direction_count()) {
    const walk_model& m = t.model();
    if (!applies(m))
      throw std::invalid_argument("radiance_table: the walker leaves voxel centres (voxel march with sub-voxel bits)");
    const scene& sc = m.scene_data();
    const std::size_t none = ~std::size_t{0};
    slot_.assign(sc.voxel_count(), none);
    for (std::size_t v = 0; v < sc.voxel_count(); ++v)
      if (sc[v].kind != material::air) add_voxel(v);
    // Where each state's moves land (adding the voxels reached, air included, until closed).
    landing_.clear();
    for (std::size_t k = 0; k < voxels_.size(); ++k)
      for (std::uint32_t d = 0; d < d_; ++d) {
        const auto centre = m.centre_of(sc.coords(voxels_[k]));
        const std::size_t w = m.voxel_of(m.moved(centre, d));
        if (slot_[w] == none) add_voxel(w);
        landing_.push_back(static_cast<std::uint32_t>(slot_[w]));
      }
    std::vector<rgb3> prev(voxels_.size() * d_, rgb3{0, 0, 0});
    value_ = prev;
    const unsigned workers = qrm::detail::threads_or_hardware(threads);
    constexpr std::size_t chunk = 4096;
    const std::size_t states = value_.size();
    for (unsigned i = 0; i < steps; ++i) {
      qrm::detail::parallel_jobs((states + chunk - 1) / chunk, workers, [&](std::size_t job) {
        for (std::size_t st = job * chunk; st < std::min(states, (job + 1) * chunk); ++st) {
          const std::size_t k = st / d_;
          rgb3 acc{0, 0, 0};
          for (const auto& tr : t.out(voxels_[k], static_cast<std::uint32_t>(st % d_))) {
            const std::uint32_t w = landing_[k * d_ + tr.direction];
            const voxel& vx = sc[voxels_[w]];
            const rgb3& next = prev[static_cast<std::size_t>(w) * d_ + tr.direction];
            for (std::size_t c = 0; c < 3; ++c)
              acc[c] += tr.probability * (vx.emission[static_cast<int>(c)] + vx.reflectance[static_cast<int>(c)] * next[c]);
          }
          value_[st] = acc;
        }
      });
      std::swap(prev, value_);
    }
    std::swap(prev, value_);
  }

  // E[f] of the walk from voxel v's centre in direction d; v must be a table state (every
  // non-air voxel is).
  template <int = 0>
  const rgb3& value(std::size_t voxel_index, std::uint32_t d) const {
    const std::size_t k = slot_[voxel_index];
    if (k == ~std::size_t{0}) throw std::out_of_range("radiance_table: voxel " + std::to_string(voxel_index) + " is not a table state");
    return value_[k * d_ + d];
  }
  std::size_t states() const { return value_.size(); }

 private:
  template <int = 0>
  void add_voxel(std::size_t v) {
    slot_[v] = voxels_.size();
    voxels_.push_back(v);
  }
  std::size_t d_;
  std::vector<std::size_t> slot_;       // per scene voxel: its index in voxels_, or none
  std::vector<std::size_t> voxels_;     // table voxels
  std::vector<std::uint32_t> landing_;  // per (table voxel, direction): the table voxel a move lands in
  std::vector<rgb3> value_;             // per (table voxel, direction): V_steps
};

struct monte_carlo_rgb {
  rgb3 mean{0, 0, 0}, standard_error{0, 0, 0};
  std::uint64_t paths = 0;
};

}  // namespace qrm::render

namespace qrm::detail {
// One random path of a walk: its contribution f per channel. The generator is read as
// qrm::monte_carlo reads it: one uniform for the initial state, then one per step.
template <int = 0>
inline render::rgb3 random_path_f(const transition_table& t, const std::vector<std::pair<walk_state, complex>>& init,
                                  unsigned steps, rng& g) {
  const walk_model& m = t.model();
  auto pick_init = [&] {
    double u = g.uniform(), acc = 0;
    for (std::size_t k = 0; k < init.size(); ++k) {
      acc += std::norm(init[k].second);
      if (u < acc) return k;
    }
    return init.size() - 1;
  };
  walk_state w = init[pick_init()].first;
  render::rgb3 prefix{1, 1, 1}, f{0, 0, 0};
  for (unsigned i = 0; i < steps; ++i) {
    const auto options = t.out(m.voxel_of(w.pos), w.dir);
    const double u = g.uniform();
    double acc = 0;
    std::size_t k = options.size() - 1;
    for (std::size_t j = 0; j < options.size(); ++j) {
      acc += options[j].probability;
      if (u < acc) {
        k = j;
        break;
      }
    }
    const std::uint32_t d = options[k].direction;
    w = {m.moved(w.pos, d), d};
    const voxel& vx = m.scene_data()[m.voxel_of(w.pos)];
    for (std::size_t c = 0; c < 3; ++c) {
      f[c] += prefix[c] * vx.emission[static_cast<int>(c)];
      prefix[c] *= vx.reflectance[static_cast<int>(c)];
    }
  }
  return f;
}
}  // namespace qrm::detail

namespace qrm::render {

// monte_carlo_rgb_walk(tables, start, steps, paths, g): qrm::monte_carlo for all three channels
// with one set of paths; each channel's result is bit-identical to qrm::monte_carlo's with a
// generator in the same state (the channels share the paths, as a spectral path tracer would).
template <int = 0>
inline monte_carlo_rgb monte_carlo_rgb_walk(const qrm::detail::transition_table& t, const walk_start& start, unsigned steps,
                                            std::uint64_t paths, rng& g) {
  if (paths == 0) throw std::invalid_argument("monte_carlo: paths must be positive");
  const auto init = t.model().initial_states(start);
  rgb3 sum{0, 0, 0}, sum2{0, 0, 0};
  for (std::uint64_t n = 0; n < paths; ++n) {
    const rgb3 f = qrm::detail::random_path_f(t, init, steps, g);
    for (std::size_t c = 0; c < 3; ++c) {
      sum[c] += f[c];
      sum2[c] += f[c] * f[c];
    }
  }
  monte_carlo_rgb r;
  r.paths = paths;
  for (std::size_t c = 0; c < 3; ++c) {
    r.mean[c] = sum[c] / static_cast<double>(paths);
    const double var = paths > 1 ? std::max(0.0, (sum2[c] - sum[c] * r.mean[c]) / static_cast<double>(paths - 1)) : 0.0;
    r.standard_error[c] = std::sqrt(var / static_cast<double>(paths));
  }
  return r;
}

// Every branching path of a walk, with its probability and contribution (the paper's emulator).
struct path_set {
  unsigned steps = 0;
  std::vector<double> probability;        // per path; they sum to 1
  std::vector<rgb3> f;                    // per path: f = sum_i Le_i prod_{k<i} rho_k, per channel
  std::vector<std::uint32_t> voxels;      // per path, `steps` entries: the voxel after each step
  std::vector<std::uint32_t> directions;  // per path, `steps` entries: the direction of each step
  std::vector<double> cumulative;         // running sums of `probability`, for sampling

  std::size_t size() const { return probability.size(); }
  // sum over paths of probability * f: the exact E[f] (equals qrm::path_sum up to rounding).
  template <int = 0>
  rgb3 exact_mean() const {
    rgb3 s{0, 0, 0};
    for (std::size_t k = 0; k < size(); ++k)
      for (std::size_t c = 0; c < 3; ++c) s[c] += probability[k] * f[k][c];
    return s;
  }
  // sample_path_indices(K, g): K paths drawn by probability, with replacement.
  template <int = 0>
  std::vector<std::size_t> sample_path_indices(std::size_t count, rng& g) const {
    if (cumulative.empty()) throw std::logic_error("path_set: no paths to sample");
    std::vector<std::size_t> out(count);
    const double total = cumulative.back();
    for (std::size_t& k : out) {
      const double u = g.uniform() * total;
      k = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
      k = std::min(k, size() - 1);
    }
    return out;
  }
  // sample_paths(K, g): the contributions f of K paths drawn by probability, with replacement.
  template <int = 0>
  std::vector<rgb3> sample_paths(std::size_t count, rng& g) const {
    std::vector<rgb3> out;
    out.reserve(count);
    for (std::size_t k : sample_path_indices(count, g)) out.push_back(f[k]);
    return out;
  }
};

// enumerate_paths(model or tables, start, steps, path_budget): every branching path, depth
// first in coin order. Exponential in steps: throws std::length_error, naming the budget, as
// soon as there are more than path_budget paths.
template <int = 0>
path_set enumerate_paths(const qrm::detail::transition_table& t, const walk_start& start, unsigned steps,
                                std::size_t path_budget = std::size_t{1} << 20) {
  const walk_model& m = t.model();
  path_set ps;
  ps.steps = steps;
  std::vector<std::uint32_t> vox(steps), dir(steps);
  auto walk = [&](auto&& self, const walk_state& w, unsigned i, double prob, const rgb3& prefix,
                  const rgb3& f) -> void {
    if (i == steps) {
      if (ps.size() == path_budget)
        throw std::length_error("enumerate_paths: more than " + std::to_string(path_budget) + " paths from voxel (" +
                                std::to_string(start.voxel[0]) + ", " + std::to_string(start.voxel[1]) + ", " +
                                std::to_string(start.voxel[2]) + ") in " + std::to_string(steps) +
                                " steps; raise path_budget or take fewer steps");
      ps.probability.push_back(prob);
      ps.f.push_back(f);
      ps.voxels.insert(ps.voxels.end(), vox.begin(), vox.end());
      ps.directions.insert(ps.directions.end(), dir.begin(), dir.end());
      return;
    }
    for (const auto& tr : t.out(m.voxel_of(w.pos), w.dir)) {
      const walk_state n{m.moved(w.pos, tr.direction), tr.direction};
      const std::size_t v = m.voxel_of(n.pos);
      const voxel& vx = m.scene_data()[v];
      rgb3 p2, f2;
      for (std::size_t c = 0; c < 3; ++c) {
        f2[c] = f[c] + prefix[c] * vx.emission[static_cast<int>(c)];
        p2[c] = prefix[c] * vx.reflectance[static_cast<int>(c)];
      }
      vox[i] = static_cast<std::uint32_t>(v);
      dir[i] = tr.direction;
      self(self, n, i + 1, prob * tr.probability, p2, f2);
    }
  };
  for (const auto& [w, a] : m.initial_states(start)) walk(walk, w, 0, std::norm(a), rgb3{1, 1, 1}, rgb3{0, 0, 0});
  ps.cumulative.resize(ps.size());
  double acc = 0;
  for (std::size_t k = 0; k < ps.size(); ++k) ps.cumulative[k] = acc += ps.probability[k];
  return ps;
}
template <int = 0>
path_set enumerate_paths(const walk_model& m, const walk_start& start, unsigned steps,
                                std::size_t path_budget = std::size_t{1} << 20) {
  return enumerate_paths(qrm::detail::transition_table(m), start, steps, path_budget);
}

// ---------------------------------------------------------------------------------------------
// Images.

struct render_options {
  unsigned steps = 3;
  unsigned threads = 0;  // 0: the hardware's; the result does not depend on it
  tile part{};           // render only these pixels (the rest stay black); see merge_tiles
  // progress(finished, total): after each job, from any thread: `finished` more of `total` jobs
  // (distinct walk starts, or pixels for Monte Carlo) are done.
  std::function<void(std::size_t, std::size_t)> progress;
};

}  // namespace qrm::render

namespace qrm::detail {
// The distinct walk starts of a tile's pixels, sorted, and for each pixel the index of its start.
struct render_start_groups {
  std::vector<std::pair<std::size_t, int>> keys;  // (voxel index, direction)
  std::vector<std::size_t> key_of_pixel;          // per pixel of the tile; unused for misses
};
template <int = 0>
inline render_start_groups group_render_starts(const std::vector<render::pixel_start>& px) {
  render_start_groups g;
  for (const render::pixel_start& p : px)
    if (p.hit) g.keys.emplace_back(p.voxel, p.start.direction);
  std::sort(g.keys.begin(), g.keys.end());
  g.keys.erase(std::unique(g.keys.begin(), g.keys.end()), g.keys.end());
  g.key_of_pixel.assign(px.size(), 0);
  for (std::size_t k = 0; k < px.size(); ++k)
    if (px[k].hit)
      g.key_of_pixel[k] = static_cast<std::size_t>(
          std::lower_bound(g.keys.begin(), g.keys.end(), std::make_pair(px[k].voxel, px[k].start.direction)) -
          g.keys.begin());
  return g;
}
// for_each_hit_pixel(pixels, threads, options, job): job(k) for every pixel k of the tile whose
// camera ray hits the scene, in parallel; the progress callback counts every pixel.
template <class Job>
void for_each_hit_pixel(const std::vector<render::pixel_start>& px, unsigned threads, const render::render_options& o,
                        Job&& job) {
  parallel_jobs(px.size(), threads, [&](std::size_t k) {
    const struct report_at_exit {
      const render::render_options& o;
      std::size_t total;
      ~report_at_exit() {
        if (o.progress) o.progress(1, total);
      }
    } report{o, px.size()};
    if (px[k].hit) job(k);
  });
}
template <int = 0>
inline walk_start render_start_of(const scene& sc, const std::pair<std::size_t, int>& key) {
  walk_start s;
  s.voxel = sc.coords(key.first);
  s.direction = key.second;
  return s;
}
// Le + rho * value, per channel, into pixel p.
template <int = 0>
inline void shade_pixel(render::image& img, std::size_t p, const voxel& v, const render::rgb3& value) {
  for (int c = 0; c < 3; ++c)
    img.pixels()[p].channel(c) =
        static_cast<float>(v.emission[c] + v.reflectance[c] * value[static_cast<std::size_t>(c)]);
}
}  // namespace qrm::detail

namespace qrm::render {

// render_exact(model, camera, options): every pixel's exact radiance (the path sum): by the
// radiance_table when the walker's states are (voxel, direction) pairs, else per start.
template <int = 0>
image render_exact(const walk_model& m, const camera& cam, const render_options& o = {}) {
  const unsigned threads = qrm::detail::threads_or_hardware(o.threads);
  const auto px = pixel_starts(m, cam, o.part, threads);
  const pixel_range r = tile_pixels(static_cast<std::size_t>(cam.width()) * cam.height(), o.part);
  const auto groups = qrm::detail::group_render_starts(px);
  const qrm::detail::transition_table tables(m);
  std::vector<rgb3> value(groups.keys.size());
  if (radiance_table::applies(m)) {
    const radiance_table table(tables, o.steps, threads);
    for (std::size_t k = 0; k < groups.keys.size(); ++k)
      value[k] = table.value(groups.keys[k].first, static_cast<std::uint32_t>(groups.keys[k].second));
    if (o.progress) o.progress(groups.keys.size(), groups.keys.size());
  } else {
    qrm::detail::parallel_jobs(groups.keys.size(), threads, [&](std::size_t k) {
      value[k] = path_sum_rgb(tables, qrm::detail::render_start_of(m.scene_data(), groups.keys[k]), o.steps);
      if (o.progress) o.progress(1, groups.keys.size());
    });
  }
  image img(cam.width(), cam.height());
  for (std::size_t k = 0; k < px.size(); ++k)
    if (px[k].hit)
      qrm::detail::shade_pixel(img, r.begin + k, m.scene_data()[px[k].voxel], value[groups.key_of_pixel[k]]);
  return img;
}

struct monte_carlo_image {
  image mean;            // Le + rho * (mean of f over the paths)
  image standard_error;  // rho * (standard error of that mean)
};

// render_monte_carlo(model, camera, paths, seed, options): `paths` random walks per pixel
// (qrm::monte_carlo's walk, all channels on the same paths), pixel p seeded with
// rng::stream(seed, p).
template <int = 0>
monte_carlo_image render_monte_carlo(const walk_model& m, const camera& cam, std::uint64_t paths,
                                            std::uint64_t seed, const render_options& o = {}) {
  if (paths == 0) throw std::invalid_argument("render_monte_carlo: paths per pixel must be positive");
  const unsigned threads = qrm::detail::threads_or_hardware(o.threads);
  const auto px = pixel_starts(m, cam, o.part, threads);
  const pixel_range r = tile_pixels(static_cast<std::size_t>(cam.width()) * cam.height(), o.part);
  const qrm::detail::transition_table tables(m);
  monte_carlo_image out{image(cam.width(), cam.height()), image(cam.width(), cam.height())};
  qrm::detail::for_each_hit_pixel(px, threads, o, [&](std::size_t k) {
    const std::size_t p = r.begin + k;
    rng g = rng::stream(seed, p);
    const monte_carlo_rgb est = monte_carlo_rgb_walk(tables, px[k].start, o.steps, paths, g);
    const voxel& v = m.scene_data()[px[k].voxel];
    qrm::detail::shade_pixel(out.mean, p, v, est.mean);
    for (int c = 0; c < 3; ++c)
      out.standard_error.pixels()[p].channel(c) =
          static_cast<float>(v.reflectance[c] * est.standard_error[static_cast<std::size_t>(c)]);
  });
  return out;
}

// Turns the K sampled contributions f of one pixel and channel into an estimate of E[f]; an
// amplitude estimator gets a = mean(f) / (steps * emission_scale) and scales its answer back.
// Called with the pixel's generator, after the paths were drawn from it.
using path_estimator =
    std::function<double(const std::vector<double>& f, unsigned steps, double emission_scale, rng& g)>;

struct emulation_options {
  std::size_t paths_per_pixel = 32;  // K, the paper's 32
  std::uint64_t seed = 1;
  std::size_t path_budget = std::size_t{1} << 20;  // per walk start; see enumerate_paths
  path_estimator estimate;                         // empty: the mean of the K contributions
};

struct emulated_image {
  image sampled;  // Le + rho * estimate from K sampled paths
  image exact;    // Le + rho * (the exact mean over all paths)
};

// render_emulated(model, camera, emulation, options): the paper's emulator: per pixel, K paths
// are drawn by probability with rng::stream(seed, pixel), and their mean contribution (or
// `estimate`) gives the pixel. Where the radiance_table applies (the walker's states are
// (voxel, direction) pairs) the paths are drawn as random walks and the exact mean comes from
// the table: polynomial at any size. Otherwise (the voxel march with sub-voxel bits, the
// authors' setting) every branching path of the pixel's start is enumerated and the K paths
// drawn from that list (exponential in steps: see emulation_options::path_budget). Either way
// the K paths have the same distribution. A channel whose exact mean is 0 (no path reaches an
// emitter through non-zero reflectances) is 0, without an estimator.
template <int = 0>
emulated_image render_emulated(const walk_model& m, const camera& cam, const emulation_options& e,
                                      const render_options& o = {}) {
  if (e.paths_per_pixel == 0) throw std::invalid_argument("render_emulated: paths per pixel must be positive");
  const unsigned threads = qrm::detail::threads_or_hardware(o.threads);
  const auto px = pixel_starts(m, cam, o.part, threads);
  const pixel_range r = tile_pixels(static_cast<std::size_t>(cam.width()) * cam.height(), o.part);
  const qrm::detail::transition_table tables(m);
  const scene& sc = m.scene_data();
  const rgb3 scale{sc.emission_scale(0), sc.emission_scale(1), sc.emission_scale(2)};
  emulated_image out{image(cam.width(), cam.height()), image(cam.width(), cam.height())};
  // The pixel's estimate from its K sampled contributions.
  auto estimate = [&](const std::vector<rgb3>& samples, const rgb3& exact, std::vector<double>& channel, rng& g) {
    rgb3 est{0, 0, 0};
    for (std::size_t c = 0; c < 3; ++c) {
      if (exact[c] == 0) continue;
      for (std::size_t j = 0; j < samples.size(); ++j) channel[j] = samples[j][c];
      if (e.estimate) {
        est[c] = e.estimate(channel, o.steps, scale[c], g);
      } else {
        double sum = 0;
        for (double x : channel) sum += x;
        est[c] = sum / static_cast<double>(channel.size());
      }
    }
    return est;
  };
  if (radiance_table::applies(m)) {
    const radiance_table table(tables, o.steps, threads);
    qrm::detail::for_each_hit_pixel(px, threads, o, [&](std::size_t k) {
      const std::size_t p = r.begin + k;
      const voxel& v = sc[px[k].voxel];
      const rgb3& exact = table.value(px[k].voxel, static_cast<std::uint32_t>(px[k].start.direction));
      qrm::detail::shade_pixel(out.exact, p, v, exact);
      rng g = rng::stream(e.seed, p);
      const auto init = m.initial_states(px[k].start);
      std::vector<rgb3> samples(e.paths_per_pixel);
      for (rgb3& f : samples) f = qrm::detail::random_path_f(tables, init, o.steps, g);
      std::vector<double> channel(e.paths_per_pixel);
      qrm::detail::shade_pixel(out.sampled, p, v, estimate(samples, exact, channel, g));
    });
    return out;
  }
  const auto groups = qrm::detail::group_render_starts(px);
  // Pixels of each start, in pixel order.
  std::vector<std::vector<std::size_t>> members(groups.keys.size());
  for (std::size_t k = 0; k < px.size(); ++k)
    if (px[k].hit) members[groups.key_of_pixel[k]].push_back(k);
  qrm::detail::parallel_jobs(groups.keys.size(), threads, [&](std::size_t key) {
    const path_set ps =
        enumerate_paths(tables, qrm::detail::render_start_of(sc, groups.keys[key]), o.steps, e.path_budget);
    const rgb3 exact = ps.exact_mean();
    std::vector<double> channel(e.paths_per_pixel);
    for (std::size_t k : members[key]) {
      const std::size_t p = r.begin + k;
      const voxel& v = sc[px[k].voxel];
      qrm::detail::shade_pixel(out.exact, p, v, exact);
      rng g = rng::stream(e.seed, p);
      qrm::detail::shade_pixel(out.sampled, p, v, estimate(ps.sample_paths(e.paths_per_pixel, g), exact, channel, g));
    }
    if (o.progress) o.progress(1, groups.keys.size());
  });
  return out;
}

}  // namespace qrm::render

// This header's part of <qrm/render/compiled_render.hpp> (QRM_COMPILED_RENDER).
#define QRM_DETAIL_CLASSICAL_RENDER_INSTANCES(PREFIX)                                                                 \
  PREFIX image render_exact<0>(const walk_model&, const camera&, const render_options&);                              \
  PREFIX monte_carlo_image render_monte_carlo<0>(const walk_model&, const camera&, std::uint64_t, std::uint64_t,      \
                                                const render_options&);                                               \
  PREFIX emulated_image render_emulated<0>(const walk_model&, const camera&, const emulation_options&,                \
                                          const render_options&);                                                     \
  PREFIX rgb3 path_sum_rgb<0>(const qrm::detail::transition_table&, const walk_start&, unsigned);                     \
  PREFIX path_set enumerate_paths<0>(const qrm::detail::transition_table&, const walk_start&, unsigned, std::size_t); \
  PREFIX path_set enumerate_paths<0>(const walk_model&, const walk_start&, unsigned, std::size_t);
#ifdef QRM_COMPILED_RENDER
namespace qrm::render {
QRM_DETAIL_CLASSICAL_RENDER_INSTANCES(extern template)
}  // namespace qrm::render
#endif
