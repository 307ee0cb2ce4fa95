#pragma once
// RayON's displaced_sphere: a sphere whose shading normal follows golf-ball dimples (bump
// mapping; the silhouette stays the sphere's, as in RayON). 150 dimples centred on a
// spherical Fibonacci spiral, each of angular radius 0.24 and depth profile
// 0.35 cos(pi/2 * angle / 0.24); the normal tilts by `strength` (RayON's
// displacement_scale, 0.2) times the depth's gradient, found by finite differences 0.015
// apart as RayON's renderer does, faded out towards grazing views and tilted at most 0.4.
// RayON also pushes the hit point outwards by up to 0.35 radius, off the sphere it
// intersected; Tessera keeps the point on the sphere, so shadows and bounces start where
// the ray met the surface.
#include <cmath>
#include <cstdint>

#include "tessera/math/vec.hpp"
#include "tessera/render/pattern.hpp"

namespace tessera {

inline constexpr std::uint32_t kGolfDimpleCount = 150;
inline constexpr float kGolfDimpleRadius = 0.24f;
inline constexpr float kGolfDimpleDepth = 0.35f;

// The dimple height (<= 0) at unit direction `d` from the centre.
TESSERA_HD inline float golf_dimple_height(const vec3& d) {
  float best = -1.0f;
  for (std::uint32_t i = 0; i < kGolfDimpleCount; ++i)
    best = glm::max(best, glm::dot(d, spherical_fibonacci_point(i, kGolfDimpleCount)));
  const float angle = std::acos(glm::clamp(best, -1.0f, 1.0f));
  if (angle >= kGolfDimpleRadius) return 0.0f;
  return -kGolfDimpleDepth * std::cos(angle / kGolfDimpleRadius * kPi * 0.5f);
}

// The dimpled shading normal. `outward`: unit, from the centre through the hit, in the
// frame the dimples are laid out in; `to_eye`: unit, towards where the ray came from.
TESSERA_HD inline vec3 golf_dimpled_normal(const vec3& outward, const vec3& to_eye,
                                           float strength) {
  const float d0 = golf_dimple_height(outward);
  if (d0 >= -0.001f) return outward;
  const vec3 helper = std::fabs(outward.x) > 0.8f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
  const vec3 t1 = glm::normalize(glm::cross(helper, outward));
  const vec3 t2 = glm::cross(outward, t1);
  constexpr float h = 0.015f;
  const float d1 = golf_dimple_height(glm::normalize(outward + h * t1));
  const float d2 = golf_dimple_height(glm::normalize(outward + h * t2));
  vec3 tilt = -strength * (((d1 - d0) / h) * t1 + ((d2 - d0) / h) * t2);
  const float facing = glm::max(0.0f, glm::dot(outward, to_eye));
  const float fade = glm::clamp((facing - 0.1f) / 0.3f, 0.0f, 1.0f);
  tilt *= fade * fade * (3.0f - 2.0f * fade);  // smoothstep(0.1, 0.4, facing)
  const float length = glm::length(tilt);
  if (length > 0.4f) tilt *= 0.4f / length;
  const vec3 n = glm::normalize(outward + tilt);
  if (!(n.x == n.x && n.y == n.y && n.z == n.z)) return outward;
  return glm::dot(n, outward) < 0.0f ? -n : n;
}

}  // namespace tessera
