#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/sdf_primitives.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// Sphere tracing (Hart 1996) of the exact signed-distance primitives, with a bounded step
// count. The ray is first clipped to the primitive's box; the march steps by |distance|
// (which never crosses the surface) but by no less than a floor that grows with the step
// count, and watches the sign of the distance: a sign change brackets a crossing, which is
// refined to double precision, so t is exact to the distance function's rounding. What
// this gives up, measured by the stress suite: a crossing whose chord is shorter than the
// floor at that point (a ray clipping an edge or corner after a long grazing crawl) can be
// stepped over, and a ray still crawling when the budget runs out is reported as a miss.
inline constexpr int kSphereTracingMaxSteps = 512;

namespace detail {

template <typename Sdf>
TESSERA_HD double sdf_scale(const Sdf& shape) {
  dvec3 lower, upper;
  sdf_local_bounds(shape, lower, upper);
  return 0.5 * glm::length(upper - lower);
}

// Crossings of the primitive's surface by the ray, ascending; all of them (up to 4) or the
// first one accepted by [t_min, t_max].
template <typename Sdf>
TESSERA_HD HitCandidates<4> sphere_trace(const Sdf& shape, const PreciseRay& ray, float t_max,
                                         bool first_only) {
  HitCandidates<4> out;
  const double length = glm::length(ray.direction);
  if (!(length > 0.0) || !std::isfinite(length)) return out;
  const dvec3 d = ray.direction / length;
  const dvec3 o = ray.origin - sdf_reference_point(shape);  // relative to the primitive
  dvec3 lower, upper;
  sdf_local_bounds(shape, lower, upper);
  const double scale = 0.5 * glm::length(upper - lower);
  // Clip to the box (padded), and to the ray's interval.
  double s0 = glm::max(static_cast<double>(ray.t_min), 0.0) * length;
  double s1 = static_cast<double>(t_max) * length;
  const double pad = 1e-6 * scale;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (o[axis] < lower[axis] - pad || o[axis] > upper[axis] + pad) return out;
      continue;
    }
    const double a = (lower[axis] - pad - o[axis]) / d[axis];
    const double b = (upper[axis] + pad - o[axis]) / d[axis];
    s0 = glm::max(s0, glm::min(a, b));
    s1 = glm::min(s1, glm::max(a, b));
  }
  if (!(s0 <= s1)) return out;

  const double band = ray.origin_error + 1e-12 * scale;
  const auto distance_at = [&](double s) { return signed_distance(shape, o + s * d); };
  double s = s0;
  double f = distance_at(s);
  int steps = 0;
  // A ray starting on the surface (within the origin's uncertainty): move along it while it
  // stays within that band, and take the side it is on there as the starting side.
  if (std::fabs(signed_distance(shape, o)) <= band) {
    while (std::fabs(f) <= 2.0 * band && s <= s1 && steps < kSphereTracingMaxSteps) {
      s += glm::max(std::fabs(f), band);
      f = distance_at(s);
      ++steps;
    }
  }
  bool inside = f < 0.0;
  while (s <= s1 && steps < kSphereTracingMaxSteps) {
    ++steps;
    // Step by the distance, but never less than a minimum that starts at 1e-6 of the size
    // and doubles every 32 steps: near an edge or at a grazing angle the distance shrinks
    // geometrically and plain sphere tracing crawls; the floor bounds the crawl, and the
    // sign check below catches any crossing a floor-sized step jumps over.
    const double floor_step = 1e-6 * scale * std::exp2(static_cast<double>(steps) / 32.0);
    const double next = s + glm::max(std::fabs(f), floor_step);
    const double f_next = distance_at(next);
    if ((f_next < 0.0) == inside) {
      s = next;
      f = f_next;
      continue;
    }
    // Crossed between s and next. The distance is nearly linear there, so the Illinois
    // variant of regula falsi usually converges in a few steps (bisection takes ~50); the
    // bracket is kept throughout, so it cannot fail.
    double a = s, b = next, fa = f, fb = f_next;
    int side = 0;
    for (int i = 0;
         i < 100 && b - a > 4e-16 * glm::max(glm::max(std::fabs(a), std::fabs(b)), scale); ++i) {
      // After 12 regula falsi steps (a grazing crossing, where the distance is far from
      // linear) fall back to bisection, which always finishes within the cap.
      double m = i < 12 ? (a * fb - b * fa) / (fb - fa) : 0.5 * (a + b);
      if (!(m > a && m < b)) m = 0.5 * (a + b);
      const double fm = distance_at(m);
      if (fm == 0.0) {
        a = b = m;
        break;
      }
      if ((fm < 0.0) != inside) {
        b = m;
        fb = fm;
        if (side == 1) fa *= 0.5;
        side = 1;
      } else {
        a = m;
        fa = fm;
        if (side == -1) fb *= 0.5;
        side = -1;
      }
    }
    const double root = 0.5 * (a + b);
    out.add(root / length, 0);
    float tf;
    if (first_only && accept_root(root / length, ray.t_min, t_max, tf)) return out;
    if (out.count == 4) return out;
    inside = !inside;
    // Resume a hair past the crossing: starting exactly on it (distance 0) would let the
    // next bracket find this same root again.
    s = glm::max(b, root + 1e-9 * scale);
    f = distance_at(s);
  }
  return out;
}

