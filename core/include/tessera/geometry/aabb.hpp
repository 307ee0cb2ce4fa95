#pragma once
#include <cmath>

#include "tessera/geometry/ray.hpp"

namespace tessera {

struct Aabb {
  vec3 lower{kInfinity};
  vec3 upper{-kInfinity};

  TESSERA_HD void extend(const vec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  TESSERA_HD void extend(const Aabb& b) {
    lower = glm::min(lower, b.lower);
    upper = glm::max(upper, b.upper);
  }
  TESSERA_HD bool empty() const {
    return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z;
  }
  TESSERA_HD vec3 centroid() const { return 0.5f * (lower + upper); }
  TESSERA_HD vec3 extent() const { return upper - lower; }
  TESSERA_HD float surface_area() const {
    if (empty()) return 0.0f;
    const vec3 e = extent();
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  TESSERA_HD int largest_axis() const {
    const vec3 e = extent();
    return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
  }
};

// Slab test. The near plane of each axis is chosen by the sign of the reciprocal, so a
// -0.0 component (reciprocal -inf) picks the upper plane, as a tiny negative one would.
// A ray parallel to an axis whose origin lies exactly on one of that axis' planes gets
// 0 * inf = NaN for that plane; the comparisons below drop NaN operands, so the plane does
// not limit the interval and the ray counts as inside the slab, boundary included (it can
// still hit a triangle lying in that plane's edge). Every other product is finite or a
// correctly signed infinity.
TESSERA_HD TESSERA_FORCE_INLINE bool intersect_aabb(const vec3& lower, const vec3& upper,
                                              const TraversalRay& ray, float t_min, float t_max,
                                              float& t_entry) {
  for (int axis = 0; axis < 3; ++axis) {
    const bool negative = ray.inv_direction[axis] < 0.0f;
    const float t_near =
        ((negative ? upper[axis] : lower[axis]) - ray.origin[axis]) * ray.inv_direction[axis];
    const float t_far =
        ((negative ? lower[axis] : upper[axis]) - ray.origin[axis]) * ray.inv_direction[axis];
    t_min = t_near > t_min ? t_near : t_min;
    t_max = t_far < t_max ? t_far : t_max;
  }
  t_entry = t_min;
  // Robust BVH traversal (Ize 2013): widen the far end by 2 ulps, so rounding neither drops
  // flat boxes nor boxes entered at the distance of the hit found so far.
  return t_min <= t_max * (1.0f + 2.0f * 1.1920929e-07f);
}

}  // namespace tessera
