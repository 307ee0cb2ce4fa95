#pragma once
#include <cmath>

#include "tessera/geometry/ray.hpp"

namespace tessera {

// Whether a ray may be traced: finite origin, finite non-zero direction and an interval
// with t_min <= t_max (t_max may be infinite). Intersectors return "no hit" without NaN
// for a zero direction, but such a ray has no meaning, so ray and scene builders reject it.
TESSERA_HD TESSERA_INLINE bool is_valid_ray(const Ray& ray) {
  const vec3 o = ray.origin, d = ray.direction;
  if (!(std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z))) return false;
  if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z))) return false;
  if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) return false;
  return !std::isnan(ray.t_min) && !std::isnan(ray.t_max) && ray.t_min <= ray.t_max;
}

}  // namespace tessera
