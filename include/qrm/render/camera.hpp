// qrm/render/camera.hpp: a pinhole camera in voxel coordinates.
//
// Pixel (px, py) counts from the left and from the top row. The image plane spans the vertical
// field of view; right = forward x up, so with +y up and the camera looking along +z, +x is on
// the image's left (the Cornell box data's convention: its red wall at large x is seen on the
// left).
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "detail/vec3.hpp"
#include "../support/random.hpp"
#include "../walk/scene.hpp"

namespace qrm::render {

struct camera_ray {
  vec3 origin{0, 0, 0};
  vec3 direction{0, 0, 1};  // unit length
};

class camera {
 public:
  // camera(position, look_at, up, vertical_fov_degrees, width, height)
  template <int = 0>
  camera(const vec3& position, const vec3& look_at, const vec3& up, double vertical_fov_degrees, unsigned width,
         unsigned height)
      : position_(position), vfov_(vertical_fov_degrees), width_(width), height_(height) {
    if (!qrm::detail::vec_finite(position) || !qrm::detail::vec_finite(look_at) || !qrm::detail::vec_finite(up))
      throw std::invalid_argument("camera: position, look_at and up must be finite");
    if (width == 0 || height == 0)
      throw std::invalid_argument("camera: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                  " must be positive");
    if (!(vertical_fov_degrees > 0.0 && vertical_fov_degrees < 180.0))
      throw std::invalid_argument("camera: vertical field of view " + std::to_string(vertical_fov_degrees) +
                                  " degrees must be in (0, 180)");
    const vec3 f = qrm::detail::vec_sub(look_at, position);
    if (!(norm(f) > 0)) throw std::invalid_argument("camera: look_at equals the position");
    forward_ = normalized(f);
    const vec3 r = qrm::detail::vec_cross(forward_, up);
    if (!(norm(r) > 1e-9 * norm(up)))
      throw std::invalid_argument("camera: up is zero or parallel to the view direction");
    right_ = normalized(r);
    up_ = qrm::detail::vec_cross(right_, forward_);
    half_height_ = std::tan(vertical_fov_degrees * std::numbers::pi / 360.0);
    half_width_ = half_height_ * static_cast<double>(width) / static_cast<double>(height);
  }

  unsigned width() const { return width_; }
  unsigned height() const { return height_; }
  const vec3& position() const { return position_; }
  const vec3& forward() const { return forward_; }
  const vec3& right() const { return right_; }
  const vec3& up() const { return up_; }
  double vertical_fov_degrees() const { return vfov_; }

  // ray(px, py): through the centre of pixel (px, py).
  camera_ray ray(unsigned px, unsigned py) const { return film_ray(px, py, 0.5, 0.5); }
  // ray(px, py, g): through a uniformly random point of pixel (px, py) (supersampling).
  template <int = 0>
  camera_ray ray(unsigned px, unsigned py, rng& g) const {
    const double fx = g.uniform();
    const double fy = g.uniform();
    return film_ray(px, py, fx, fy);
  }
  // film_ray(px, py, fx, fy): through the point (fx, fy) in [0, 1)^2 of pixel (px, py).
  template <int = 0>
  camera_ray film_ray(unsigned px, unsigned py, double fx, double fy) const {
    if (px >= width_ || py >= height_)
      throw std::out_of_range("camera: pixel (" + std::to_string(px) + ", " + std::to_string(py) + ") is outside the " +
                              std::to_string(width_) + "x" + std::to_string(height_) + " image");
    const double sx = ((static_cast<double>(px) + fx) / static_cast<double>(width_) * 2.0 - 1.0) * half_width_;
    const double sy = (1.0 - (static_cast<double>(py) + fy) / static_cast<double>(height_) * 2.0) * half_height_;
    const vec3 d = qrm::detail::vec_add_scaled(qrm::detail::vec_add_scaled(forward_, right_, sx), up_, sy);
    return {position_, normalized(d)};
  }

 private:
  vec3 position_, forward_{0, 0, 1}, right_{1, 0, 0}, up_{0, 1, 0};
  double vfov_ = 0, half_width_ = 0, half_height_ = 0;
  unsigned width_ = 0, height_ = 0;
};

}  // namespace qrm::render
