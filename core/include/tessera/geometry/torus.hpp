#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/polynomial.hpp"
#include "tessera/math/solver_bracketed.hpp"
#include "tessera/math/solver_quartic.hpp"

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

// Signed distance to the tube on the point's own side of the axis.
TESSERA_HD TESSERA_INLINE double torus_distance(const dvec3& q, double R, double r) {
  const double rho = std::sqrt(q.x * q.x + q.y * q.y);
  return std::sqrt((rho - R) * (rho - R) + q.z * q.z) - r;
}

// Roots t of ray/torus, ascending, found inside [max(t_min, 0), t_max].
// How the quartic is solved: root isolation on the ray's interval (the default, see
// solver_bracketed.hpp) or Algorithm 1010 on the whole real line (solver_quartic.hpp), kept
// selectable so the stress suite can compare the two on the same rays.
enum class QuarticMethod { kIsolation, kAlgorithm1010 };

template <QuarticMethod kMethod = QuarticMethod::kIsolation>
TESSERA_HD HitCandidates<4> torus_candidates(const Torus& torus, const PreciseRay& ray, float t_max,
                                             bool first_only = false) {
  HitCandidates<4> out;
  // A zero minor radius is the core circle, not a surface (rays through it hit it).
  if (!(torus.minor_radius > 0.0f)) return out;
  const AxisFrame frame = AxisFrame::from_axis(torus.axis);
  const LocalRay local = to_local_ray(ray, torus.center, frame);
  const double length = glm::length(local.direction);
  if (!(length > 0.0) || !std::isfinite(length)) return out;
  const dvec3 d = local.direction / length;  // unit: s = t * length is a distance
  const dvec3& o = local.origin;
  const double R = torus.major_radius, r = torus.minor_radius;
  const double bound = R + r;

  // The search interval: inside the bounding sphere and the slab |z| <= r, and inside the
  // ray's own interval. Clipping first keeps the expansion point near the torus (the
  // origin is moved there before the coefficients are formed) and the interval short.
  const double f = glm::dot(o, d);
  const dvec3 perpendicular = o - f * d;
  const double distance = glm::length(perpendicular);
  if (distance > bound) return out;
  const double half_chord = std::sqrt((bound - distance) * (bound + distance));
  double s0 = -f - half_chord;
  double s1 = -f + half_chord;
  if (d.z != 0.0) {
    const double sa = (-r - o.z) / d.z, sb = (r - o.z) / d.z;
    s0 = glm::max(s0, glm::min(sa, sb));
    s1 = glm::min(s1, glm::max(sa, sb));
  } else if (std::fabs(o.z) > r) {
    return out;
  }
  // A root can sit exactly on the bounding sphere or slab (the outer equator, the top
  // circle): widen by a hair so that its sign change lies inside the interval.
  const double pad = 1e-9 * bound;
  s0 = glm::max(s0 - pad, glm::max(static_cast<double>(ray.t_min), 0.0) * length);
  s1 = glm::min(s1 + pad, static_cast<double>(t_max) * length);
  if (!(s0 <= s1)) return out;

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
  const bool spindle = r > R;
  const double band = ray.origin_error + 1e-14 * bound;
  const auto signed_distance = [R, r](const dvec3& q) { return torus_distance(q, R, r); };
  double origin_distance = -1.0;  // computed when the first root needs it
  // Keeps a root unless it is on the inner lemon of a spindle torus or is the surface the
  // ray starts on; returns true (stop) once a hit is kept and only the first is wanted.
  const auto consider = [&](double sigma) {
    if (spindle) {
      const TorusFactors at_root = torus_factors(oc + sigma * d, R, r);
      if (std::fabs(at_root.near) > std::fabs(at_root.far)) return false;  // inner lemon
    }
    const double t = (s_mid + sigma) / length;
    if (origin_distance < 0.0) origin_distance = std::fabs(signed_distance(local.origin));
    if (is_start_surface_root(signed_distance, origin_distance, local, t, band)) return false;
    out.add(t, 0);
    float tf;
    return first_only && accept_root(t, ray.t_min, t_max, tf);
  };
  // The interval is already inside the bounding sphere, so the search skips the Cauchy
  // clip of visit_roots_in_interval (4% of the torus's instructions, measured).
  if constexpr (kMethod == QuarticMethod::kIsolation) {
    detail::visit_roots(quartic, s0 - s_mid, s1 - s_mid, consider, 0.0);
  } else {
    double all[4];
    const int found =
        solve_quartic(quartic.c[4], quartic.c[3], quartic.c[2], quartic.c[1], quartic.c[0], all);
    if (found == kSolverFailed) {  // not expected of a torus's coefficients; isolation decides
      detail::visit_roots(quartic, s0 - s_mid, s1 - s_mid, consider, 0.0);
      return out;
    }
    for (int i = 0; i < found; ++i)
      if (all[i] >= s0 - s_mid && all[i] <= s1 - s_mid && consider(all[i])) break;
  }
  return out;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Torus& torus, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::torus_candidates(torus, ray, t_max, true)
      .closest(ray.t_min, t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE bool intersect(const Torus& torus, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(torus, make_precise_ray(ray), t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Torus& torus, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::torus_candidates(torus, ray, t_max)
      .all(ray.t_min, t_max, hits, max_hits, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Torus& torus, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(torus, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Torus& torus, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  // The float t is refined to the double root it came from, so that the point, normal and
  // uv do not inherit float rounding of t (which is large for far-away origins).
  PreciseRay search = ray;
  search.t_min = 0.0f;
  const double t = detail::torus_candidates(torus, search, kInfinity).nearest(hit.t, 0);
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
  set_face_normal(si, vec3(ray.direction), vec3(glm::normalize(frame.to_world(outward))));
  si.uv = vec2(angle_fraction(q.y, q.x), angle_fraction(q.z, rho - R));
  si.material = torus.material;
  return si;
}
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Torus& torus, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(torus, make_precise_ray(ray), hit);
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
