// qrm/walk/scene.hpp: voxel scenes (2D grids and 3D voxel grids) as run-time data.
//
// A scene is N^dims voxels, N = 2^P. Voxel (x, y[, z]) has index x + N (y + N z); in 2D, x is
// the column and y the row, y growing downwards (the paper's convention). Each voxel has a kind
// (which coin the walk applies there), a normal, and RGB reflectance and emission.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace qrm {

enum class material : unsigned char { air, lambertian, boundary, specular, glossy, medium };

constexpr const char* material_name(material m) {
  switch (m) {
    case material::air: return "air";
    case material::lambertian: return "lambertian";
    case material::boundary: return "boundary";
    case material::specular: return "specular";
    case material::glossy: return "glossy";
    case material::medium: return "medium";
  }
  return "?";
}

// How a walk moves between steps (walk/model.hpp): the paper's one voxel per step, or one
// bounce per step (to the next surface). A scene may name the one it was made for.
enum class march_mode : unsigned char { voxel, surface };
constexpr const char* march_name(march_mode m) { return m == march_mode::voxel ? "voxel" : "surface"; }

// Which 2D Lambertian coin a scene's Lambertian cells use (walk/coins.hpp): the paper's, whose
// lobe is one-sided about the normal, or the mirror-symmetric one.
enum class lambertian_2d : unsigned char { paper, symmetric };
constexpr const char* lambertian_2d_name(lambertian_2d l) { return l == lambertian_2d::paper ? "paper" : "symmetric"; }

struct rgb {
  double r = 0, g = 0, b = 0;
  double operator[](int c) const { return c == 0 ? r : c == 1 ? g : b; }
  double& operator[](int c) { return c == 0 ? r : c == 1 ? g : b; }
  bool operator==(const rgb&) const = default;
};

using vec3 = std::array<double, 3>;

// The 2D compass, the authors' convention for both directions and normals: index i = 0 N, 1 NE,
// 2 E, ..., 7 NW as a step of one cell (x = column, y = row growing downwards, so N is -y).
inline constexpr int compass_2d[8][2] = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}};

inline double dot(const vec3& a, const vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const vec3& a) { return std::sqrt(dot(a, a)); }
// The unit vector along a: any finite nonzero a, however large or small its components.
template <int = 0>
inline vec3 normalized(const vec3& a) {
  const double l = norm(a);
  // Squares of components between 1e-150 and 1e150 neither overflow nor underflow.
  if (l > 1e-150 && l < 1e150) return {a[0] / l, a[1] / l, a[2] / l};
  const double m = std::max({std::abs(a[0]), std::abs(a[1]), std::abs(a[2])});
  if (!(m > 0) || !std::isfinite(m)) throw std::invalid_argument("normalized: zero or non-finite vector");
  const vec3 s{a[0] / m, a[1] / m, a[2] / m};  // largest component exactly +-1: norm(s) in [1, sqrt 3]
  const double ls = norm(s);
  return {s[0] / ls, s[1] / ls, s[2] / ls};
}

// The unit vector of compass index i (0..7): a 2D normal or direction.
template <int = 0>
inline vec3 compass_vector_2d(int i) {
  return normalized({double(compass_2d[i][0]), double(compass_2d[i][1]), 0.0});
}

// The glossy lobe parameter's range (glossy_coin in walk/coins.hpp): up to 4 the lobe's mean
// cosine to the mirror direction falls monotonically for every direction set of 14 to 64
// directions (the discrete wave spreads; further on it partly comes back).
inline constexpr double glossy_lobe_max = 4.0;

struct voxel {
  material kind = material::air;
  // 2D: the normal as one of the 8 direction indices (0 N, 1 NE, ..., 7 NW); -1 for none.
  int normal_index = -1;
  // 3D (and 2D, derived from the index): the unit outward normal.
  vec3 normal{0, 0, 0};
  rgb reflectance{1, 1, 1};  // air transmits everything (the paper's "A" = (1,1,1))
  rgb emission{0, 0, 0};
  // Glossy voxels: the lobe parameter tau of glossy_coin (walk/coins.hpp), in [0,
  // glossy_lobe_max]; 0 for every other kind.
  double lobe = 0;
  // Medium voxels (participating media, medium_coin in walk/coins.hpp): the probability, in
  // [0, 1], that a walker crossing the voxel scatters there (isotropically); 0 for every other
  // kind. A medium has no normal; its reflectance is the fraction of light a walker keeps per
  // visit, scatter or not (absorption), sampled like a surface's rho.
  double density = 0;
  bool operator==(const voxel&) const = default;
};

