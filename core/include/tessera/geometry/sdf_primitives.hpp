#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"

namespace tessera {

// Signed-distance primitives (exact Euclidean distances, so a sphere tracer may step by
// |distance| without passing through the surface). Each is placed by its own centre or
// endpoints; rotation and non-uniform scale come from Instance. Distances are evaluated in
// double on points relative to the primitive, like the analytic shapes.

// Box with half extents `half_extent`; rounding > 0 rounds its edges and corners with that
// radius while keeping the same outer size (a rounded box).
struct SdfBox {
  vec3 center;
  vec3 half_extent;
  float rounding;
  std::uint32_t material;
};

// Torus around the unit `axis` (major radius R, minor radius r; ring tori, r < R).
struct SdfTorus {
  vec3 center;
  vec3 axis;
  float major_radius;
  float minor_radius;
  std::uint32_t material;
};

// All points within `radius` of the segment from a to b.
struct SdfCapsule {
  vec3 a;
  vec3 b;
  float radius;
  std::uint32_t material;
};

// Distance from a point given relative to the primitive's reference point (centre, or a
// for the capsule).
TESSERA_HD TESSERA_INLINE double signed_distance(const SdfBox& box, const dvec3& p) {
  const double r = box.rounding;
  const dvec3 q = glm::abs(p) - (dvec3(box.half_extent) - dvec3(r));
  const dvec3 outside = glm::max(q, dvec3(0.0));
  return glm::length(outside) + glm::min(glm::max(q.x, glm::max(q.y, q.z)), 0.0) - r;
}

TESSERA_HD TESSERA_INLINE double signed_distance(const SdfTorus& torus, const dvec3& p) {
  const dvec3 w = glm::normalize(dvec3(torus.axis));
  const double z = glm::dot(p, w);
  const double rho = glm::length(p - z * w);
  const double R = torus.major_radius;
  return std::sqrt((rho - R) * (rho - R) + z * z) - torus.minor_radius;
}

TESSERA_HD TESSERA_INLINE double signed_distance(const SdfCapsule& capsule, const dvec3& p) {
  const dvec3 ab = dvec3(capsule.b) - dvec3(capsule.a);
  const double ab2 = glm::dot(ab, ab);
  const double h = ab2 > 0.0 ? glm::clamp(glm::dot(p, ab) / ab2, 0.0, 1.0) : 0.0;
  return glm::length(p - h * ab) - capsule.radius;
}

TESSERA_HD TESSERA_INLINE dvec3 sdf_reference_point(const SdfBox& b) {
  return dvec3(b.center);
}
TESSERA_HD TESSERA_INLINE dvec3 sdf_reference_point(const SdfTorus& t) {
  return dvec3(t.center);
}
TESSERA_HD TESSERA_INLINE dvec3 sdf_reference_point(const SdfCapsule& c) {
  return dvec3(c.a);
}

// Bounds relative to the reference point.
TESSERA_HD TESSERA_INLINE void sdf_local_bounds(const SdfBox& b, dvec3& lower, dvec3& upper) {
  upper = dvec3(b.half_extent);
  lower = -upper;
}
TESSERA_HD TESSERA_INLINE void sdf_local_bounds(const SdfTorus& t, dvec3& lower, dvec3& upper) {
  upper = circle_half_extent(glm::normalize(dvec3(t.axis)), t.major_radius) + dvec3(t.minor_radius);
  lower = -upper;
}
TESSERA_HD TESSERA_INLINE void sdf_local_bounds(const SdfCapsule& c, dvec3& lower, dvec3& upper) {
  const dvec3 ab = dvec3(c.b) - dvec3(c.a);
  lower = glm::min(dvec3(0.0), ab) - dvec3(c.radius);
  upper = glm::max(dvec3(0.0), ab) + dvec3(c.radius);
}

template <typename Sdf>
TESSERA_HD Aabb sdf_bounds(const Sdf& shape) {
  dvec3 lower, upper;
  sdf_local_bounds(shape, lower, upper);
  const dvec3 origin = sdf_reference_point(shape);
  return conservative_aabb(origin + lower, origin + upper);
}
TESSERA_HD TESSERA_INLINE Aabb bounds(const SdfBox& s) {
  return sdf_bounds(s);
}
TESSERA_HD TESSERA_INLINE Aabb bounds(const SdfTorus& s) {
  return sdf_bounds(s);
}
TESSERA_HD TESSERA_INLINE Aabb bounds(const SdfCapsule& s) {
  return sdf_bounds(s);
}

TESSERA_HD TESSERA_INLINE float surface_area(const SdfBox& b) {
  const double r = b.rounding;
  const dvec3 e = 2.0 * (dvec3(b.half_extent) - dvec3(r));  // flat face sizes
  const double faces = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  const double edges =
      3.14159265358979323846 * r * (e.x + e.y + e.z) * 2.0;     // 12 quarter cylinders
  const double corners = 4.0 * 3.14159265358979323846 * r * r;  // 8 eighth spheres
  return static_cast<float>(faces + edges + corners);
}
TESSERA_HD TESSERA_INLINE float surface_area(const SdfTorus& t) {
  return 4.0f * kPi * kPi * t.major_radius * t.minor_radius;
}
TESSERA_HD TESSERA_INLINE float surface_area(const SdfCapsule& c) {
  const float length = glm::length(c.b - c.a);
  return 2.0f * kPi * c.radius * length + 4.0f * kPi * c.radius * c.radius;
}

}  // namespace tessera
