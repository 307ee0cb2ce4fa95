#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/plane.hpp"
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
  // AxisFrame::from_axis(axis), computed once by make instead of on every intersection.
  // Build cylinders through make (or refresh the frame after changing the axis).
  AxisFrame frame;

  static Cylinder make(const vec3& base, const vec3& axis, float radius, float height, bool capped,
                       std::uint32_t material) {
    const vec3 unit = glm::normalize(axis);
    return Cylinder{
        base, unit, radius, height, capped ? 1u : 0u, material, AxisFrame::from_axis(unit)};
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

// A root on one part of a capped cylinder or cone is a start-surface root also when the
// ray starts on, and runs along, another part: a ray that starts on a cap and runs in its
// plane meets the side at the rim (stress seed 148 reported that rim 0.24 away as a hit),
// and one along a ruling of the side meets a cap's rim. These are the two parts' distances
// in the local frame, and cheap tests of whether the origin is near each.
// The signed distance to the side of radius r0 + slope z (first order: the radial gap times
// 1 / sqrt(1 + slope^2), the side's distance per unit of radius).
struct SideDistance {
  double r0, slope, normalisation;
  TESSERA_HD SideDistance(double r0_, double slope_)
      : r0(r0_), slope(slope_), normalisation(1.0 / std::sqrt(1.0 + slope_ * slope_)) {}
  TESSERA_HD double operator()(const dvec3& p) const {
    return (std::sqrt(p.x * p.x + p.y * p.y) - (r0 + slope * p.z)) * normalisation;
  }
};

TESSERA_HD TESSERA_INLINE double cap_distance(const dvec3& p, double r0, double slope,
                                              double height) {
  const double rho = std::sqrt(p.x * p.x + p.y * p.y);
  const auto disk = [&](double z_cap, double radius) {
    const double outside = glm::max(rho - radius, 0.0);
    return std::sqrt((p.z - z_cap) * (p.z - z_cap) + outside * outside);
  };
  return glm::min(disk(0.0, r0), disk(height, r0 + slope * height));
}

// Whether p may lie within `band` of the side: |rho - r| <= band implies
// |rho^2 - r^2| <= band (rho + |r|) <= band (|x| + |y| + |r|), without a square root.
TESSERA_HD TESSERA_INLINE bool may_be_near_side(const dvec3& p, double r0, double slope,
                                                double band) {
  const double r = r0 + slope * p.z;
  return std::fabs(p.x * p.x + p.y * p.y - r * r) <=
         band * (std::fabs(p.x) + std::fabs(p.y) + std::fabs(r) + band);
}

// Side roots of the circular cone/cylinder x^2 + y^2 = (r0 + k z)^2, 0 <= z <= height, for
// the local ray. The origin is first moved along the ray to `t_shift` (near the shape) so
// that the coefficients are formed from small numbers, and the constant term is written
// as a product so that it keeps its digits near the surface; the quadratic itself is the
// stable one (q = -(b + sign(b) sqrt(disc)) / 2).
template <int N>
TESSERA_HD void lateral_roots(const LocalRay& ray, double t_shift, double r0, double slope,
                              double height, bool capped, double band, HitCandidates<N>& out) {
  const dvec3 o = ray.origin + t_shift * ray.direction;
  const dvec3& d = ray.direction;
  const double radius_at_o = r0 + slope * o.z;
  const double rho = std::sqrt(o.x * o.x + o.y * o.y);
  const double a = d.x * d.x + d.y * d.y - slope * slope * d.z * d.z;
  const double b = 2.0 * (o.x * d.x + o.y * d.y - slope * d.z * radius_at_o);
  const double c = (rho - radius_at_o) * (rho + radius_at_o);
  double s[2];
  int n = solve_quadratic_in_range(a, b, c, s);
  // a < 0: the direction is steeper than the cone's generators, and such a line meets the
  // double cone in two points in exact arithmetic (one per nappe). Near the apex the two
  // roots differ by the ray's distance from the apex, below what the rounded coefficients
  // resolve, and the discriminant can come out negative: it is then a double root at the
  // apex, which the ray passes through.
  if (n == 0 && a < 0.0) {
    s[0] = -b / (2.0 * a);
    n = 1;
  }
  // A root at a pointed end (radius 0: the apex) is a near-double root, known only to about
  // sqrt(epsilon) of the size, and may land that far outside [0, height].
  const double radius_scale = std::fabs(r0) + std::fabs(r0 + slope * height);
  const SideDistance distance(r0, slope);
  const double origin_distance = n > 0 ? distance(ray.origin) : 0.0;
  const bool origin_on_cap =
      capped && n > 0 &&
      glm::min(std::fabs(ray.origin.z), std::fabs(ray.origin.z - height)) <= band &&
      cap_distance(ray.origin, r0, slope, height) <= band;
  for (int i = 0; i < n; ++i) {
    const double z = o.z + s[i] * d.z;
    const double t = t_shift + s[i];
    const bool in_range = z >= 0.0 && z <= height;
    const bool at_apex = std::fabs(r0 + slope * z) <= 1e-7 * radius_scale && z >= -1e-6 * height &&
                         z <= height * (1.0 + 1e-6);
    // Both roots at the apex: one is on the mirrored nappe (radius < 0), keep the other.
    if (at_apex && n == 2) {
      const double other_z = o.z + s[1 - i] * d.z;
      if (slope * (z - other_z) < 0.0 || (z == other_z && i == 1)) continue;
    }
    if (!(in_range || at_apex) || is_start_surface_root(distance, origin_distance, ray, t, band))
      continue;
    if (origin_on_cap &&
        cap_distance(ray.origin + (0.5 * t) * ray.direction, r0, slope, height) <= band)
      continue;
    out.add(t, kPartSide);
  }
}

// Cap at local height z_cap with radius cap_radius (a disk perpendicular to the axis) of
// the side of radius r0 + slope z.
template <int N>
TESSERA_HD void cap_root(const LocalRay& ray, double z_cap, double cap_radius, double r0,
                         double slope, std::uint32_t part, double band, HitCandidates<N>& out) {
  if (!(cap_radius > 0.0)) return;
  double t;
  if (!local_plane_root(ray, z_cap, band, t)) return;
  const double x = ray.origin.x + t * ray.direction.x;
  const double y = ray.origin.y + t * ray.direction.y;
  if (!(x * x + y * y <= cap_radius * cap_radius)) return;
  // Along the side to the cap's rim: the surface the ray starts on.
  if (may_be_near_side(ray.origin, r0, slope, band)) {
    const SideDistance distance(r0, slope);
    if (is_start_surface_root(distance, distance(ray.origin), ray, t, band)) return;
  }
  out.add(t, part);
}

TESSERA_HD TESSERA_INLINE HitCandidates<4> cylinder_candidates(const Cylinder& c,
                                                               const PreciseRay& ray) {
  HitCandidates<4> out;
  const LocalRay local = to_local_ray(ray, c.base, c.frame);
  const double band = ray.origin_error + 1e-15 * (c.radius + c.height);
  const double a = local.direction.x * local.direction.x + local.direction.y * local.direction.y;
  // The side has no area at zero radius (a segment, which rays through the axis hit) or
  // zero height (a circle, hit by rays in its plane): skipped. The caps need radius > 0
  // (cap_root); a flat capped cylinder is still its two caps.
  if (a > 0.0 && c.radius > 0.0f && c.height > 0.0f) {
    // Closest approach to the axis: the side roots are symmetric around it.
    const double t_shift =
        -(local.origin.x * local.direction.x + local.origin.y * local.direction.y) / a;
    lateral_roots(local, t_shift, c.radius, 0.0, c.height, c.capped != 0, band, out);
  }
  if (c.capped != 0) {
    cap_root(local, 0.0, c.radius, c.radius, 0.0, kPartBottomCap, band, out);
    cap_root(local, c.height, c.radius, c.radius, 0.0, kPartTopCap, band, out);
  }
  return out;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Cylinder& c, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::cylinder_candidates(c, ray).closest(ray.t_min, t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE bool intersect(const Cylinder& c, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(c, make_precise_ray(ray), t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Cylinder& c, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::cylinder_candidates(c, ray).all(ray.t_min, t_max, hits, max_hits, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Cylinder& c, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(c, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Cylinder& c, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = c.frame;
  const LocalRay local = to_local_ray(ray, c.base, frame);
  const std::uint32_t part = static_cast<std::uint32_t>(hit.v);
  const double t = detail::cylinder_candidates(c, ray).nearest(hit.t, part);
  dvec3 p = local.origin + t * local.direction;
  const double rho = std::sqrt(p.x * p.x + p.y * p.y);
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
  set_face_normal(si, vec3(ray.direction), vec3(glm::normalize(frame.to_world(normal))));
  si.material = c.material;
  return si;
}
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Cylinder& c, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(c, make_precise_ray(ray), hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Cylinder& c) {
  const float side = 2.0f * kPi * c.radius * c.height;
  return c.capped != 0 ? side + 2.0f * kPi * c.radius * c.radius : side;
}

}  // namespace tessera
