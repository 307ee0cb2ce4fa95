#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/ray.hpp"

namespace tessera {

// Shared by the analytic shapes (sphere, plane, disk, cylinder, cone, torus): the ray is
// taken into the shape's own frame in double before anything is subtracted, because the
// subtractions that decide hit or miss (origin minus centre, the perpendicular distance to
// an axis) lose the digits that matter when the origin is 1e4 to 1e6 shape sizes away.
// Every product of two floats is exact in double, so the local ray is accurate to ~1e-16
// relative; t is rounded to float only when it is stored in the HitRecord.

struct AxisFrame {
  dvec3 u, v, w;  // right-handed orthonormal, w is the shape's axis

  // Duff et al. 2017 branchless basis, in double.
  TESSERA_HD static AxisFrame from_axis(const vec3& axis) {
    const dvec3 n = glm::normalize(dvec3(axis));
    const double sign = n.z >= 0.0 ? 1.0 : -1.0;
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    return AxisFrame{dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
                     dvec3(b, sign + n.y * n.y * a, -n.y), n};
  }
  TESSERA_HD dvec3 to_local(const dvec3& world) const {
    return dvec3(glm::dot(world, u), glm::dot(world, v), glm::dot(world, w));
  }
  TESSERA_HD dvec3 to_world(const dvec3& local) const {
    return u * local.x + v * local.y + w * local.z;
  }
};

// Largest absolute coordinate.
TESSERA_HD TESSERA_INLINE double max_abs(const dvec3& p) {
  return glm::max(std::fabs(p.x), glm::max(std::fabs(p.y), std::fabs(p.z)));
}

// A ray in double with the uncertainty of its origin: how far the point the caller means
// may lie from `origin` (the rounding of a float origin, or that rounding carried through
// an instance transform). The analytic shapes intersect this form; instances hand their
// object-space ray over in it, so that it is never rounded to float.
struct PreciseRay {
  dvec3 origin;
  dvec3 direction;
  float t_min;
  double origin_error;
};

// A float origin lies within sqrt(3)/2 ulp of the point it stands for, and an ulp of x is
// at most 2^-23 |x|: 2^-23 |o|_max bounds the distance (the surface a ray "starts on" is
// one within about one ulp of its origin).
TESSERA_HD TESSERA_INLINE PreciseRay make_precise_ray(const Ray& ray) {
  return PreciseRay{dvec3(ray.origin), dvec3(ray.direction), ray.t_min,
                    1.1920928955078125e-07 * max_abs(dvec3(ray.origin))};
}

// The ray in a shape's frame; t is unchanged by the change of frame.
struct LocalRay {
  dvec3 origin;
  dvec3 direction;
};

TESSERA_HD TESSERA_INLINE LocalRay to_local_ray(const PreciseRay& ray, const vec3& center,
                                                const AxisFrame& frame) {
  return LocalRay{frame.to_local(ray.origin - dvec3(center)), frame.to_local(ray.direction)};
}

// Self-hits of rays that start on a surface. A ray whose origin lies on a surface (to the
// precision the origin is known: `band`) finds that surface again at some t near 0, and
// rounding decides whether that t comes out slightly positive; for a ray leaving at a
// grazing angle it can be far from 0, so no threshold on t separates it from real hits.
// It is recognised geometrically instead: the origin is within the band of the surface and
// so is the midpoint between origin and root, i.e. the ray never left the band before
// "returning". A genuine second hit (the far side of a sphere, another part of a torus)
// has its midpoint well away from the surface. `distance` is the part's signed distance
// (or a function with the same zero set and unit slope there) in the local frame, and
// origin_distance its value at the origin (computed once per part, not per root).
template <typename Distance>
TESSERA_HD TESSERA_INLINE bool is_start_surface_root(const Distance& distance,
                                                     double origin_distance, const LocalRay& ray,
                                                     double t, double band) {
  return std::fabs(origin_distance) <= band &&
         std::fabs(distance(ray.origin + (0.5 * t) * ray.direction)) <= band;
}

// A root in double becomes a hit when its float t lies strictly inside the ray interval.
TESSERA_HD TESSERA_INLINE bool accept_root(double t, float t_min, float t_max, float& t_out) {
  if (!(t > 0.0)) return false;
  const float tf = static_cast<float>(t);
  if (!(tf > t_min && tf < t_max)) return false;
  t_out = tf;
  return true;
}

// A float box that contains the double box [lower, upper] despite rounding.
TESSERA_HD TESSERA_INLINE Aabb conservative_aabb(const dvec3& lower, const dvec3& upper) {
  Aabb box;
  for (int axis = 0; axis < 3; ++axis) {
    const double pad = 1e-6 * (std::fabs(lower[axis]) + std::fabs(upper[axis])) + 1e-30;
    box.lower[axis] = static_cast<float>(lower[axis] - pad);
    box.upper[axis] = static_cast<float>(upper[axis] + pad);
  }
  return box;
}

// Half-extent along each world axis of a circle of radius r around `axis`:
// r * sqrt(1 - axis_i^2).
TESSERA_HD TESSERA_INLINE dvec3 circle_half_extent(const dvec3& unit_axis, double radius) {
  return dvec3(radius * std::sqrt(glm::max(0.0, 1.0 - unit_axis.x * unit_axis.x)),
               radius * std::sqrt(glm::max(0.0, 1.0 - unit_axis.y * unit_axis.y)),
               radius * std::sqrt(glm::max(0.0, 1.0 - unit_axis.z * unit_axis.z)));
}

// Inserts hit into the ascending list hits[0..count) keeping at most max_hits entries.
TESSERA_HD TESSERA_INLINE int insert_hit_sorted(HitRecord* hits, int count, int max_hits,
                                                const HitRecord& hit) {
  if (max_hits <= 0) return 0;
  if (count >= max_hits && !(hit.t < hits[max_hits - 1].t)) return count;
  int i = count < max_hits ? count : max_hits - 1;
  while (i > 0 && hits[i - 1].t > hit.t) {
    hits[i] = hits[i - 1];
    --i;
  }
  hits[i] = hit;
  return count < max_hits ? count + 1 : max_hits;
}

// Roots of a shape's parts (side, caps) in double, each tagged with the part it belongs to;
// turned into the closest hit or the sorted list of all hits once every part was tried.
template <int kCapacity>
struct HitCandidates {
  double t[kCapacity];
  std::uint32_t part[kCapacity];
  int count = 0;

