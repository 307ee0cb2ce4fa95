#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "tessera/math/vec.hpp"

namespace tessera {

// Spawn-point offset by Wächter and Binder ("A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6): move the hit point off the surface by a
// fixed number of ulps along the geometric normal, which scales with the magnitude of the
// coordinates instead of using an epsilon that fails far from the origin.
namespace detail {
TESSERA_HD TESSERA_INLINE float int_as_float(std::int32_t i) {
  float f;
  std::memcpy(&f, &i, sizeof f);
  return f;
}
TESSERA_HD TESSERA_INLINE std::int32_t float_as_int(float f) {
  std::int32_t i;
  std::memcpy(&i, &f, sizeof i);
  return i;
}
}  // namespace detail

// `normal` must point to the side the new ray leaves towards.
TESSERA_HD TESSERA_INLINE vec3 offset_ray_origin(const vec3& p, const vec3& normal) {
  constexpr float kOrigin = 1.0f / 32.0f;
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  vec3 result;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int32_t of_i = static_cast<std::int32_t>(kIntScale * normal[axis]);
    const float moved =
        detail::int_as_float(detail::float_as_int(p[axis]) + (p[axis] < 0.0f ? -of_i : of_i));
    result[axis] = std::fabs(p[axis]) < kOrigin ? p[axis] + kFloatScale * normal[axis] : moved;
  }
  return result;
}

}  // namespace tessera
