#pragma once
#include <cstdint>

#include "tessera/accel/bvh.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/triangle.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/material.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {

// Primitive references carry their shape type in the top two bits so one BVH can hold a
// mix of shapes stored in flat arrays, one array per type.
enum class PrimitiveType : std::uint32_t { kSphere = 0, kQuad = 1, kTriangle = 2 };
inline constexpr std::uint32_t kPrimitiveIndexMask = 0x3fffffffU;

TESSERA_HD TESSERA_INLINE std::uint32_t make_primitive_ref(PrimitiveType type,
                                                           std::uint32_t index) {
  return (static_cast<std::uint32_t>(type) << 30) | index;
}
TESSERA_HD TESSERA_INLINE PrimitiveType primitive_type(std::uint32_t ref) {
  return static_cast<PrimitiveType>(ref >> 30);
}
TESSERA_HD TESSERA_INLINE std::uint32_t primitive_index(std::uint32_t ref) {
  return ref & kPrimitiveIndexMask;
}

struct LightSource {
  std::uint32_t primitive;  // tagged reference
  float area;
};

// Read-only view of the render scene: plain pointers into arrays that live for the job,
// valid on the host or, once uploaded, on a device.
struct SceneView {
  const Sphere* spheres = nullptr;
  const Quad* quads = nullptr;
  const Triangle* triangles = nullptr;
  const Material* materials = nullptr;
  const LightSource* lights = nullptr;
  std::uint32_t light_count = 0;
  BvhView bvh;
  Camera camera;
  vec3 background{0.0f};
};

// Intersection program for the shape types in kShapes; the others compile to nothing.
template <unsigned kShapes>
struct SceneIntersection {
  static constexpr unsigned kShapeMask = kShapes;
  const Sphere* spheres;
  const Quad* quads;
  const Triangle* triangles;

  TESSERA_HD bool intersect(std::uint32_t primitive, const Ray& ray, float t_max,
                            HitRecord& hit) const {
    const std::uint32_t index = primitive_index(primitive);
    switch (primitive_type(primitive)) {
      case PrimitiveType::kSphere:
        if constexpr ((kShapes & kShapeSphere) != 0)
          return tessera::intersect(spheres[index], ray, t_max, hit, primitive);
        break;
      case PrimitiveType::kQuad:
        if constexpr ((kShapes & kShapeQuad) != 0)
          return tessera::intersect(quads[index], ray, t_max, hit, primitive);
        break;
      case PrimitiveType::kTriangle:
        if constexpr ((kShapes & kShapeTriangle) != 0)
          return tessera::intersect(triangles[index], ray, t_max, hit, primitive);
        break;
    }
    return false;
  }

  // Both crossings of a sphere, one hit for flat shapes: what multi-hit queries need.
  TESSERA_HD int intersect_all(std::uint32_t primitive, const Ray& ray, float t_max,
                               HitRecord* hits, int max_hits) const {
    if (max_hits <= 0 || !intersect(primitive, ray, t_max, hits[0])) return 0;
    if (primitive_type(primitive) != PrimitiveType::kSphere || max_hits < 2) return 1;
    Ray beyond = ray;
    beyond.t_min = hits[0].t;
    return intersect(primitive, beyond, t_max, hits[1]) ? 2 : 1;
  }
};

template <unsigned kShapes>
TESSERA_HD SurfaceInteraction surface_at(const SceneView& scene, const Ray& ray,
                                         const HitRecord& hit) {
  const std::uint32_t index = primitive_index(hit.primitive);
  switch (primitive_type(hit.primitive)) {
    case PrimitiveType::kSphere:
      if constexpr ((kShapes & kShapeSphere) != 0)
        return surface_at(scene.spheres[index], ray, hit);
      break;
    case PrimitiveType::kQuad:
      if constexpr ((kShapes & kShapeQuad) != 0) return surface_at(scene.quads[index], ray, hit);
      break;
    case PrimitiveType::kTriangle:
      if constexpr ((kShapes & kShapeTriangle) != 0)
        return surface_at(scene.triangles[index], ray, hit);
      break;
  }
  return SurfaceInteraction{};
}

}  // namespace tessera
