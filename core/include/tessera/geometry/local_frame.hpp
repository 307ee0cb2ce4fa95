#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/ray.hpp"

namespace tessera {

// Shared by the analytic shapes (plane, disk, cylinder, cone, torus): the ray is taken into
// the shape's own frame in double before anything is subtracted, because the subtractions
// that decide hit or miss (origin minus centre, the perpendicular distance to an axis) lose
// the digits that matter when the origin is 1e4 to 1e6 shape sizes away. Every product of
// two floats is exact in double, so the local ray is accurate to ~1e-16 relative.

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

// The ray in a shape's frame, in double; t is unchanged by the change of frame.
struct LocalRay {
  dvec3 origin;
  dvec3 direction;
};

TESSERA_HD TESSERA_INLINE LocalRay to_local_ray(const Ray& ray, const vec3& center,
                                                const AxisFrame& frame) {
  return LocalRay{frame.to_local(dvec3(ray.origin) - dvec3(center)),
                  frame.to_local(dvec3(ray.direction))};
}

// Hits closer to the origin than a few float ulps of the coordinates involved are not
// hits: a ray that starts on a surface (to float precision) must not find that surface
// again at t ~ 0, whatever the sign the rounding gives that root. `scale` is the size of
// the coordinates the origin was rounded at (its largest world coordinate, plus the
// shape's extent for curved shapes whose double roots carry an error relative to their
// size). 2^-21 is 8 half-ulps of float, far below the 256-ulp offset of offset_ray_origin.
TESSERA_HD TESSERA_INLINE double origin_margin(double scale, double direction_length) {
  return 4.76837158203125e-07 * scale / direction_length;
}

// A root in double becomes a hit when its float t lies strictly inside the ray interval
// and beyond the origin margin.
TESSERA_HD TESSERA_INLINE bool accept_root(double t, float t_min, float t_max, double margin,
                                           float& t_out) {
  if (!(t > margin)) return false;
  const float tf = static_cast<float>(t);
  if (!(tf > t_min && tf < t_max)) return false;
  t_out = tf;
  return true;
}

// Largest absolute coordinate, the scale for origin_margin.
TESSERA_HD TESSERA_INLINE double max_abs(const dvec3& p) {
  return glm::max(std::fabs(p.x), glm::max(std::fabs(p.y), std::fabs(p.z)));
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

// Inserts t into the ascending list hits[0..count) keeping at most max_hits entries.
TESSERA_HD TESSERA_INLINE int insert_hit_sorted(HitRecord* hits, int count, int max_hits,
                                                const HitRecord& hit) {
  if (max_hits <= 0) return 0;
  int i = count < max_hits ? count : max_hits - 1;
  if (count >= max_hits && !(hit.t < hits[max_hits - 1].t)) return count;
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

  // Closest accepted root; the part goes to hit.v (as a small integer), hit.u is 0.
  TESSERA_HD bool closest(float t_min, float t_max, double margin, HitRecord& hit,
                          std::uint32_t primitive) const {
    bool found = false;
    float best = t_max;
    std::uint32_t best_part = 0;
    for (int i = 0; i < count; ++i) {
      float tf;
      if (accept_root(t[i], t_min, best, margin, tf)) {
        best = tf;
        best_part = part[i];
        found = true;
      }
    }
    if (!found) return false;
    hit.t = best;
    hit.u = 0.0f;
    hit.v = static_cast<float>(best_part);
    hit.primitive = primitive;
    return true;
  }

  TESSERA_HD int all(float t_min, float t_max, double margin, HitRecord* hits, int max_hits,
                     std::uint32_t primitive) const {
    int n = 0;
    for (int i = 0; i < count; ++i) {
      float tf;
      if (accept_root(t[i], t_min, t_max, margin, tf)) {
        HitRecord h;
        h.t = tf;
        h.u = 0.0f;
        h.v = static_cast<float>(part[i]);
        h.primitive = primitive;
        n = insert_hit_sorted(hits, n, max_hits, h);
      }
    }
    return n;
  }
};

TESSERA_HD TESSERA_INLINE float angle_fraction(double y, double x) {
  constexpr double kTwoPi = 6.283185307179586476925;
  double phi = std::atan2(y, x);
  if (phi < 0.0) phi += kTwoPi;
  return static_cast<float>(phi / kTwoPi);
}

}  // namespace tessera
