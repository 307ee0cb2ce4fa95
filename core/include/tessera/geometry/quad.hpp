#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/math/offset_ray.hpp"

namespace tessera {

// Parallelogram corner + s*u + t*v, s,t in [0,1] (RayON's `rectangle`).
struct Quad {
  vec3 corner;
  vec3 u;
  vec3 v;
  vec3 normal;  // unit, along u x v
  vec3 w;       // (u x v) / |u x v|^2: maps a plane point to (s, t) with two dot products
  std::uint32_t material;
  // The plane and the parallelogram's coordinates in double, formed once here instead of
  // per ray: the unit normal, and the vectors whose dot products with a plane point
  // relative to the corner give s and t ((v x n) / |n|^2 and (n x u) / |n|^2 for
  // n = u x v; from the triple product (p x v) . n = p . (v x n)). All zero for a
  // degenerate quad, which no ray then hits.
  dvec3 plane_normal{0.0};
  dvec3 s_axis{0.0};
  dvec3 t_axis{0.0};
  // For a rectangle (|u . v| <= 1e-4 |u| |v|), which lights sample by its solid angle: the
  // unit edge directions and the edge lengths, so the per-sample frame costs no square roots
  // or divisions. Zero lengths when the quad is not one.
  vec3 u_direction{0.0f};
  vec3 v_direction{0.0f};
  float u_length = 0.0f;
  float v_length = 0.0f;

  TESSERA_HD bool is_rectangle() const { return u_length > 0.0f; }

  static Quad make(const vec3& corner, const vec3& u, const vec3& v, std::uint32_t material) {
    const vec3 n = glm::cross(u, v);
    Quad q{};
    q.corner = corner;
    q.u = u;
    q.v = v;
    q.normal = glm::normalize(n);
    q.w = n / glm::dot(n, n);
    q.material = material;
    // Products of floats are exact in double, so n_d is u x v rounded once.
    const dvec3 n_d = glm::cross(dvec3(u), dvec3(v));
    const double n2 = glm::dot(n_d, n_d);
    if (n2 > 0.0 && std::isfinite(n2)) {
      q.plane_normal = n_d / std::sqrt(n2);
      q.s_axis = glm::cross(dvec3(v), n_d) / n2;
      q.t_axis = glm::cross(n_d, dvec3(u)) / n2;
    }
    const float uu = glm::dot(u, u), vv = glm::dot(v, v), uv = glm::dot(u, v);
    if (uv * uv <= 1e-8f * uu * vv && uu > 0.0f && vv > 0.0f && std::isfinite(uu * vv)) {
      q.u_length = std::sqrt(uu);
      q.v_length = std::sqrt(vv);
      q.u_direction = u / q.u_length;
      q.v_direction = v / q.v_length;
    }
    return q;
  }
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Quad& q) {
  Aabb b;
  b.extend(q.corner);
  b.extend(q.corner + q.u);
  b.extend(q.corner + q.v);
  b.extend(q.corner + q.u + q.v);
  return b;
}

// Plane hit and parallelogram coordinates in double: the hit point relative to the corner
// is formed as (origin - corner) + t d without rounding to float first, which for origins
// far away (1e5 quad sizes) would otherwise move the point by ulps of the origin and flip
// decisions near the edges. A ray starting on the quad's plane (within its origin's
// uncertainty) does not hit it again.
TESSERA_HD TESSERA_INLINE bool intersect(const Quad& q, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  const double denominator = glm::dot(q.plane_normal, ray.direction);
  if (denominator == 0.0) return false;  // parallel, or a degenerate quad: no 0/0
  const dvec3 offset = ray.origin - dvec3(q.corner);
  const double height = glm::dot(q.plane_normal, offset);
  if (std::fabs(height) <= ray.origin_error) return false;  // starts on it
  const double t = -height / denominator;
  float tf;
  if (!accept_root(t, ray.t_min, t_max, tf)) return false;
  const dvec3 planar = offset + t * ray.direction;
  const double s = glm::dot(planar, q.s_axis);
  const double r = glm::dot(planar, q.t_axis);
  if (!(s >= 0.0 && s <= 1.0 && r >= 0.0 && r <= 1.0)) return false;
  hit.t = tf;
  hit.u = static_cast<float>(s);
  hit.v = static_cast<float>(r);
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE bool intersect(const Quad& q, const Ray& ray, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  return intersect(q, make_precise_ray(ray), t_max, hit, primitive);
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Quad& q, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(q, ray, t_max, hits[0], primitive) ? 1 : 0;
}

// A flat shape is hit at most once: the sorted list of all hits is the closest hit.
TESSERA_HD TESSERA_INLINE int intersect_all(const Quad& q, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(q, ray, t_max, hits[0], primitive) ? 1 : 0;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Quad& q, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  si.position = q.corner + hit.u * q.u + hit.v * q.v;
  // As a triangle's (triangle.hpp): roundings of the largest coordinate on the quad.
  const vec3 largest = glm::abs(q.corner) + glm::abs(q.u) + glm::abs(q.v);
  si.position_error = position_error_bound(max_component(largest));
  set_face_normal(si, ray.direction, q.normal);
  si.uv = vec2(hit.u, hit.v);
  si.material = q.material;
  return si;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Quad& q, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  return surface_at(q, Ray{vec3(ray.origin), vec3(ray.direction), ray.t_min, kInfinity}, hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Quad& q) {
  return glm::length(glm::cross(q.u, q.v));
}

}  // namespace tessera
