#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/solver_quadratic.hpp"

namespace tessera {

// Finite cylinder of `radius` around the unit `axis`, from `base` to base + height * axis,
// optionally closed by two disks. uv on the side: (angle / 2 pi, height fraction); on a
// cap: (angle / 2 pi, radial fraction). HitRecord::v holds the part: 0 side, 1 bottom cap,
// 2 top cap.
struct Cylinder {
  vec3 base;
  vec3 axis;  // unit
  float radius;
  float height;
  std::uint32_t capped;  // 0 or 1 (an integer keeps the struct plain for device copies)
  std::uint32_t material;

  static Cylinder make(const vec3& base, const vec3& axis, float radius, float height, bool capped,
                       std::uint32_t material) {
    return Cylinder{base, glm::normalize(axis), radius, height, capped ? 1u : 0u, material};
  }
};

inline constexpr std::uint32_t kPartSide = 0;
inline constexpr std::uint32_t kPartBottomCap = 1;
inline constexpr std::uint32_t kPartTopCap = 2;

TESSERA_HD TESSERA_INLINE Aabb bounds(const Cylinder& c) {
  const dvec3 w(c.axis);
  const dvec3 b(c.base);
  const dvec3 top = b + w * static_cast<double>(c.height);
  const dvec3 e = circle_half_extent(w, c.radius);
  return conservative_aabb(glm::min(b, top) - e, glm::max(b, top) + e);
}

namespace detail {

// Roots of the side of a circular cone/cylinder x^2 + y^2 = (r0 + k z)^2 for local ray o + t
// d, with the origin first moved along the ray to `t_shift` so that the coefficients are
// formed from small numbers (no cancellation for origins far away), and the constant term
// written as a product so that it keeps its digits near the surface. Appends roots with
// 0 <= z <= height.
template <int N>
TESSERA_HD void lateral_roots(const LocalRay& ray, double t_shift, double r0, double slope,
                              double height, HitCandidates<N>& out) {
  const dvec3 o = ray.origin + t_shift * ray.direction;
  const dvec3& d = ray.direction;
  const double radius_at_o = r0 + slope * o.z;
  const double rho = std::sqrt(o.x * o.x + o.y * o.y);
  const double a = d.x * d.x + d.y * d.y - slope * slope * d.z * d.z;
  const double b = 2.0 * (o.x * d.x + o.y * d.y - slope * d.z * radius_at_o);
  const double c = (rho - radius_at_o) * (rho + radius_at_o);
  double s[2];
  const int n = solve_quadratic(a, b, c, s);
  for (int i = 0; i < n; ++i) {
    const double z = o.z + s[i] * d.z;
    if (z >= 0.0 && z <= height) out.add(t_shift + s[i], kPartSide);
  }
}

// Cap at local height z_cap with radius cap_radius (a disk perpendicular to the axis).
template <int N>
TESSERA_HD void cap_root(const LocalRay& ray, double z_cap, double cap_radius, std::uint32_t part,
                         HitCandidates<N>& out) {
  if (ray.direction.z == 0.0 || !(cap_radius > 0.0)) return;
  const double t = (z_cap - ray.origin.z) / ray.direction.z;
  const double x = ray.origin.x + t * ray.direction.x;
  const double y = ray.origin.y + t * ray.direction.y;
  if (x * x + y * y <= cap_radius * cap_radius) out.add(t, part);
}

TESSERA_HD TESSERA_INLINE HitCandidates<4> cylinder_candidates(const Cylinder& c, const Ray& ray,
                                                               double& margin) {
  HitCandidates<4> candidates;
  const AxisFrame frame = AxisFrame::from_axis(c.axis);
  const LocalRay local = to_local_ray(ray, c.base, frame);
  const double dd = glm::dot(local.direction, local.direction);
  margin = origin_margin(max_abs(dvec3(ray.origin)) + c.radius + c.height, std::sqrt(dd));
  const double a = local.direction.x * local.direction.x + local.direction.y * local.direction.y;
  if (a > 0.0) {
    // Closest approach to the axis: the side roots are symmetric around it.
    const double t_shift =
        -(local.origin.x * local.direction.x + local.origin.y * local.direction.y) / a;
    lateral_roots(local, t_shift, c.radius, 0.0, c.height, candidates);
  }
  if (c.capped != 0) {
    cap_root(local, 0.0, c.radius, kPartBottomCap, candidates);
    cap_root(local, c.height, c.radius, kPartTopCap, candidates);
  }
  return candidates;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Cylinder& c, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  double margin;
  const HitCandidates<4> candidates = detail::cylinder_candidates(c, ray, margin);
  return candidates.closest(ray.t_min, t_max, margin, hit, primitive);
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Cylinder& c, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  double margin;
  const HitCandidates<4> candidates = detail::cylinder_candidates(c, ray, margin);
  return candidates.all(ray.t_min, t_max, margin, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Cylinder& c, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = AxisFrame::from_axis(c.axis);
  const LocalRay local = to_local_ray(ray, c.base, frame);
  dvec3 p = local.origin + static_cast<double>(hit.t) * local.direction;
  const double rho = std::sqrt(p.x * p.x + p.y * p.y);
  const std::uint32_t part = static_cast<std::uint32_t>(hit.v);
  dvec3 normal;
  if (part == kPartSide) {
    // Project back onto the surface (the ray-evaluated point is off by t's rounding).
    const dvec3 radial = rho > 0.0 ? dvec3(p.x / rho, p.y / rho, 0.0) : dvec3(1.0, 0.0, 0.0);
    p = dvec3(radial.x * c.radius, radial.y * c.radius,
              glm::clamp(p.z, 0.0, static_cast<double>(c.height)));
    normal = radial;
    si.uv =
        vec2(angle_fraction(p.y, p.x), c.height > 0.0f ? static_cast<float>(p.z / c.height) : 0.0f);
  } else {
    p.z = part == kPartBottomCap ? 0.0 : c.height;
    normal = dvec3(0.0, 0.0, part == kPartBottomCap ? -1.0 : 1.0);
    si.uv = vec2(angle_fraction(p.y, p.x), static_cast<float>(glm::min(rho / c.radius, 1.0)));
  }
  si.position = vec3(dvec3(c.base) + frame.to_world(p));
  set_face_normal(si, ray.direction, vec3(glm::normalize(frame.to_world(normal))));
  si.material = c.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Cylinder& c) {
  const float side = 2.0f * kPi * c.radius * c.height;
  return c.capped != 0 ? side + 2.0f * kPi * c.radius * c.radius : side;
}

}  // namespace tessera
