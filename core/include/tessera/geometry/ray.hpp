#pragma once
#include <cstdint>
#include <limits>

#include "tessera/math/vec.hpp"

namespace tessera {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr std::uint32_t kInvalidIndex = 0xffffffffU;

struct Ray {
  vec3 origin{0.0f};
  vec3 direction{0.0f, 0.0f, 1.0f};
  float t_min = 0.0f;
  float t_max = kInfinity;
};

// What traversal records about the closest hit so far: enough to shade it later.
// Shading data (normal, uv) is derived afterwards from (primitive, u, v) so the inner loop
// carries only four words.
struct HitRecord {
  float t = kInfinity;
  float u = 0.0f;  // shape parameters: barycentrics for triangles, uv for quads/spheres
  float v = 0.0f;
  std::uint32_t primitive = kInvalidIndex;  // tagged primitive reference, see PrimitiveRef

  TESSERA_HD bool valid() const { return primitive != kInvalidIndex; }
};

// Ray with precomputed reciprocal direction for slab tests. Zero components give infinite
// reciprocals on purpose (+0.0 gives +inf, -0.0 gives -inf); intersect_aabb handles the
// 0 * inf = NaN of an origin lying on a slab plane.
struct TraversalRay {
  vec3 origin;
  vec3 inv_direction;

  TESSERA_HD explicit TraversalRay(const Ray& ray)
      : origin(ray.origin),
        inv_direction(1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z) {}
};

}  // namespace tessera
