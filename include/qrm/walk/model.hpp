// qrm/walk/model.hpp: the walk as classical data, shared by the circuit builder (walk.hpp) and
// the classical references (classical.hpp), so both see the same coins, shifts and samples.
//
// A walker state is a fixed-point position per axis (P integer bits, F fractional bits; the
// voxel is the integer part) and a direction index. One step: apply the coin of the current
// voxel to the direction, move, then sample Le (and, except after the last step, rho) of the
// voxel reached. How the walker moves is the model's march:
//   voxel    (the paper's Section 4) one displacement, wrapping modulo 2^(P+F) per axis: a step
//            crosses one voxel, so s steps reach only surfaces within s voxels.
//   surface  (bounce-driven) the displacement repeated k times, k >= 1 the first count that
//            lands in a voxel that is not air (or march_limit() if none does), then the walker
//            is put at that voxel's centre: a step is a bounce, whatever the distance, and
//            between steps the walker always sits at a voxel centre, so the walk's states are
//            (voxel, direction) pairs. The circuit keeps k in a fresh distance register
//            (distance_bits() qubits per step): the move is not injective on positions alone
//            (parallel rays from different voxels reach the same surface), but from a centre c,
//            k displacements and the snap land at c + delta(k, d) with delta depending only on
//            (k, d), so (landing voxel, d, k) determines c and the step stays a permutation.
// A medium voxel (participating media) is not air, so the surface march stops in it like at a
// surface: a walker crossing fog advances one voxel per step, fog costs steps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "coins.hpp"
#include "directions.hpp"
#include "../circuit/ops.hpp"
#include "scene.hpp"

namespace qrm {

// Where a walk starts: a voxel, and one direction or a uniform superposition of all of them.
struct walk_start {
  std::array<unsigned, 3> voxel{0, 0, 0};
  int direction = -1;  // -1: uniform over every direction
};

struct walk_state {
  std::array<std::uint64_t, 3> pos{0, 0, 0};  // fixed point per axis
  std::uint32_t dir = 0;
  auto operator<=>(const walk_state&) const = default;
};

class walk_model {
 public:
  // (A constructor template, so that the coin builders are compiled only where a walk is made.)
  // The march: `march` if given, else the scene's own, else the paper's voxel march.
  template <int = 0>
  walk_model(scene s_in, direction_set dirs, std::optional<march_mode> march = std::nullopt);

  const scene& scene_data() const { return *scene_; }
  const direction_set& directions() const { return dirs_; }
  unsigned dims() const { return scene_->dims(); }
  unsigned position_bits() const { return scene_->position_bits(); }
  unsigned fractional_bits() const { return dirs_.fractional_bits; }
  unsigned axis_bits() const { return position_bits() + fractional_bits(); }
  unsigned direction_bits() const { return dirs_.bits(); }
  std::size_t direction_count() const { return dirs_.size(); }

  march_mode march() const { return march_; }
  // Surface march: the most displacements one step takes, and the qubits that count them.
  std::uint64_t march_limit() const { return march_limit_; }
  unsigned distance_bits() const { return distance_bits_; }

  // Distinct coin matrices and, per voxel, the index of its coin (-1 for air: identity).
  const std::vector<dense_matrix>& coins() const { return coins_; }
  const std::vector<material>& coin_kinds() const { return coin_kinds_; }
  int coin_of(std::size_t voxel_index) const { return coin_of_voxel_[voxel_index]; }
  template <int = 0>
  bool coins_are_real() const {
    for (const auto& c : coins_)
      if (!c.is_real()) return false;
    return true;
  }

  // The voxel index of a fixed-point position.
  template <int = 0>
  std::size_t voxel_of(const std::array<std::uint64_t, 3>& pos) const {
    const unsigned f = fractional_bits();
    return scene_->index(static_cast<unsigned>(pos[0] >> f), static_cast<unsigned>(pos[1] >> f),
                         dims() == 3 ? static_cast<unsigned>(pos[2] >> f) : 0u);
  }
  // The fixed-point centre of a voxel.
  template <int = 0>
  std::array<std::uint64_t, 3> centre_of(const std::array<unsigned, 3>& v) const {
    const unsigned f = fractional_bits();
    const std::uint64_t half = f == 0 ? 0 : std::uint64_t{1} << (f - 1);
    std::array<std::uint64_t, 3> p{};
    for (unsigned a = 0; a < dims(); ++a) p[a] = (static_cast<std::uint64_t>(v[a]) << f) | half;
    return p;
  }
  // Move by direction d's displacement, wrapping modulo 2^(P+F) on each axis.
  template <int = 0>
  std::array<std::uint64_t, 3> shifted(const std::array<std::uint64_t, 3>& pos, std::uint32_t d) const {
    const std::uint64_t wrap = (std::uint64_t{1} << axis_bits()) - 1;
    std::array<std::uint64_t, 3> p = pos;
    for (unsigned a = 0; a < dims(); ++a) p[a] = (pos[a] + static_cast<std::uint64_t>(dirs_.displacement[d][a])) & wrap;
    return p;
  }