  TESSERA_HD void add(double root, std::uint32_t which) {
    if (count < kCapacity) {
      t[count] = root;
      part[count] = which;
      ++count;
    }
  }

  // Closest accepted root; the part goes to hit.v (as a small integer), and hit.u holds the
  // double root's remainder past the float t (root - t, a float that keeps it to about 1e-15
  // of t), so a surface_at can place the point from the root without solving again
  // (root_of_hit).
  TESSERA_HD bool closest(float t_min, float t_max, HitRecord& hit, std::uint32_t primitive) const {
    bool found = false;
    float best = t_max;
    double best_root = 0.0;
    std::uint32_t best_part = 0;
    for (int i = 0; i < count; ++i) {
      float tf;
      if (accept_root(t[i], t_min, best, tf)) {
        best = tf;
        best_root = t[i];
        best_part = part[i];
        found = true;
      }
    }
    if (!found) return false;
    hit.t = best;
    hit.u = static_cast<float>(best_root - static_cast<double>(best));
    hit.v = static_cast<float>(best_part);
    hit.primitive = primitive;
    return true;
  }

  TESSERA_HD int all(float t_min, float t_max, HitRecord* hits, int max_hits,
                     std::uint32_t primitive) const {
    int n = 0;
    for (int i = 0; i < count; ++i) {
      float tf;
      if (accept_root(t[i], t_min, t_max, tf)) {
        HitRecord h;
        h.t = tf;
        h.u = static_cast<float>(t[i] - static_cast<double>(tf));
        h.v = static_cast<float>(part[i]);
        h.primitive = primitive;
        n = insert_hit_sorted(hits, n, max_hits, h);
      }
    }
    return n;
  }

  // The candidate of `which` part closest to a float t (for surface_at, which refines the
  // stored float t to the double root it came from).
  TESSERA_HD double nearest(double t_float, std::uint32_t which) const {
    double best = t_float;
    double best_distance = -1.0;
    for (int i = 0; i < count; ++i) {
      if (part[i] != which) continue;
      const double distance = std::fabs(t[i] - t_float);
      if (best_distance < 0.0 || distance < best_distance) {
        best = t[i];
        best_distance = distance;
      }
    }
    // Only a root that rounds to (nearly) the stored t is the same hit.
    return best_distance >= 0.0 && best_distance <= 1e-5 * std::fabs(t_float) + 1e-30 ? best
                                                                                      : t_float;
  }
};

// The double root a HitCandidates hit came from: its float t plus the remainder closest()
// and all() keep in hit.u. A remainder is under one float ulp of t; anything larger is not
// one (a hit made by hand), and the float t stands.
TESSERA_HD TESSERA_INLINE double root_of_hit(const HitRecord& hit) {
  const double t = hit.t, remainder = hit.u;
  return std::fabs(remainder) <= 1.2e-7 * std::fabs(t) ? t + remainder : t;
}

TESSERA_HD TESSERA_INLINE float angle_fraction(double y, double x) {
  constexpr double kTwoPi = 6.283185307179586476925;
  double phi = std::atan2(y, x);
  if (phi < 0.0) phi += kTwoPi;
  return static_cast<float>(phi / kTwoPi);
}

}  // namespace tessera
