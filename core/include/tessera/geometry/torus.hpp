#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/polynomial.hpp"
#include "tessera/math/solver_bracketed.hpp"

namespace tessera {

// Torus around the unit `axis` through `center`: the circle of radius major_radius (R) in
// the plane perpendicular to the axis, swept by a disk of radius minor_radius (r).
// Ring (r < R), horn (r == R) and spindle (r > R) tori are all valid. For a spindle torus
// the quartic also vanishes on the inner "lemon" that the tube sweeps across the axis,
// which lies inside the solid; those roots are discarded so that only the visible outer
// surface is hit. uv = (angle around the axis, angle around the tube) / 2 pi.
struct Torus {
  vec3 center;
  vec3 axis;  // unit
  float major_radius;
  float minor_radius;
  std::uint32_t material;

  static Torus make(const vec3& center, const vec3& axis, float major_radius, float minor_radius,
                    std::uint32_t material) {
    return Torus{center, glm::normalize(axis), major_radius, minor_radius, material};
  }
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Torus& t) {
  const dvec3 c(t.center);
  const dvec3 e = circle_half_extent(dvec3(t.axis), t.major_radius) +
                  dvec3(static_cast<double>(t.minor_radius));
  return conservative_aabb(c - e, c + e);
}

namespace detail {

// The quartic factors as near * far with near = (rho - R)^2 + z^2 - r^2 (the tube around
// the circle of radius R on the point's own side of the axis) and far = (rho + R)^2 + z^2 -
// r^2 (the same tube seen from the opposite side). Written this way neither factor is the
// difference of the O(R^4) terms that cancel in the expanded quartic.
struct TorusFactors {
  double near, far;
};
TESSERA_HD TESSERA_INLINE TorusFactors torus_factors(const dvec3& q, double R, double r) {
  const double rho = std::sqrt(q.x * q.x + q.y * q.y);
  const double z_term = (q.z - r) * (q.z + r);
  return TorusFactors{(rho - R) * (rho - R) + z_term, (rho + R) * (rho + R) + z_term};
}

// Roots t of ray/torus, ascending, accepted against [t_min, t_max] and the origin margin.
TESSERA_HD TESSERA_INLINE int torus_roots(const Torus& torus, const Ray& ray, float t_max,
                                          double roots[4]) {
  const AxisFrame frame = AxisFrame::from_axis(torus.axis);
  const LocalRay local = to_local_ray(ray, torus.center, frame);
  const double length = glm::length(local.direction);
  if (!(length > 0.0) || !std::isfinite(length)) return 0;
  const dvec3 d = local.direction / length;  // unit: s = t * length is a distance
  const dvec3& o = local.origin;
  const double R = torus.major_radius, r = torus.minor_radius;
  const double bound = R + r;
  const double margin = origin_margin(max_abs(dvec3(ray.origin)) + bound, length);

  // The search interval: inside the bounding sphere and the slab |z| <= r, and inside the
  // ray's own interval. Clipping first keeps the expansion point near the torus (the
  // origin is moved there before the coefficients are formed) and the interval short.
  const double f = glm::dot(o, d);
  const dvec3 perpendicular = o - f * d;
  const double perpendicular2 = glm::dot(perpendicular, perpendicular);
  if (perpendicular2 > bound * bound) return 0;
  const double half_chord =
      std::sqrt((bound - std::sqrt(perpendicular2)) * (bound + std::sqrt(perpendicular2)));
  double s0 = -f - half_chord;
  double s1 = -f + half_chord;
  if (d.z != 0.0) {
    const double sa = (-r - o.z) / d.z, sb = (r - o.z) / d.z;
    s0 = glm::max(s0, glm::min(sa, sb));
    s1 = glm::min(s1, glm::max(sa, sb));
  } else if (std::fabs(o.z) > r) {
    return 0;
  }
  // A root can sit exactly on the bounding sphere or slab (the outer equator, the top
  // circle): widen by a hair so that its sign change lies inside the interval.
  const double pad = 1e-9 * bound;
  s0 = glm::max(s0 - pad, glm::max(static_cast<double>(ray.t_min), margin) * length);
  s1 = glm::min(s1 + pad, static_cast<double>(t_max) * length);
  if (!(s0 <= s1)) return 0;

  const double s_mid = 0.5 * (s0 + s1);
  const dvec3 oc = o + s_mid * d;
  const double dd = glm::dot(d, d);
  const double fc = glm::dot(oc, d);
  const double e = glm::dot(oc, oc) + (R - r) * (R + r);
  const double R2 = R * R;
  const TorusFactors at_origin = torus_factors(oc, R, r);
  const Polynomial<4, double> quartic{
      {at_origin.near * at_origin.far, 4.0 * e * fc - 8.0 * R2 * (oc.x * d.x + oc.y * d.y),
       4.0 * fc * fc + 2.0 * dd * e - 4.0 * R2 * (d.x * d.x + d.y * d.y), 4.0 * dd * fc, dd * dd}};
  double sigma[4];
  const int n = roots_in_interval(quartic, s0 - s_mid, s1 - s_mid, sigma);
  const bool spindle = r > R;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    if (spindle) {
      const TorusFactors at_root = torus_factors(oc + sigma[i] * d, R, r);
      if (std::fabs(at_root.near) > std::fabs(at_root.far)) continue;  // inner lemon
    }
    const double t = (s_mid + sigma[i]) / length;
    if (t > margin) roots[count++] = t;
  }
  return count;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Torus& torus, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  double roots[4];
  const int n = detail::torus_roots(torus, ray, t_max, roots);
  for (int i = 0; i < n; ++i) {
    const float t = static_cast<float>(roots[i]);
    if (t > ray.t_min && t < t_max) {
      hit.t = t;
      hit.u = 0.0f;
      hit.v = 0.0f;
      hit.primitive = primitive;
      return true;
    }
  }
  return false;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Torus& torus, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  double roots[4];
  const int n = detail::torus_roots(torus, ray, t_max, roots);
  int count = 0;
  for (int i = 0; i < n && count < max_hits; ++i) {
    const float t = static_cast<float>(roots[i]);
    if (!(t > ray.t_min && t < t_max)) continue;
    hits[count].t = t;
    hits[count].u = 0.0f;
    hits[count].v = 0.0f;
    hits[count].primitive = primitive;
    ++count;
  }
  return count;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Torus& torus, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  // The float t is refined to the double root nearest to it, so that the point, normal and
  // uv do not inherit float rounding of t (which is large for far-away origins).
  double t = hit.t;
  double roots[4];
  Ray full = ray;
  full.t_min = -kInfinity;
  const int n = detail::torus_roots(torus, full, kInfinity, roots);
  for (int i = 0; i < n; ++i)
    if (std::fabs(roots[i] - hit.t) < std::fabs(t - hit.t) || i == 0) t = roots[i];
  if (!(std::fabs(t - hit.t) <=
        1e-3 * (std::fabs(static_cast<double>(hit.t)) + torus.major_radius + torus.minor_radius)))
    t = hit.t;

