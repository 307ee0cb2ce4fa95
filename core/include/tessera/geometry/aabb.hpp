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

// Slab test. With an infinite reciprocal and an origin exactly on a slab plane the product
// 0 * inf is NaN; min/max written with comparisons drop the NaN operand, so such rays are
// treated as inside the slab rather than poisoning the interval.
TESSERA_HD TESSERA_INLINE bool intersect_aabb(const vec3& lower, const vec3& upper,
                                              const TraversalRay& ray, float t_min, float t_max,
                                              float& t_entry) {
  for (int axis = 0; axis < 3; ++axis) {
    float t0 = (lower[axis] - ray.origin[axis]) * ray.inv_direction[axis];
    float t1 = (upper[axis] - ray.origin[axis]) * ray.inv_direction[axis];
    if (t0 > t1) {
      const float tmp = t0;
      t0 = t1;
      t1 = tmp;
    }
    // Robust BVH traversal (Ize 2013): widen the far bound by 2 ulps-ish.
    t1 *= 1.0f + 2.0f * 1.1920929e-07f;
    t_min = t0 > t_min ? t0 : t_min;
    t_max = t1 < t_max ? t1 : t_max;
  }
  t_entry = t_min;
  return t_min <= t_max;
}

}  // namespace tessera
