#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/fast_trig.hpp"

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

// Roots of |o + t d - c|^2 = r^2 without catastrophic cancellation. After Haines et al.,
// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems ch. 7): the
// discriminant is r^2 minus the squared distance from the centre to the ray line (never
// b^2 - 4ac of two huge nearly equal terms), the larger-magnitude root is q / a with
// q = -(b + sign(b) sqrt(disc)) / 2 and the other is c / q, with c = |f|^2 - r^2.
// Evaluated in double from the float inputs: in float the distance to the line of an
// origin 1e6 radii away is itself uncertain by ~1e6 * 6e-8 radii, which flips hit or miss
// for rays within 6% of the silhouette; in double that band is below 1e-9.
// Squared lengths, not lengths: a miss then costs no square root and a hit one (double
// square roots are among the slowest instructions, and shadow rays test every sphere whose
// box they cross). The origin's distance to the surface, a root of its own, is formed only
// when the origin may lie on the surface, which |c| = ||f| - r| (|f| + r) bounds.
TESSERA_HD TESSERA_FORCE_INLINE HitCandidates<2> sphere_candidates(const Sphere& s,
                                                                   const PreciseRay& ray) {
  HitCandidates<2> out;
  const LocalRay local{ray.origin - dvec3(s.center), ray.direction};
  const dvec3& d = local.direction;
  const dvec3& f = local.origin;
  const double a = glm::dot(d, d);
  if (!(a > 0.0) || !std::isfinite(a)) return out;
  const double r = s.radius;
  // A zero radius is a point, not a surface: a ray through the centre would otherwise find
  // the double root there (and a made-up normal).
  if (!(std::fabs(r) > 0.0)) return out;
  const double r2 = r * r;
  const double b_half = -glm::dot(f, d);  // b = -2 b_half
  const dvec3 perpendicular = f + (b_half / a) * d;
  const double reduced_disc = r2 - glm::dot(perpendicular, perpendicular);  // disc / (4 a)
  if (!(reduced_disc >= 0.0)) return out;
  const double f2 = glm::dot(f, f);
  const double c = f2 - r2;
  const double root = std::sqrt(a * reduced_disc);
  const double q = b_half + (b_half >= 0.0 ? root : -root);  // -(b + sign(b) sqrt(disc)) / 2
  const double t_far = q / a;
  const double t_near = q != 0.0 ? c / q : 0.0;
  const double band = ray.origin_error + 1e-15 * r;
  // ||f| - r| <= band implies |c| <= band (2 |r| + band); the last term covers c's rounding.
  const bool may_start_on_surface =
      std::fabs(c) <= band * (2.0 * std::fabs(r) + band) * (1.0 + 1e-6) + 1e-15 * r2;
  const double origin_distance = may_start_on_surface ? std::sqrt(f2) - r : 0.0;
  const auto signed_distance = [r](const dvec3& p) { return glm::length(p) - r; };
  const double roots[2] = {glm::min(t_near, t_far), glm::max(t_near, t_far)};
  for (int i = 0; i < 2; ++i)
    if (!may_start_on_surface ||
        !is_start_surface_root(signed_distance, origin_distance, local, roots[i], band))
      out.add(roots[i], 0);
  return out;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Sphere& s, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::sphere_candidates(s, ray).closest(ray.t_min, t_max, hit, primitive);
}

TESSERA_HD TESSERA_INLINE bool intersect(const Sphere& s, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(s, make_precise_ray(ray), t_max, hit, primitive);
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Sphere& s, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::sphere_candidates(s, ray).all(ray.t_min, t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Sphere& s, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(s, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Sphere& s, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  // The point from the double root the float t came from (kept with the hit: root_of_hit):
  // far from the origin the float t alone places the point off the surface by many ulps.
  const double t = root_of_hit(hit);
  const dvec3 local = ray.origin + t * ray.direction - dvec3(s.center);
  const double length = glm::length(local);
  const dvec3 outward_d = length > 0.0 ? local / length : dvec3(0.0, 1.0, 0.0);
  const vec3 outward(outward_d);
  si.position = vec3(dvec3(s.center) + static_cast<double>(s.radius) * outward_d);
  set_face_normal(si, vec3(ray.direction), outward);
  // Inline arctangents (a few float ulps) instead of libm's out-of-line acosf and atan2f:
  // every sphere hit forms its uv, textured or not. theta from the arctangent, not acos(-y),
  // also keeps its precision at the poles.
  const float theta =
      fast_atan2(std::sqrt(outward.x * outward.x + outward.z * outward.z), -outward.y);
  const float phi = fast_atan2(-outward.z, outward.x) + kPi;
  si.uv = vec2(phi / (2.0f * kPi), theta / kPi);
  si.material = s.material;
  return si;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Sphere& s, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(s, make_precise_ray(ray), hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Sphere& s) {
  return 4.0f * kPi * s.radius * s.radius;
}

}  // namespace tessera