  const AxisFrame frame = AxisFrame::from_axis(torus.axis);
  const LocalRay local = to_local_ray(ray, torus.center, frame);
  const dvec3 q = local.origin + t * local.direction;
  const double R = torus.major_radius, r = torus.minor_radius;
  const double rho = std::sqrt(q.x * q.x + q.y * q.y);
  const double cos_phi = rho > 0.0 ? q.x / rho : 1.0;
  const double sin_phi = rho > 0.0 ? q.y / rho : 0.0;
  const dvec3 tube_center(R * cos_phi, R * sin_phi, 0.0);
  dvec3 outward = q - tube_center;
  const double distance = glm::length(outward);
  outward = distance > 0.0 ? outward / distance : dvec3(cos_phi, sin_phi, 0.0);
  const dvec3 p = tube_center + r * outward;
  si.position = vec3(dvec3(torus.center) + frame.to_world(p));
  set_face_normal(si, ray.direction, vec3(glm::normalize(frame.to_world(outward))));
  si.uv = vec2(angle_fraction(q.y, q.x), angle_fraction(q.z, rho - R));
  si.material = torus.material;
  return si;
}

// Area of the visible surface: the tube's circle swept around the axis, for a spindle
// torus only the arc outside the axis (Pappus: 2 pi r times the integral of rho over the
// arc angle).
TESSERA_HD TESSERA_INLINE float surface_area(const Torus& torus) {
  const double R = torus.major_radius, r = torus.minor_radius;
  const double theta0 = r > R ? std::acos(-R / r) : 3.14159265358979323846;
  return static_cast<float>(2.0 * 3.14159265358979323846 * r *
                            (2.0 * R * theta0 + 2.0 * r * std::sin(theta0)));
}

}  // namespace tessera
