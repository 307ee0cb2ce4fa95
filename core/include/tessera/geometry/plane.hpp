#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// Infinite plane through `point` with unit `normal`. uv are the in-plane coordinates of
// the hit along the Duff et al. basis of the normal, divided by uv_scale (texture tiling).
struct Plane {
  vec3 point;
  vec3 normal;  // unit
  float uv_scale;
  std::uint32_t material;

  static Plane make(const vec3& point, const vec3& normal, std::uint32_t material,
                    float uv_scale = 1.0f) {
    return Plane{point, glm::normalize(normal), uv_scale, material};
  }
};

// An infinite plane has infinite bounds except along an axis it is perpendicular to;
// acceleration structures must keep planes outside their hierarchy (no finite box holds
// them), so this box is only informative.
TESSERA_HD TESSERA_INLINE Aabb bounds(const Plane& p) {
  Aabb box;
  for (int axis = 0; axis < 3; ++axis) {
    const bool perpendicular = std::fabs(p.normal[axis]) == 1.0f;
    box.lower[axis] = perpendicular ? p.point[axis] : -kInfinity;
    box.upper[axis] = perpendicular ? p.point[axis] : kInfinity;
  }
  return box;
}

namespace detail {
// t of the plane hit in double: dot(n, point - origin) is exact enough for any origin.
TESSERA_HD TESSERA_INLINE bool plane_hit_t(const vec3& point, const vec3& normal, const Ray& ray,
                                           double& t, double& margin) {
  const dvec3 n(normal);
  const dvec3 d(ray.direction);
  const double denominator = glm::dot(n, d);
  if (denominator == 0.0) return false;  // parallel (or zero direction): no hit, no 0/0
  const dvec3 to_point = dvec3(point) - dvec3(ray.origin);
  t = glm::dot(n, to_point) / denominator;
  margin = origin_margin(max_abs(dvec3(ray.origin)), glm::length(d));
  return std::isfinite(t);
}
}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Plane& p, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  double t, margin;
  if (!detail::plane_hit_t(p.point, p.normal, ray, t, margin)) return false;
  float tf;
  if (!accept_root(t, ray.t_min, t_max, margin, tf)) return false;
  hit.t = tf;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Plane& p, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(p, ray, t_max, hits[0], primitive) ? 1 : 0;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Plane& p, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = AxisFrame::from_axis(p.normal);
  const dvec3 local = frame.to_local(
      dvec3(ray.origin) + static_cast<double>(hit.t) * dvec3(ray.direction) - dvec3(p.point));
  // Project onto the plane: the ray-evaluated point is off it by the rounding of t.
  si.position = vec3(dvec3(p.point) + frame.u * local.x + frame.v * local.y);
  set_face_normal(si, ray.direction, p.normal);
  si.uv = vec2(static_cast<float>(local.x / p.uv_scale), static_cast<float>(local.y / p.uv_scale));
  si.material = p.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Plane&) {
  return kInfinity;
}

}  // namespace tessera
