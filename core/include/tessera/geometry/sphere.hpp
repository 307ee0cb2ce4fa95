#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

struct Sphere {
  vec3 center;
  float radius;
  std::uint32_t material;
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Sphere& s) {
  return Aabb{s.center - vec3(s.radius), s.center + vec3(s.radius)};
}

// Roots of |o + t d - c|^2 = r^2 without catastrophic cancellation (Haines et al.,
// "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7): the
// discriminant is formed from the squared distance of the centre to the ray line, and the
// smaller-magnitude root comes from c/q rather than a difference of near-equal terms.
TESSERA_HD TESSERA_INLINE bool intersect(const Sphere& s, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  const vec3 f = ray.origin - s.center;
  const float a = glm::dot(ray.direction, ray.direction);
  const float b_half = -glm::dot(f, ray.direction);
  const vec3 perpendicular = f + (b_half / a) * ray.direction;
  const float r2 = s.radius * s.radius;
  const float discriminant = a * (r2 - glm::dot(perpendicular, perpendicular));
  if (!(discriminant >= 0.0f)) return false;
  const float c = glm::dot(f, f) - r2;
  const float sqrt_d = std::sqrt(discriminant);
  const float q = b_half + (b_half >= 0.0f ? sqrt_d : -sqrt_d);
  float t0 = q != 0.0f ? c / q : 0.0f;
  float t1 = q / a;
  if (t0 > t1) {
    const float tmp = t0;
    t0 = t1;
    t1 = tmp;
  }
  float t = t0;
  if (!(t > ray.t_min && t < t_max)) {
    t = t1;
    if (!(t > ray.t_min && t < t_max)) return false;
  }
  hit.t = t;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Sphere& s, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  // Reproject onto the surface: the ray-evaluated point can be off by many ulps far away.
  const vec3 p = ray.origin + hit.t * ray.direction;
  vec3 outward = (p - s.center) / s.radius;
  outward = glm::normalize(outward);
  si.position = s.center + s.radius * outward;
  set_face_normal(si, ray.direction, outward);
  const float theta = std::acos(glm::clamp(-outward.y, -1.0f, 1.0f));
  const float phi = std::atan2(-outward.z, outward.x) + kPi;
  si.uv = vec2(phi / (2.0f * kPi), theta / kPi);
  si.material = s.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Sphere& s) {
  return 4.0f * kPi * s.radius * s.radius;
}

}  // namespace tessera
