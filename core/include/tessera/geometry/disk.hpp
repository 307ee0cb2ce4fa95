#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/surface.hpp"

namespace tessera {

// Disk (or annulus when inner_radius > 0) around `center` in the plane with unit `normal`.
// uv: u = angle around the normal / 2 pi (from the Duff et al. basis), v = 0 at the inner
// edge to 1 at the rim.
struct Disk {
  vec3 center;
  vec3 normal;  // unit
  float radius;
  float inner_radius;
  std::uint32_t material;

  static Disk make(const vec3& center, const vec3& normal, float radius, std::uint32_t material,
                   float inner_radius = 0.0f) {
    return Disk{center, glm::normalize(normal), radius, inner_radius, material};
  }
};

TESSERA_HD TESSERA_INLINE Aabb bounds(const Disk& d) {
  const dvec3 c(d.center);
  const dvec3 e = circle_half_extent(dvec3(d.normal), d.radius);
  return conservative_aabb(c - e, c + e);
}

namespace detail {
TESSERA_HD TESSERA_INLINE HitCandidates<1> disk_candidates(const Disk& d, const PreciseRay& ray) {
  HitCandidates<1> out;
  // No area (zero radius, or an annulus of zero width): no surface to hit; without this a
  // ray through the centre, or exactly through the rim, hit it.
  if (!(d.radius > 0.0f && d.radius > d.inner_radius)) return out;
  const LocalRay local = to_local_ray(ray, d.center, AxisFrame::from_axis(d.normal));
  double t;
  if (!local_plane_root(local, 0.0, ray.origin_error, t)) return out;
  const double x = local.origin.x + t * local.direction.x;
  const double y = local.origin.y + t * local.direction.y;
  const double rho2 = x * x + y * y;
  const double r = d.radius, ri = d.inner_radius;
  if (rho2 <= r * r && rho2 >= ri * ri) out.add(t, 0);
  return out;
}
}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Disk& d, const PreciseRay& ray, float t_max,
                                         HitRecord& hit, std::uint32_t primitive) {
  return detail::disk_candidates(d, ray).closest(ray.t_min, t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE bool intersect(const Disk& d, const Ray& ray, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  return intersect(d, make_precise_ray(ray), t_max, hit, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Disk& d, const PreciseRay& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return detail::disk_candidates(d, ray).all(ray.t_min, t_max, hits, max_hits, primitive);
}
TESSERA_HD TESSERA_INLINE int intersect_all(const Disk& d, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  return intersect_all(d, make_precise_ray(ray), t_max, hits, max_hits, primitive);
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Disk& d, const PreciseRay& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = AxisFrame::from_axis(d.normal);
  const double t = detail::disk_candidates(d, ray).nearest(hit.t, 0);
  const dvec3 local = frame.to_local(ray.origin + t * ray.direction - dvec3(d.center));
  si.position = vec3(dvec3(d.center) + frame.u * local.x + frame.v * local.y);
  set_face_normal(si, vec3(ray.direction), d.normal);
  const double rho = std::sqrt(local.x * local.x + local.y * local.y);
  const double width = static_cast<double>(d.radius) - d.inner_radius;
  si.uv =
      vec2(angle_fraction(local.y, local.x),
           width > 0.0 ? static_cast<float>(glm::clamp((rho - d.inner_radius) / width, 0.0, 1.0))
                       : 0.0f);
  si.material = d.material;
  return si;
}
TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Disk& d, const Ray& ray,
                                                        const HitRecord& hit) {
  return surface_at(d, make_precise_ray(ray), hit);
}

TESSERA_HD TESSERA_INLINE float surface_area(const Disk& d) {
  return kPi * (d.radius * d.radius - d.inner_radius * d.inner_radius);
}

}  // namespace tessera
