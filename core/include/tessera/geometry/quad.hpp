#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// Parallelogram corner + s*u + t*v, s,t in [0,1] (RayON's `rectangle`).
struct Quad {
  vec3 corner;
  vec3 u;
  vec3 v;
  vec3 normal;  // unit, along u x v
  vec3 w;       // (u x v) / |u x v|^2: maps a plane point to (s, t) with two dot products
  std::uint32_t material;

  static Quad make(const vec3& corner, const vec3& u, const vec3& v, std::uint32_t material) {
    const vec3 n = glm::cross(u, v);
    return Quad{corner, u, v, glm::normalize(n), n / glm::dot(n, n), material};
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

TESSERA_HD TESSERA_INLINE bool intersect(const Quad& q, const Ray& ray, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  const float denom = glm::dot(q.normal, ray.direction);
  if (denom == 0.0f) return false;  // parallel: no hit, and no 0/0 below
  const float t = glm::dot(q.normal, q.corner - ray.origin) / denom;
  if (!(t > ray.t_min && t < t_max)) return false;
  const vec3 planar = ray.origin + t * ray.direction - q.corner;
  const float s = glm::dot(q.w, glm::cross(planar, q.v));
  const float r = glm::dot(q.w, glm::cross(q.u, planar));
  if (!(s >= 0.0f && s <= 1.0f && r >= 0.0f && r <= 1.0f)) return false;
  hit.t = t;
  hit.u = s;
  hit.v = r;
  hit.primitive = primitive;
  return true;
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
  set_face_normal(si, ray.direction, q.normal);
  si.uv = vec2(hit.u, hit.v);
  si.material = q.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Quad& q) {
  return glm::length(glm::cross(q.u, q.v));
}

}  // namespace tessera
