#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera {

// The watertight test of triangle.hpp (Woop, Benthin and Wald 2013) evaluated in double on
// a PreciseRay. The float version is the fast path for meshes in the BVH; this one is for
// callers that need decisions exact to the float inputs far from the origin (the float
// edge functions of a 1-unit triangle seen from 1e6 units away are uncertain by ~6% of its
// size) and for instances, whose object-space ray is never rounded to float. The algorithm
// is the same, so it is watertight the same way: shared edges give bit-identical edge
// functions in both triangles. A ray whose origin lies on the triangle's plane (within the
// origin's uncertainty) does not hit it again.
TESSERA_HD TESSERA_INLINE bool intersect(const Triangle& tri, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  const dvec3& d = ray.direction;
  const dvec3 ad = glm::abs(d);
  const int kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz + 1 == 3 ? 0 : kz + 1;
  int ky = kx + 1 == 3 ? 0 : kx + 1;
  if (d[kz] == 0.0) return false;  // zero direction
  if (d[kz] < 0.0) {
    const int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  const double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  const dvec3 a = dvec3(tri.p0) - ray.origin;
  const dvec3 b = dvec3(tri.p1) - ray.origin;
  const dvec3 c = dvec3(tri.p2) - ray.origin;
  const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  const double u = cx * by - cy * bx;
  const double v = ax * cy - ay * cx;
  const double w = bx * ay - by * ax;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  const double det = u + v + w;
  if (det == 0.0) return false;  // degenerate or edge-on: no hit, no NaN
  const double t = (u * a[kz] + v * b[kz] + w * c[kz]) * sz / det;
  float tf;
  if (!accept_root(t, ray.t_min, t_max, tf)) return false;
  // Starts on the triangle's plane: the origin's distance to it within its uncertainty.
  const dvec3 n = glm::cross(b - a, c - a);
  const double n_length = glm::length(n);
  if (std::fabs(glm::dot(n, a)) <= ray.origin_error * n_length) return false;
  // Zero or near-zero area (see is_degenerate): never a hit, as in the float test.
  if (is_degenerate(tri)) return false;
  hit.t = tf;
  hit.u = static_cast<float>(v / det);
  hit.v = static_cast<float>(w / det);
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Triangle& tri, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(tri, ray, t_max, hits[0], primitive) ? 1 : 0;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Triangle& tri, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  return surface_at(tri, Ray{vec3(ray.origin), vec3(ray.direction), ray.t_min, kInfinity}, hit);
}

// The double path for a float ray, for callers that want it directly.
TESSERA_HD TESSERA_INLINE bool intersect_precise(const Triangle& tri, const Ray& ray, float t_max,
                                                 HitRecord& hit, std::uint32_t primitive) {
  return intersect(tri, make_precise_ray(ray), t_max, hit, primitive);
}

}  // namespace tessera