// scene_view: the camera a 3D scene file may carry, in voxel units (voxel (x, y, z) fills
// [x, x+1) x [y, y+1) x [z, z+1)); the renderer turns it into a pinhole camera of any image size.
struct scene_view {
  vec3 position{0, 0, 0};
  vec3 look_at{0, 0, 1};
  vec3 up{0, 1, 0};
  double vertical_fov_degrees = 39.3;
  bool operator==(const scene_view&) const = default;
};

class scene {
 public:
  scene() = default;
  // An all-air scene of size^dims voxels; size must be a power of two >= 2, dims 2 or 3.
  template <int = 0>
  scene(std::string name, unsigned dims, unsigned size) : name_(std::move(name)), dims_(dims), size_(size) {
    if (dims != 2 && dims != 3)
      throw std::invalid_argument("scene: dims must be 2 or 3, got " + std::to_string(dims));
    if (size < 2 || (size & (size - 1)) != 0)
      throw std::invalid_argument("scene: size must be a power of two >= 2 (N = 2^P), got " + std::to_string(size));
    if (size > (1u << 12)) throw std::invalid_argument("scene: size " + std::to_string(size) + " is larger than 4096");
    bits_ = 0;
    while ((1u << bits_) < size) ++bits_;
    std::size_t count = 1;
    for (unsigned d = 0; d < dims; ++d) count *= size;
    voxels_.assign(count, voxel{});
  }

  const std::string& name() const { return name_; }
  void set_name(std::string n) { name_ = std::move(n); }
  unsigned dims() const { return dims_; }
  unsigned size() const { return size_; }
  // view(): the scene's own camera, if its file gave one (3D only).
  const std::optional<scene_view>& view() const { return view_; }
  void set_view(const scene_view& v) { view_ = v; }
  // march(): the march its file asked for ('march voxel|surface'), if any.
  const std::optional<march_mode>& march() const { return march_; }
  void set_march(march_mode m) { march_ = m; }
  // lambertian_coin(): the 2D Lambertian coin its file asked for ('lambertian paper|symmetric').
  lambertian_2d lambertian_coin() const { return lambertian_; }
  void set_lambertian_coin(lambertian_2d l) { lambertian_ = l; }
  unsigned position_bits() const { return bits_; }  // P, with N = 2^P
  std::size_t voxel_count() const { return voxels_.size(); }

  template <int = 0>
  std::size_t index(unsigned x, unsigned y, unsigned z = 0) const {
    if (x >= size_ || y >= size_ || z >= (dims_ == 3 ? size_ : 1u))
      throw std::out_of_range(voxel_name(x, y, z) + " is outside the " + std::to_string(size_) + "^" +
                              std::to_string(dims_) + " grid");
    return x + static_cast<std::size_t>(size_) * (y + static_cast<std::size_t>(size_) * z);
  }
  template <int = 0>
  std::array<unsigned, 3> coords(std::size_t i) const {
    return {static_cast<unsigned>(i % size_), static_cast<unsigned>((i / size_) % size_),
            static_cast<unsigned>(i / (static_cast<std::size_t>(size_) * size_))};
  }
  voxel& at(unsigned x, unsigned y, unsigned z = 0) { return voxels_[index(x, y, z)]; }
  const voxel& at(unsigned x, unsigned y, unsigned z = 0) const { return voxels_[index(x, y, z)]; }
  voxel& operator[](std::size_t i) { return voxels_[i]; }
  const voxel& operator[](std::size_t i) const { return voxels_[i]; }
  const std::vector<voxel>& voxels() const { return voxels_; }