template <typename Sdf>
TESSERA_HD dvec3 sdf_gradient(const Sdf& shape, const dvec3& p, double h) {
  return dvec3(
      signed_distance(shape, p + dvec3(h, 0, 0)) - signed_distance(shape, p - dvec3(h, 0, 0)),
      signed_distance(shape, p + dvec3(0, h, 0)) - signed_distance(shape, p - dvec3(0, h, 0)),
      signed_distance(shape, p + dvec3(0, 0, h)) - signed_distance(shape, p - dvec3(0, 0, h)));
}

template <typename Sdf>
TESSERA_HD SurfaceInteraction sdf_surface_at(const Sdf& shape, const PreciseRay& ray,
                                             const HitRecord& hit, std::uint32_t material) {
  SurfaceInteraction si;
  const double t = sphere_trace(shape, ray, kInfinity, false).nearest(hit.t, 0);
  const dvec3 p = ray.origin + t * ray.direction - sdf_reference_point(shape);
  const double scale = sdf_scale(shape);
  dvec3 gradient = sdf_gradient(shape, p, 1e-6 * scale);
  const double g = glm::length(gradient);
  gradient = g > 0.0 ? gradient / g : dvec3(0.0, 0.0, 1.0);
  // Project onto the surface along the gradient (the distance is exact).
  const dvec3 on_surface = p - signed_distance(shape, p) * gradient;
  si.position = vec3(on_surface + sdf_reference_point(shape));
  set_face_normal(si, vec3(ray.direction), vec3(gradient));
  // Spherical uv of the normal: a generic parameterisation for shapes without a natural one.
  si.uv = vec2(
      angle_fraction(gradient.y, gradient.x),
      static_cast<float>(std::acos(glm::clamp(gradient.z, -1.0, 1.0)) / 3.14159265358979323846));
  si.material = material;
  return si;
}

}  // namespace detail

// Any primitive with an exact signed_distance and local bounds is sphere traced.
template <typename Sdf>
concept SphereTraced = requires(const Sdf& shape, const dvec3& p, dvec3& lower, dvec3& upper) {
  signed_distance(shape, p);
  sdf_local_bounds(shape, lower, upper);
  sdf_reference_point(shape);
};

template <SphereTraced Sdf>
TESSERA_HD bool intersect(const Sdf& s, const PreciseRay& ray, float t_max, HitRecord& hit,
                          std::uint32_t primitive) {
  return detail::sphere_trace(s, ray, t_max, true).closest(ray.t_min, t_max, hit, primitive);
}
template <SphereTraced Sdf>
TESSERA_HD bool intersect(const Sdf& s, const Ray& ray, float t_max, HitRecord& hit,
                          std::uint32_t primitive) {
  return intersect(s, make_precise_ray(ray), t_max, hit, primitive);
}
template <SphereTraced Sdf>
TESSERA_HD int intersect_all(const Sdf& s, const PreciseRay& ray, float t_max, HitRecord* hits,
                             int max_hits, std::uint32_t primitive) {
  return detail::sphere_trace(s, ray, t_max, false)
      .all(ray.t_min, t_max, hits, max_hits, primitive);
}
template <SphereTraced Sdf>
TESSERA_HD int intersect_all(const Sdf& s, const Ray& ray, float t_max, HitRecord* hits,
                             int max_hits, std::uint32_t primitive) {
  return intersect_all(s, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}
template <SphereTraced Sdf>
TESSERA_HD SurfaceInteraction surface_at(const Sdf& s, const PreciseRay& ray,
                                         const HitRecord& hit) {
  return detail::sdf_surface_at(s, ray, hit, s.material);
}
template <SphereTraced Sdf>
TESSERA_HD SurfaceInteraction surface_at(const Sdf& s, const Ray& ray, const HitRecord& hit) {
  return surface_at(s, make_precise_ray(ray), hit);
}

}  // namespace tessera
