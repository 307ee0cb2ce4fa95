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

// Root of a plane z = z_plane in a local frame, unless it is the plane the ray starts on.
TESSERA_HD TESSERA_INLINE bool local_plane_root(const LocalRay& local, double z_plane, double band,
                                                double& t) {
  if (local.direction.z == 0.0) return false;  // parallel (or zero direction): no 0/0
  t = (z_plane - local.origin.z) / local.direction.z;
  if (!std::isfinite(t)) return false;
  const auto height = [z_plane](const dvec3& p) { return p.z - z_plane; };
  return !is_start_surface_root(height, local.origin.z - z_plane, local, t, band);
}

TESSERA_HD TESSERA_INLINE HitCandidates<1> plane_candidates(const Plane& p, const PreciseRay& ray) {
  HitCandidates<1> out;
  const LocalRay local = to_local_ray(ray, p.point, AxisFrame::from_axis(p.normal));
  double t;
  if (local_plane_root(local, 0.0, ray.origin_error, t)) out.add(t, 0);
  return out;
}

}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Plane& p, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::plane_candidates(p, ray).closest(ray.t_min, t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE bool intersect(const Plane& p, const Ray& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return intersect(p, make_precise_ray(ray), t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Plane& p, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::plane_candidates(p, ray).all(ray.t_min, t_max, hits, max_hits, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Plane& p, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(p, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Plane& p, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = AxisFrame::from_axis(p.normal);
  const double t = detail::plane_candidates(p, ray).nearest(hit.t, 0);
  const dvec3 local = frame.to_local(ray.origin + t * ray.direction - dvec3(p.point));
  // Project onto the plane: the ray-evaluated point is off it by the rounding of t.
  si.position = vec3(dvec3(p.point) + frame.u * local.x + frame.v * local.y);
  set_face_normal(si, vec3(ray.direction), p.normal);
  si.uv = vec2(static_cast<float>(local.x / p.uv_scale), static_cast<float>(local.y / p.uv_scale));
  si.material = p.material;
  return si;
}
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Plane& p, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(p, make_precise_ray(ray), hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Plane&) {
  return kInfinity;
}

}  // namespace tessera
