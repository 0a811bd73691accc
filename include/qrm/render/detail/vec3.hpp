// qrm/render/detail/vec3.hpp: the few 3-vector operations the renderer needs (qrm::vec3 is a plain
// std::array<double, 3>; dot, norm and normalized live in scene.hpp).
#pragma once

#include "../../walk/scene.hpp"

namespace qrm::detail {

template <int = 0>
inline vec3 vec_add(const vec3& a, const vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <int = 0>
inline vec3 vec_sub(const vec3& a, const vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <int = 0>
inline vec3 vec_scale(const vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
// a + s * b
template <int = 0>
inline vec3 vec_add_scaled(const vec3& a, const vec3& b, double s) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}
template <int = 0>
inline vec3 vec_cross(const vec3& a, const vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <int = 0>
inline bool vec_finite(const vec3& a) {
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

}  // namespace qrm::detail