  // One step's move in direction d: the new position and the number of displacements k (1 in
  // the voxel march).
  struct move {
    std::array<std::uint64_t, 3> pos;
    std::uint64_t distance;
  };
  template <int = 0>
  move moved_by(const std::array<std::uint64_t, 3>& pos, std::uint32_t d) const {
    std::array<std::uint64_t, 3> p = shifted(pos, d);
    if (march_ == march_mode::voxel) return {p, 1};
    std::uint64_t k = 1;
    for (; k < march_limit_ && (*scene_)[voxel_of(p)].kind == material::air; ++k) p = shifted(p, d);
    return {centre_of(scene_->coords(voxel_of(p))), k};
  }
  template <int = 0>
  std::array<std::uint64_t, 3> moved(const std::array<std::uint64_t, 3>& pos, std::uint32_t d) const {
    return moved_by(pos, d).pos;
  }

  // Where the coin at `voxel_index` sends direction d: (new direction, amplitude) pairs.
  template <int = 0>
  std::vector<std::pair<std::uint32_t, complex>> scatter(std::size_t voxel_index, std::uint32_t d) const {
    const int c = coin_of_voxel_[voxel_index];
    if (c < 0) return {{d, complex(1.0)}};
    std::vector<std::pair<std::uint32_t, complex>> r;
    const dense_matrix& u = coins_[static_cast<std::size_t>(c)];
    for (std::size_t row = 0; row < u.dim; ++row)
      if (u(row, d) != complex{}) r.push_back({static_cast<std::uint32_t>(row), u(row, d)});
    return r;
  }

  // The start of a light-map sample at a voxel's centre: in air or a medium (no normal), every
  // direction; on a surface, the direction that points into it (2D: (normal + 4) mod 8, as the
  // paper).
  template <int = 0>
  walk_start light_map_start(const std::array<unsigned, 3>& v) const {
    walk_start s;
    s.voxel = v;
    const voxel& vox = scene_->at(v[0], v[1], v[2]);
    if (vox.kind == material::air || vox.kind == material::medium) return s;
    if (dims() == 2) {
      s.direction = (vox.normal_index + 4) % 8;
    } else {
      s.direction = static_cast<int>(nearest_direction({-vox.normal[0], -vox.normal[1], -vox.normal[2]}));
    }
    return s;
  }
  // The direction of the set closest to unit vector v.
  template <int = 0>
  std::uint32_t nearest_direction(const vec3& v) const {
    std::uint32_t best = 0;
    double best_dot = -2;
    for (std::uint32_t d = 0; d < dirs_.size(); ++d) {
      const double c = dot(dirs_.vectors[d], v);
      if (c > best_dot) {
        best_dot = c;
        best = d;
      }
    }
    return best;
  }

  // Initial states and their amplitudes.
  template <int = 0>
  std::vector<std::pair<walk_state, complex>> initial_states(const walk_start& s) const {
    if (s.direction >= static_cast<int>(dirs_.size()))
      throw std::invalid_argument("walk start direction " + std::to_string(s.direction) + " is not one of the " +
                                  std::to_string(dirs_.size()) + " directions");
    scene_->index(s.voxel[0], s.voxel[1], s.voxel[2]);  // range check
    walk_state w;
    w.pos = centre_of(s.voxel);
    if (s.direction >= 0) {
      w.dir = static_cast<std::uint32_t>(s.direction);
      return {{w, complex(1.0)}};
    }
    std::vector<std::pair<walk_state, complex>> r;
    const double a = 1.0 / std::sqrt(static_cast<double>(dirs_.size()));
    for (std::uint32_t d = 0; d < dirs_.size(); ++d) {
      w.dir = d;
      r.push_back({w, complex(a)});
    }
    return r;
  }

