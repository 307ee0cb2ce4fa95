#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/geometry/local_frame.hpp"
#include "tessera/geometry/surface.hpp"
#include "tessera/geometry/transform.hpp"

namespace tessera {

// Any shape placed by an affine object-to-world transform (translate, rotate, scale,
// shear). The ray is mapped into object space with the direction left unnormalised, so t
// means the same thing in both spaces and hits from different instances compare directly.
// Normals go back to world space by the inverse transpose (the transpose of the
// world-to-object linear part), which keeps them perpendicular under non-uniform scale.
template <typename Shape>
struct Instance {
  Shape shape;
  AffineTransform object_to_world;
  AffineTransform world_to_object;
  // Per-instance constants of the error bounds, computed once by make() rather than at
  // every intersection test and hit: world_to_object's Frobenius norm (how far a world
  // origin's rounding can move the object-space origin) and object_to_world's largest
  // row sum of |linear| (how much an object-space position error grows in world space).
  double object_origin_error_gain = 0.0;
  double world_position_error_gain = 0.0;

  // Returns false (and leaves `out` alone) for a singular transform, which would map a
  // ray to a zero direction: such an instance must be rejected when the scene is built.
  static bool make(const Shape& shape, const AffineTransform& object_to_world, Instance& out) {
    const double det = object_to_world.determinant();
    if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) return false;
    const AffineTransform world_to_object = object_to_world.inverse();
    out = Instance{shape, object_to_world, world_to_object, world_to_object.frobenius_norm(),
                   object_to_world.max_error_gain()};
    return true;
  }
};

// Shapes that intersect a double-precision ray directly (the analytic ones); the others
// (triangle, quad) get the object-space ray rounded to float.
template <typename Shape>
concept PreciseIntersectable = requires(const Shape& shape, const PreciseRay& ray, HitRecord& hit) {
  intersect(shape, ray, 1.0f, hit, 0u);
};

// The world ray in object space, in double. The origin's uncertainty is carried over: the
// world origin's own (its float rounding) mapped through the linear part, bounded by the
// Frobenius norm.
template <typename Shape>
TESSERA_HD PreciseRay to_object_ray(const Instance<Shape>& instance, const Ray& ray) {
  const PreciseRay world = make_precise_ray(ray);
  return PreciseRay{instance.world_to_object.point(world.origin),
                    instance.world_to_object.vector(world.direction), ray.t_min,
                    world.origin_error * instance.object_origin_error_gain};
}

TESSERA_HD TESSERA_INLINE Ray to_float_ray(const PreciseRay& ray) {
  return Ray{vec3(ray.origin), vec3(ray.direction), ray.t_min, kInfinity};
}

template <typename Shape>
TESSERA_HD Aabb bounds(const Instance<Shape>& instance) {
  const Aabb local = bounds(instance.shape);
  dvec3 lower(kInfinity), upper(-kInfinity);
  for (int corner = 0; corner < 8; ++corner) {
    const dvec3 p((corner & 1) ? local.upper.x : local.lower.x,
                  (corner & 2) ? local.upper.y : local.lower.y,
                  (corner & 4) ? local.upper.z : local.lower.z);
    const dvec3 w = instance.object_to_world.point(p);
    lower = glm::min(lower, w);
    upper = glm::max(upper, w);
  }
  return conservative_aabb(lower, upper);
}

template <typename Shape>
TESSERA_HD bool intersect(const Instance<Shape>& instance, const Ray& ray, float t_max,
                          HitRecord& hit, std::uint32_t primitive) {
  const PreciseRay object = to_object_ray(instance, ray);
  if constexpr (PreciseIntersectable<Shape>) {
    return intersect(instance.shape, object, t_max, hit, primitive);
  } else {
    return intersect(instance.shape, to_float_ray(object), t_max, hit, primitive);
  }
}

template <typename Shape>
TESSERA_HD int intersect_all(const Instance<Shape>& instance, const Ray& ray, float t_max,
                             HitRecord* hits, int max_hits, std::uint32_t primitive) {
  const PreciseRay object = to_object_ray(instance, ray);
  if constexpr (PreciseIntersectable<Shape>) {
    return intersect_all(instance.shape, object, t_max, hits, max_hits, primitive);
  } else {
    return intersect_all(instance.shape, to_float_ray(object), t_max, hits, max_hits, primitive);
  }
}

template <typename Shape>
TESSERA_HD SurfaceInteraction surface_at(const Instance<Shape>& instance, const Ray& ray,
                                         const HitRecord& hit) {
  const PreciseRay object = to_object_ray(instance, ray);
  SurfaceInteraction si;
  if constexpr (PreciseIntersectable<Shape>) {
    si = surface_at(instance.shape, object, hit);
  } else {
    si = surface_at(instance.shape, to_float_ray(object), hit);
  }
  si.position = vec3(instance.object_to_world.point(dvec3(si.position)));
  si.position_error = transformed_position_error(si.position_error,
                                                 instance.world_position_error_gain, si.position);
  const glm::dmat3 normal_matrix = glm::transpose(instance.world_to_object.linear);
  // n . d is invariant under (M^-T n) . (M d), so the object-space orientation against the
  // ray (and front_face) carries over.
  const dvec3 geometric = normal_matrix * dvec3(si.geometric_normal);
  const dvec3 shading = normal_matrix * dvec3(si.shading_normal);
  si.geometric_normal = vec3(glm::normalize(geometric));
  si.shading_normal = vec3(glm::normalize(shading));
  return si;
}

// Exact for rigid motions and uniform scale (area times scale^2); for non-uniform scale
// the true factor depends on the shape's orientation and lies between the products of the
// two smallest and the two largest singular values: |det|^(2/3) is used as an estimate.
template <typename Shape>
TESSERA_HD float surface_area(const Instance<Shape>& instance) {
  const double det = std::fabs(instance.object_to_world.determinant());
  return static_cast<float>(surface_area(instance.shape) * std::cbrt(det * det));
}

}  // namespace tessera
