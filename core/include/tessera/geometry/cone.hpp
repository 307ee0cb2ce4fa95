#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// Finite cone (one nappe) along the unit `axis` from `base`: radius base_radius at the
// base, top_radius at base + height * axis (0 for a pointed cone, > 0 for a frustum),
// optionally closed by disks. Because both radii are >= 0 and hits are kept only for
// 0 <= height fraction <= 1, the mirrored nappe beyond the apex is never hit.
// uv and HitRecord::v as for Cylinder.
struct Cone {
  vec3 base;
  vec3 axis;  // unit
  float base_radius;
  float top_radius;
  float height;
  std::uint32_t capped;
  std::uint32_t material;
  // AxisFrame::from_axis(axis), computed once by make (see Cylinder::frame).
  AxisFrame frame;

  static Cone make(const vec3& base, const vec3& axis, float base_radius, float top_radius,
                   float height, bool capped, std::uint32_t material) {
    const vec3 unit = glm::normalize(axis);
    return Cone{base,        unit,
                base_radius, top_radius,
                height,      capped ? 1u : 0u,
                material,    AxisFrame::from_axis(unit)};
  }
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Cone& c) {
  const dvec3 w(c.axis);
  const dvec3 b(c.base);
  const dvec3 top = b + w * static_cast<double>(c.height);
  const dvec3 eb = circle_half_extent(w, c.base_radius);
  const dvec3 et = circle_half_extent(w, c.top_radius);
  return conservative_aabb(glm::min(b - eb, top - et), glm::max(b + eb, top + et));
}

namespace detail {
TESSERA_HD TESSERA_INLINE HitCandidates<4> cone_candidates(const Cone& c, const PreciseRay& ray) {
  HitCandidates<4> out;
  const LocalRay local = to_local_ray(ray, c.base, c.frame);
  const double dd = glm::dot(local.direction, local.direction);
  const double r0 = c.base_radius, r1 = c.top_radius, h = c.height;
  // Zero height, or both radii zero (a segment, hit by rays through the axis with a made-up
  // normal): no area, no hits.
  if (!(dd > 0.0) || !(h > 0.0) || !(glm::max(r0, r1) > 0.0)) return out;
  const double band = ray.origin_error + 1e-15 * (glm::max(r0, r1) + h);
  // Move the origin to the closest approach to the cone's middle before forming
  // coefficients; a shift along the ray changes no root, only the digits kept.
  const dvec3 to_middle = dvec3(0.0, 0.0, 0.5 * h) - local.origin;
  const double t_shift = glm::dot(to_middle, local.direction) / dd;
  const double slope = (r1 - r0) / h;
  lateral_roots(local, t_shift, r0, slope, h, c.capped != 0, band, out);
  if (c.capped != 0) {
    cap_root(local, 0.0, r0, r0, slope, kPartBottomCap, band, out);
    cap_root(local, h, r1, r0, slope, kPartTopCap, band, out);
  }
  return out;
}
}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Cone& c, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::cone_candidates(c, ray).closest(ray.t_min, t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE bool intersect(const Cone& c, const Ray& ray, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  return intersect(c, make_precise_ray(ray), t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Cone& c, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::cone_candidates(c, ray).all(ray.t_min, t_max, hits, max_hits, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Cone& c, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(c, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Cone& c, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = c.frame;
  const LocalRay local = to_local_ray(ray, c.base, frame);
  const std::uint32_t part = static_cast<std::uint32_t>(hit.v);
  const double t = detail::cone_candidates(c, ray).nearest(hit.t, part);
  dvec3 p = local.origin + t * local.direction;
  const double rho = std::sqrt(p.x * p.x + p.y * p.y);
  const double h = c.height;
  const double slope = (static_cast<double>(c.top_radius) - c.base_radius) / h;
  dvec3 normal;
  if (part == kPartSide) {
    const double z = glm::clamp(p.z, 0.0, h);
    const double radius = c.base_radius + slope * z;
    if (rho > 0.0) {
      const double cos_phi = p.x / rho, sin_phi = p.y / rho;
      p = dvec3(cos_phi * radius, sin_phi * radius, z);
      // Gradient of x^2 + y^2 - (r0 + slope z)^2 on the surface, up to a factor 2 radius.
      normal = glm::normalize(dvec3(cos_phi, sin_phi, -slope));
    } else {  // the apex: the axis direction pointing away from the cone
      p = dvec3(0.0, 0.0, z);
      normal = dvec3(0.0, 0.0, slope < 0.0 ? 1.0 : -1.0);
    }
    si.uv = vec2(angle_fraction(p.y, p.x), static_cast<float>(z / h));
  } else {
    p.z = part == kPartBottomCap ? 0.0 : h;
    normal = dvec3(0.0, 0.0, part == kPartBottomCap ? -1.0 : 1.0);
    const double cap_radius = part == kPartBottomCap ? c.base_radius : c.top_radius;
    si.uv = vec2(angle_fraction(p.y, p.x), static_cast<float>(glm::min(rho / cap_radius, 1.0)));
  }
  si.position = vec3(dvec3(c.base) + frame.to_world(p));
  set_face_normal(si, vec3(ray.direction), vec3(glm::normalize(frame.to_world(normal))));
  si.material = c.material;
  return si;
}
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Cone& c, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(c, make_precise_ray(ray), hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Cone& c) {
  const float r0 = c.base_radius, r1 = c.top_radius;
  const float side = kPi * (r0 + r1) * std::sqrt((r0 - r1) * (r0 - r1) + c.height * c.height);
  return c.capped != 0 ? side + kPi * (r0 * r0 + r1 * r1) : side;
}

}  // namespace tessera
