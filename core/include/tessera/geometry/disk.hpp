#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
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
// Plane hit of a disk-shaped cap at `center` with normal `normal`: t and squared radial
// distance of the hit, all in double.
TESSERA_HD TESSERA_INLINE bool disk_hit(const dvec3& center, const dvec3& normal,
                                        const dvec3& origin, const dvec3& direction, double& t,
                                        double& radius2) {
  const double denominator = glm::dot(normal, direction);
  if (denominator == 0.0) return false;
  const dvec3 to_center = center - origin;
  t = glm::dot(normal, to_center) / denominator;
  if (!std::isfinite(t)) return false;
  // Offset of the hit from the centre: (origin - center) + t d, evaluated as one sum so the
  // in-plane distance is not the difference of two large numbers when t d is large.
  const dvec3 offset = t * direction - to_center;
  const dvec3 in_plane = offset - glm::dot(offset, normal) * normal;
  radius2 = glm::dot(in_plane, in_plane);
  return true;
}
}  // namespace detail

TESSERA_HD TESSERA_INLINE bool intersect(const Disk& d, const Ray& ray, float t_max, HitRecord& hit,
                                         std::uint32_t primitive) {
  double t, radius2;
  if (!detail::disk_hit(dvec3(d.center), dvec3(d.normal), dvec3(ray.origin), dvec3(ray.direction),
                        t, radius2))
    return false;
  const double r = d.radius, ri = d.inner_radius;
  if (!(radius2 <= r * r && radius2 >= ri * ri)) return false;
  float tf;
  const double margin =
      origin_margin(max_abs(dvec3(ray.origin)), glm::length(dvec3(ray.direction)));
  if (!accept_root(t, ray.t_min, t_max, margin, tf)) return false;
  hit.t = tf;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.primitive = primitive;
  return true;
}

TESSERA_HD TESSERA_INLINE int intersect_all(const Disk& d, const Ray& ray, float t_max,
                                            HitRecord* hits, int max_hits,
                                            std::uint32_t primitive) {
  if (max_hits <= 0) return 0;
  return intersect(d, ray, t_max, hits[0], primitive) ? 1 : 0;
}

TESSERA_HD TESSERA_INLINE SurfaceInteraction surface_at(const Disk& d, const Ray& ray,
                                                        const HitRecord& hit) {
  SurfaceInteraction si;
  const AxisFrame frame = AxisFrame::from_axis(d.normal);
  const dvec3 local = frame.to_local(
      dvec3(ray.origin) + static_cast<double>(hit.t) * dvec3(ray.direction) - dvec3(d.center));
  si.position = vec3(dvec3(d.center) + frame.u * local.x + frame.v * local.y);
  set_face_normal(si, ray.direction, d.normal);
  const double rho = std::sqrt(local.x * local.x + local.y * local.y);
  const double width = static_cast<double>(d.radius) - d.inner_radius;
  si.uv =
      vec2(angle_fraction(local.y, local.x),
           width > 0.0 ? static_cast<float>(glm::clamp((rho - d.inner_radius) / width, 0.0, 1.0))
                       : 0.0f);
  si.material = d.material;
  return si;
}

TESSERA_HD TESSERA_INLINE float surface_area(const Disk& d) {
  return kPi * (d.radius * d.radius - d.inner_radius * d.inner_radius);
}

}  // namespace tessera
