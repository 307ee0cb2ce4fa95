#pragma once
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

// Everything shading needs about a hit, computed once from a HitRecord.
struct SurfaceInteraction {
  vec3 position;
  vec3 geometric_normal;  // unit, faces against the incoming ray
  vec3 shading_normal;    // unit, same hemisphere as geometric_normal
  vec2 uv;
  std::uint32_t material = 0;
  bool front_face = true;  // true when the ray hit the side the geometric normal points to
  // A bound on each coordinate's absolute error in `position` (position_error_bound, for the
  // shapes that compute their hit point in float from their own coordinates: triangles and
  // quads, and instances of them); negative where none is known. offset_ray_origin moves
  // spawned rays past it.
  float position_error = -1.0f;
};

// Orients the normal against the ray and records which side was hit.
TESSERA_HD TESSERA_INLINE void set_face_normal(SurfaceInteraction& si, const vec3& ray_direction,
                                               const vec3& outward_normal) {
  si.front_face = glm::dot(ray_direction, outward_normal) < 0.0f;
  si.geometric_normal = si.front_face ? outward_normal : -outward_normal;
  si.shading_normal = si.geometric_normal;
}

}  // namespace tessera
