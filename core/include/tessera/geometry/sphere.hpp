#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

struct Sphere {
  vec3 center;
  float radius;
  std::uint32_t material;
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Sphere& s) {
  return conservative_aabb(dvec3(s.center) - dvec3(static_cast<double>(s.radius)),
                           dvec3(s.center) + dvec3(static_cast<double>(s.radius)));
}

namespace detail {

// Roots of |o + t d - c|^2 = r^2 without catastrophic cancellation, ascending; returns 0
// or 2. After Haines et al., "Precision Improvements for Ray/Sphere Intersection" (Ray
// Tracing Gems ch. 7): the discriminant is r^2 minus the squared distance from the centre
// to the ray line (never b^2 - 4ac of two huge nearly equal terms), the larger-magnitude
// root is q / a with q = -(b + sign(b) sqrt(disc)) / 2, the other c / q. Evaluated in double
// from the float inputs: in float, the distance to the line of an origin 1e6 radii away is
// itself off by ~1e6 * 6e-8 radii, which flips hit/miss for rays within 6% of the
// silhouette; in double that band is below 1e-9.
TESSERA_HD TESSERA_INLINE int sphere_roots(const Sphere& s, const Ray& ray, double roots[2],
                                           double& margin) {
  const dvec3 d(ray.direction);
  const dvec3 f = dvec3(ray.origin) - dvec3(s.center);
  const double a = glm::dot(d, d);
  if (!(a > 0.0) || !std::isfinite(a)) return 0;
  const double r = s.radius;
  margin = origin_margin(max_abs(dvec3(ray.origin)) + r, std::sqrt(a));
  const double b_half = -glm::dot(f, d);  // b = -2 b_half
  const dvec3 perpendicular = f + (b_half / a) * d;
  const double distance = glm::length(perpendicular);
  const double reduced_disc = (r - distance) * (r + distance);  // disc / (4 a)
  if (!(reduced_disc >= 0.0)) return 0;
  const double f_length = glm::length(f);
  const double c = (f_length - r) * (f_length + r);
  const double root = std::sqrt(a * reduced_disc);
  const double q = b_half + (b_half >= 0.0 ? root : -root);  // -(b + sign(b) sqrt(disc)) / 2
  double t0 = q != 0.0 ? c / q : 0.0;
  double t1 = q / a;
  if (t0 > t1) {
    const double tmp = t0;
    t0 = t1;
    t1 = tmp;
  }
  roots[0] = t0;
  roots[1] = t1;
  return 2;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Sphere& s, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  double roots[2];
  double margin = 0.0;
  const int n = detail::sphere_roots(s, ray, roots, margin);
  for (int i = 0; i < n; ++i) {
    float t;
    if (accept_root(roots[i], ray.t_min, t_max, margin, t)) {
      hit.t = t;
      hit.u = 0.0f;
      hit.v = 0.0f;
      hit.primitive = primitive;
      return true;
    }
  }
  return false;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Sphere& s, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  double roots[2];
  double margin = 0.0;
  const int n = detail::sphere_roots(s, ray, roots, margin);
  int count = 0;
  for (int i = 0; i < n && count < max_hits; ++i) {
    float t;
    if (accept_root(roots[i], ray.t_min, t_max, margin, t)) {
      hits[count].t = t;
      hits[count].u = 0.0f;
      hits[count].v = 0.0f;
      hits[count].primitive = primitive;
      ++count;
    }
  }
  return count;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Sphere& s, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  // The hit point from the double root nearest to the float t: far from the origin the
  // float t alone places the point off the surface by many ulps.
  double roots[2];
  double margin = 0.0;
  double t = hit.t;
  if (detail::sphere_roots(s, ray, roots, margin) == 2)
    t = std::fabs(roots[0] - hit.t) <= std::fabs(roots[1] - hit.t) ? roots[0] : roots[1];
  const dvec3 local = dvec3(ray.origin) + t * dvec3(ray.direction) - dvec3(s.center);
  const double length = glm::length(local);
  const dvec3 outward_d = length > 0.0 ? local / length : dvec3(0.0, 1.0, 0.0);
  const vec3 outward(outward_d);
  si.position = vec3(dvec3(s.center) + static_cast<double>(s.radius) * outward_d);
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
