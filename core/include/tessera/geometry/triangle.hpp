#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/offset_ray.hpp"

namespace tessera {

struct Triangle {
  vec3 p0, p1, p2;
  std::uint32_t material;
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Triangle& tri) {
  Aabb b;
  b.extend(tri.p0);
  b.extend(tri.p1);
  b.extend(tri.p2);
  return b;
}

// A triangle is degenerate when its height over its longest edge is at most this fraction of
// that edge (twice its area at most kDegenerateTriangleHeight * longest^2): 16 times float's
// rounding unit 2^-24.
// Such a triangle has no surface a float test can find: sheared into the ray's frame, its
// rounded vertices are collinear up to noise, the edge functions come out with the same sign
// by chance and the determinant and t are noise over noise; its normal has no reliable
// direction either. Real slivers (CAD strips of 1:10^4) are a hundred times above it.
inline constexpr double kDegenerateTriangleHeight = 0x1p-20;

// Decided in double from the float vertices (their differences are exact for all but
// extreme exponent gaps), so it neither overflows nor underflows for any finite float
// triangle. Non-finite vertices count as degenerate. Also used by the accelerators, which
// drop these triangles at build time.
TESSERA_HD TESSERA_INLINE bool is_degenerate(const Triangle& tri) {
  const dvec3 p0(tri.p0), p1(tri.p1), p2(tri.p2);
  const dvec3 e0 = p1 - p0, e1 = p2 - p0, e2 = p2 - p1;
  const dvec3 n = glm::cross(e0, e1);
  const double l0 = glm::dot(e0, e0), l1 = glm::dot(e1, e1), l2 = glm::dot(e2, e2);
  const double longest2 = l0 > l1 ? (l0 > l2 ? l0 : l2) : (l1 > l2 ? l1 : l2);
  constexpr double k2 = kDegenerateTriangleHeight * kDegenerateTriangleHeight;
  // |n|^2 > k^2 longest^4, written so that NaN (and inf) compare false: degenerate.
  return !(glm::dot(n, n) > k2 * longest2 * longest2);
}

// Per-ray constants of the watertight test: the axis permutation that makes the largest
// direction component z, and the shear that maps the ray onto +z.
struct WatertightRay {
  int kx, ky, kz;
  float sx, sy, sz;

  TESSERA_HD explicit WatertightRay(const vec3& d) {
    const vec3 a = glm::abs(d);
    kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = kz + 1 == 3 ? 0 : kz + 1;
    ky = kx + 1 == 3 ? 0 : kx + 1;
    if (d[kz] < 0.0f) {  // keep winding: swap x and y
      const int tmp = kx;
      kx = ky;
      ky = tmp;
    }
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0f / d[kz];
  }
};

// Watertight ray/triangle intersection (Woop, Benthin and Wald, JCGT 2013): edge functions
// are evaluated in a ray-aligned frame, so a ray through a shared edge or vertex hits at
// least one of the triangles sharing it. When an edge function is exactly zero it is
// recomputed in double, as the paper prescribes, so the sign decision is exact.
TESSERA_HD TESSERA_INLINE bool intersect(const Triangle& tri, const Ray& ray,
                                         const WatertightRay& wr, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  const vec3 a = tri.p0 - ray.origin;
  const vec3 b = tri.p1 - ray.origin;
  const vec3 c = tri.p2 - ray.origin;
  const float ax = a[wr.kx] - wr.sx * a[wr.kz];
  const float ay = a[wr.ky] - wr.sy * a[wr.kz];
  const float bx = b[wr.kx] - wr.sx * b[wr.kz];
  const float by = b[wr.ky] - wr.sy * b[wr.kz];
  const float cx = c[wr.kx] - wr.sx * c[wr.kz];
  const float cy = c[wr.ky] - wr.sy * c[wr.kz];
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  if (u == 0.0f || v == 0.0f || w == 0.0f) {
    u = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
    v = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
    w = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
  }
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const float det = u + v + w;
  if (det == 0.0f) return false;  // degenerate (zero-area or edge-on): no hit, no NaN
  const float az = wr.sz * a[wr.kz];
  const float bz = wr.sz * b[wr.kz];
  const float cz = wr.sz * c[wr.kz];
  const float t_scaled = u * az + v * bz + w * cz;
  const float inv_det = 1.0f / det;
  const float t = t_scaled * inv_det;
  if (!(t > ray.t_min && t < t_max)) return false;
  // Degenerate triangles are rejected here, last, so only a hit about to be reported pays for
  // the check, never a miss. The accelerators drop them at build time instead (their SIMD
  // kernels stay as they were); this keeps every other caller (GPU, BvhTracer, brute-force
  // references) from reporting them.
  if (is_degenerate(tri)) return false;
  hit.t = t;
  hit.u = v * inv_det;  // weight of p1
  hit.v = w * inv_det;  // weight of p2
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE bool intersect(const Triangle& tri, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(tri, ray, WatertightRay(ray.direction), t_max, hit, primitive);
}

// A flat shape is hit at most once: the sorted list of all hits is the closest hit.
TESSERA_HD TESSERA_INLINE int intersect_all(const Triangle& tri, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(tri, ray, t_max, hits[0], primitive) ? 1 : 0;
}

// The unit normal of the winding (p1 - p0) x (p2 - p0). Float first; when its squared length
// leaves float's normal range (triangles below ~1e-10 or above ~1e10 units, where the
// square underflows or overflows) the cross product is redone in double, where every finite
// float triangle's normal is representable (|n|^2 < 1e156). Only a degenerate triangle, which
// intersect never reports, has none: it gets the normal facing the ray, so shading sees no NaN.
TESSERA_HD TESSERA_INLINE vec3 geometric_normal(const Triangle& tri, const vec3& ray_direction) {
  const vec3 n = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
  const float len2 = glm::dot(n, n);
  if (len2 >= 0x1p-126f && len2 <= 0x1.fffffep+127f) return n / std::sqrt(len2);
  const dvec3 nd = glm::cross(dvec3(tri.p1) - dvec3(tri.p0), dvec3(tri.p2) - dvec3(tri.p0));
  const double len2d = glm::dot(nd, nd);
  if (len2d > 0.0) return vec3(nd / std::sqrt(len2d));
  return -glm::normalize(ray_direction);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Triangle& tri, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const float b0 = 1.0f - hit.u - hit.v;
  si.position = b0 * tri.p0 + hit.u * tri.p1 + hit.v * tri.p2;
  // The point is off the plane by roundings of the corners' magnitude (and so is the next
  // ray's test of this triangle), however near the origin the point itself lies.
  const vec3 largest = glm::max(glm::abs(tri.p0), glm::max(glm::abs(tri.p1), glm::abs(tri.p2)));
  si.position_error = position_error_bound(max_component(largest));
  set_face_normal(si, ray.direction, geometric_normal(tri, ray.direction));
  si.uv = vec2(hit.u, hit.v);
  si.material = tri.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Triangle& tri) {
  return 0.5f * glm::length(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
}

}  // namespace tessera