  double emission(std::size_t voxel_index, int channel) const { return (*scene_)[voxel_index].emission[channel]; }
  template <int = 0>
  double reflectance(std::size_t voxel_index, int channel) const {
    return (*scene_)[voxel_index].reflectance[channel];
  }

 private:
  template <int = 0>
  dense_matrix make_coin(const voxel& v) const {
    switch (v.kind) {
      case material::lambertian:
        if (dims() == 3) return lambertian_coin(dirs_, v.normal);
        return scene_->lambertian_coin() == lambertian_2d::symmetric ? lambertian_coin_2d_symmetric(v.normal_index)
                                                                     : lambertian_coin_2d(v.normal_index);
      case material::boundary: return boundary_coin(dirs_);
      case material::specular: return specular_coin(dirs_, mirror_normal(v));
      case material::glossy: return glossy_coin(dirs_, mirror_normal(v), v.lobe);
      case material::medium: return medium_coin(dirs_, v.density);
      case material::air: break;
    }
    throw std::logic_error("make_coin: air has no coin");
  }

  // A 2D voxel's normal is its index (scenes built in code may leave the vector unset): the
  // king direction of that index.
  template <int = 0>
  vec3 mirror_normal(const voxel& v) const {
    return dims() == 2 ? dirs_.vectors[static_cast<std::size_t>(v.normal_index)] : v.normal;
  }

  std::shared_ptr<const scene> scene_;  // shared: copies of a model are cheap
  direction_set dirs_;
  std::vector<dense_matrix> coins_;
  std::vector<material> coin_kinds_;
  std::vector<int> coin_of_voxel_;
  march_mode march_ = march_mode::voxel;
  std::uint64_t march_limit_ = 1;
  unsigned distance_bits_ = 0;
};

template <int Deferred>
walk_model::walk_model(scene s_in, direction_set dirs, std::optional<march_mode> march)
    : scene_(std::make_shared<const scene>(std::move(s_in))), dirs_(std::move(dirs)) {
  march_ = march.value_or(scene_->march().value_or(march_mode::voxel));
  const scene& s = *scene_;
  s.validate();
  if (dirs_.dims != s.dims())
    throw std::invalid_argument("walk_model: a " + std::to_string(dirs_.dims) + "D direction set for a " +
                                std::to_string(s.dims()) + "D scene");
  if (s.dims() == 2 && dirs_.fractional_bits != 0)
    throw std::invalid_argument("walk_model: 2D walks move whole cells (0 fractional bits)");
  coin_of_voxel_.assign(s.voxel_count(), -1);
  // Voxels with equal coin parameters share one coin. The key is an array, not a tuple: a
  // 7-tuple's comparison operators cost the umbrella header ~1 MiB of g++'s heap.
  std::map<std::array<double, 7>, int> seen;
  for (std::size_t i = 0; i < s.voxel_count(); ++i) {
    const voxel& v = s[i];
    if (v.kind == material::air) continue;
    const std::array<double, 7> key = {static_cast<double>(v.kind), v.normal[0], v.normal[1], v.normal[2],
                                       static_cast<double>(v.normal_index), v.lobe, v.density};
    auto it = seen.find(key);
    if (it == seen.end()) {
      it = seen.emplace(key, static_cast<int>(coins_.size())).first;
      coins_.push_back(make_coin(v));
      coin_kinds_.push_back(v.kind);
    }
    coin_of_voxel_[i] = it->second;
  }
  // The longest march: enough displacements to cross the grid along the slowest direction's
  // largest component (a march that finds no surface by then stops in air).
  const std::uint64_t axis_length = std::uint64_t{s.size()} << dirs_.fractional_bits;
  march_limit_ = 1;
  for (const auto& d : dirs_.displacement) {
    std::uint64_t largest = 0;
    for (unsigned a = 0; a < s.dims(); ++a) largest = std::max<std::uint64_t>(largest, static_cast<std::uint64_t>(std::llabs(d[a])));
    march_limit_ = std::max(march_limit_, (axis_length + largest - 1) / largest);
  }
  distance_bits_ = march_ == march_mode::surface ? static_cast<unsigned>(bits_for(march_limit_ + 1)) : 0;
}


}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_MODEL_INSTANCES(PREFIX)                                        \
  PREFIX walk_model::walk_model(scene, direction_set, std::optional<march_mode>);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_MODEL_INSTANCES(extern template)
}  // namespace qrm
#endif