  template <int = 0>
  bool has(material m) const {
    for (const voxel& v : voxels_)
      if (v.kind == m) return true;
    return false;
  }
  // Channels c1 and c2 carry the same reflectance and emission everywhere (so one circuit
  // serves both).
  template <int = 0>
  bool same_channels(int c1, int c2) const {
    for (const voxel& v : voxels_)
      if (v.reflectance[c1] != v.reflectance[c2] || v.emission[c1] != v.emission[c2]) return false;
    return true;
  }
  // For each channel, the first channel with the same data (grey scenes: {0, 0, 0}), so results
  // are computed once per distinct channel.
  template <int = 0>
  std::array<int, 3> channel_sources() const {
    std::array<int, 3> source{0, 1, 2};
    for (int c = 1; c < 3; ++c)
      for (int e = 0; e < c; ++e)
        if (source[static_cast<std::size_t>(e)] == e && same_channels(c, e)) {
          source[static_cast<std::size_t>(c)] = e;
          break;
        }
    return source;
  }
  // The factor emission is divided by before amplitude encoding: max(1, largest emission).
  template <int = 0>
  double emission_scale(int channel) const {
    double m = 1.0;
    for (const voxel& v : voxels_) m = std::max(m, v.emission[channel]);
    return m;
  }

  // Throws, naming the voxel and the value, if any voxel is out of range. The checks run on every
  // voxel and the message is built only for the one that fails: building the voxel's name for each
  // voxel cost 0.93 s on an empty 256^3 scene (0.06 s without; AMD EPYC VM, 2026-12-04).
  template <int = 0>
  void validate() const;

 private:
  // "scene 'NAME': voxel (x, y)" or "(x, y, z)": how errors name a voxel.
  template <int = 0>
  std::string voxel_name(unsigned x, unsigned y, unsigned z) const {
    return "scene '" + name_ + "': voxel (" + std::to_string(x) + ", " + std::to_string(y) +
           (dims_ == 3 ? ", " + std::to_string(z) : std::string()) + ")";
  }
  template <int = 0>
  [[noreturn]] void invalid_voxel(std::size_t i, const std::string& what) const {
    const auto c = coords(i);
    throw std::invalid_argument(voxel_name(c[0], c[1], c[2]) + ": " + what);
  }

  std::string name_;
  unsigned dims_ = 2, size_ = 2, bits_ = 1;
  std::vector<voxel> voxels_;
  std::optional<scene_view> view_;
  std::optional<march_mode> march_;
  lambertian_2d lambertian_ = lambertian_2d::paper;
};

template <int Deferred>
void scene::validate() const {
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    const voxel& v = voxels_[i];
    for (int ch = 0; ch < 3; ++ch) {
      const double r = v.reflectance[ch], e = v.emission[ch];
      if (!(r >= 0.0 && r <= 1.0))
        invalid_voxel(i, "reflectance " + std::to_string(r) + " outside [0, 1] in channel " + "RGB"[ch]);
      if (!(e >= 0.0) || !std::isfinite(e))
        invalid_voxel(i, "emission " + std::to_string(e) + " must be finite and >= 0 in channel " + "RGB"[ch]);
    }
    if (v.kind == material::glossy ? !(v.lobe >= 0.0 && v.lobe <= glossy_lobe_max) : v.lobe != 0.0)
      invalid_voxel(i, "lobe " + std::to_string(v.lobe) +
                           (v.kind == material::glossy
                                ? " outside [0, " + std::to_string(static_cast<int>(glossy_lobe_max)) + "] (the glossy lobe parameter)"
                                : " on a " + std::string(material_name(v.kind)) + " voxel (only glossy voxels have a lobe)"));
    if (v.kind == material::medium ? !(v.density >= 0.0 && v.density <= 1.0) : v.density != 0.0)
      invalid_voxel(i, "density " + std::to_string(v.density) +
                           (v.kind == material::medium
                                ? " outside [0, 1] (the medium's scattering probability)"
                                : " on a voxel of kind " + std::string(material_name(v.kind)) + " (only medium voxels have a density)"));
    if (v.kind == material::air || v.kind == material::medium) continue;  // no normal
    if (dims_ == 2 && (v.normal_index < 0 || v.normal_index > 7))
      invalid_voxel(i, "a " + std::string(material_name(v.kind)) + " voxel needs a normal index 0..7, got " +
                           std::to_string(v.normal_index));
    if (dims_ == 3 && !(std::abs(norm(v.normal) - 1.0) < 1e-9))
      invalid_voxel(i, "a " + std::string(material_name(v.kind)) + " voxel needs a unit normal");
  }
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_SCENE_INSTANCES(PREFIX) \
  PREFIX void scene::validate<0>() const;
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_SCENE_INSTANCES(extern template)
}  // namespace qrm
#endif
