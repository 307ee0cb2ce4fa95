#pragma once
#include <cstdint>

#include "tessera/accel/bvh.hpp"
#include "tessera/geometry/cone.hpp"
#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/disk.hpp"
#include "tessera/geometry/instance.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sdf_primitives.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/sphere_tracing.hpp"
#include "tessera/geometry/spline_patch.hpp"
#include "tessera/geometry/torus.hpp"
#include "tessera/geometry/triangle.hpp"
#include "tessera/geometry/triangle_attributes.hpp"
#include "tessera/geometry/trimmed_face.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/material.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {

// Primitive references carry their shape type in the top five bits, the index into that
// type's flat array in the other 27, so one BVH can hold a mix of shapes. 27 bits hold
// 134 million primitives per type, above SceneLimits::max_triangles and
// max_shapes_per_type (validate_scene rejects scenes beyond them).
//
// Transformed shapes are baked into the same type where it can represent the result
// (prepared_scene.cpp); what it cannot (curved shapes under non-uniform scale, every
// transformed signed-distance primitive) becomes an Instance<Shape>. Each Instance<Shape>
// type has its own flat array and primitive type, but they all share one ShapeBit,
// kShapeInstance: a bit per instanced type would double the masks for nothing, since the
// compiled shape classes (pipeline_features.hpp) put every non-trivial shape in "all".
// Patches (kShapePatch) hold their transform baked into the control points. Trimmed faces
// (kShapeTrimmed) are always instances (identity when untransformed): a trim region is in
// the surface's own uv, which most baked transforms would change, and one stored form per
// surface type keeps the primitive types at 28 of the 32 the tag bits hold.
enum class PrimitiveType : std::uint32_t {
  kSphere = 0,
  kQuad,
  kTriangle,
  kPlane,  // never in the BVH: SceneIntersection tests planes per ray
  kDisk,
  kCylinder,
  kCone,
  kTorus,
  kSdfBox,
  kSdfTorus,
  kSdfCapsule,
  kSphereInstance,
  kDiskInstance,
  kCylinderInstance,
  kConeInstance,
  kTorusInstance,
  kSdfBoxInstance,
  kSdfTorusInstance,
  kSdfCapsuleInstance,
  kSplinePatch,
  kTrimmedPlane,
  kTrimmedDisk,
  kTrimmedQuad,
  kTrimmedSphere,
  kTrimmedCylinder,
  kTrimmedCone,
  kTrimmedTorus,
  kTrimmedPatch,
};
inline constexpr std::uint32_t kPrimitiveTypeShift = 27;
inline constexpr std::uint32_t kPrimitiveIndexMask = (1u << kPrimitiveTypeShift) - 1u;
static_assert(static_cast<std::uint32_t>(PrimitiveType::kTrimmedPatch) <
                  (1u << (32 - kPrimitiveTypeShift)),
              "primitive types must fit the tag bits");

TESSERA_HD TESSERA_INLINE std::uint32_t make_primitive_ref(PrimitiveType type,
                                                           std::uint32_t index) {
  return (static_cast<std::uint32_t>(type) << kPrimitiveTypeShift) | index;
}
TESSERA_HD TESSERA_INLINE PrimitiveType primitive_type(std::uint32_t ref) {
  return static_cast<PrimitiveType>(ref >> kPrimitiveTypeShift);
}
TESSERA_HD TESSERA_INLINE std::uint32_t primitive_index(std::uint32_t ref) {
  return ref & kPrimitiveIndexMask;
}

// Emitters with an area sampler for next-event estimation. Other emitting shapes are not
// in SceneView::lights; the path tracer counts their emission when a scattered ray hits
// them, so every emitter is counted by exactly one strategy.
TESSERA_HD TESSERA_INLINE bool has_light_sampler(PrimitiveType type) {
  return type == PrimitiveType::kSphere || type == PrimitiveType::kQuad ||
         type == PrimitiveType::kTriangle || type == PrimitiveType::kDisk;
}

struct LightSource {
  std::uint32_t primitive;  // tagged reference
  float area;
};

// The flat shape arrays of a render scene, one per primitive type. Planes carry a count
// because they are tested one by one rather than found through the BVH.
struct SceneShapes {
  const Sphere* spheres = nullptr;
  const Quad* quads = nullptr;
  const Triangle* triangles = nullptr;
  // Per-vertex normals and uvs, indexed like `triangles`; null when no mesh has any (then
  // triangles shade flat, with barycentric uvs).
  const TriangleAttributes* triangle_attributes = nullptr;
  const Plane* planes = nullptr;
  std::uint32_t plane_count = 0;
  const Disk* disks = nullptr;
  const Cylinder* cylinders = nullptr;
  const Cone* cones = nullptr;
  const Torus* tori = nullptr;
  const SdfBox* sdf_boxes = nullptr;
  const SdfTorus* sdf_tori = nullptr;
  const SdfCapsule* sdf_capsules = nullptr;
  const Instance<Sphere>* sphere_instances = nullptr;
  const Instance<Disk>* disk_instances = nullptr;
  const Instance<Cylinder>* cylinder_instances = nullptr;
  const Instance<Cone>* cone_instances = nullptr;
  const Instance<Torus>* torus_instances = nullptr;
  const Instance<SdfBox>* sdf_box_instances = nullptr;
  const Instance<SdfTorus>* sdf_torus_instances = nullptr;
  const Instance<SdfCapsule>* sdf_capsule_instances = nullptr;
  // Patches and trimmed faces point into pools (Bézier pieces, trim loops) that live as
  // long as these arrays.
  const SplinePatch* patches = nullptr;
  const Instance<Trimmed<Plane>>* trimmed_planes = nullptr;
  const Instance<Trimmed<Disk>>* trimmed_disks = nullptr;
  const Instance<Trimmed<Quad>>* trimmed_quads = nullptr;
  const Instance<Trimmed<Sphere>>* trimmed_spheres = nullptr;
  const Instance<Trimmed<Cylinder>>* trimmed_cylinders = nullptr;
  const Instance<Trimmed<Cone>>* trimmed_cones = nullptr;
  const Instance<Trimmed<Torus>>* trimmed_tori = nullptr;
  const Instance<Trimmed<SplinePatch>>* trimmed_patches = nullptr;
};

// Read-only view of the render scene: plain pointers into arrays that live for the job,
// valid on the host or, once uploaded, on a device.
struct SceneView : SceneShapes {
  const Material* materials = nullptr;
  const LightSource* lights = nullptr;
  std::uint32_t light_count = 0;
  BvhView bvh;
  Camera camera;
  vec3 background{0.0f};
};

namespace scene_detail {

// Calls `fn(shape)` with the shape `primitive` names, for the types in kShapes; returns
// `fallback` for the others (they compile to nothing). One `if constexpr` per ShapeBit.
template <unsigned kShapes, typename R, typename Fn>
TESSERA_HD R dispatch(const SceneShapes& s, std::uint32_t primitive, R fallback, Fn&& fn) {
  const std::uint32_t i = primitive_index(primitive);
  constexpr bool kInstances = (kShapes & kShapeInstance) != 0;
  constexpr bool kTrimmed = (kShapes & kShapeTrimmed) != 0;
  switch (primitive_type(primitive)) {
    case PrimitiveType::kSphere:
      if constexpr ((kShapes & kShapeSphere) != 0) return fn(s.spheres[i]);
      break;
    case PrimitiveType::kQuad:
      if constexpr ((kShapes & kShapeQuad) != 0) return fn(s.quads[i]);
      break;
    case PrimitiveType::kTriangle:
      if constexpr ((kShapes & kShapeTriangle) != 0) return fn(s.triangles[i]);
      break;
    case PrimitiveType::kPlane:
      if constexpr ((kShapes & kShapePlane) != 0) return fn(s.planes[i]);
      break;
    case PrimitiveType::kDisk:
      if constexpr ((kShapes & kShapeDisk) != 0) return fn(s.disks[i]);
      break;
    case PrimitiveType::kCylinder:
      if constexpr ((kShapes & kShapeCylinder) != 0) return fn(s.cylinders[i]);
      break;
    case PrimitiveType::kCone:
      if constexpr ((kShapes & kShapeCone) != 0) return fn(s.cones[i]);
      break;
    case PrimitiveType::kTorus:
      if constexpr ((kShapes & kShapeTorus) != 0) return fn(s.tori[i]);
      break;
    case PrimitiveType::kSdfBox:
      if constexpr ((kShapes & kShapeSdf) != 0) return fn(s.sdf_boxes[i]);
      break;
    case PrimitiveType::kSdfTorus:
      if constexpr ((kShapes & kShapeSdf) != 0) return fn(s.sdf_tori[i]);
      break;
    case PrimitiveType::kSdfCapsule:
      if constexpr ((kShapes & kShapeSdf) != 0) return fn(s.sdf_capsules[i]);
      break;
    case PrimitiveType::kSphereInstance:
      if constexpr (kInstances) return fn(s.sphere_instances[i]);
      break;
    case PrimitiveType::kDiskInstance:
      if constexpr (kInstances) return fn(s.disk_instances[i]);
      break;
    case PrimitiveType::kCylinderInstance:
      if constexpr (kInstances) return fn(s.cylinder_instances[i]);
      break;
    case PrimitiveType::kConeInstance:
      if constexpr (kInstances) return fn(s.cone_instances[i]);
      break;
    case PrimitiveType::kTorusInstance:
      if constexpr (kInstances) return fn(s.torus_instances[i]);
      break;
    case PrimitiveType::kSdfBoxInstance:
      if constexpr (kInstances) return fn(s.sdf_box_instances[i]);
      break;
    case PrimitiveType::kSdfTorusInstance:
      if constexpr (kInstances) return fn(s.sdf_torus_instances[i]);
      break;
    case PrimitiveType::kSdfCapsuleInstance:
      if constexpr (kInstances) return fn(s.sdf_capsule_instances[i]);
      break;
    case PrimitiveType::kSplinePatch:
      if constexpr ((kShapes & kShapePatch) != 0) return fn(s.patches[i]);
      break;
    case PrimitiveType::kTrimmedPlane:
      if constexpr (kTrimmed) return fn(s.trimmed_planes[i]);
      break;
    case PrimitiveType::kTrimmedDisk:
      if constexpr (kTrimmed) return fn(s.trimmed_disks[i]);
      break;
    case PrimitiveType::kTrimmedQuad:
      if constexpr (kTrimmed) return fn(s.trimmed_quads[i]);
      break;
    case PrimitiveType::kTrimmedSphere:
      if constexpr (kTrimmed) return fn(s.trimmed_spheres[i]);
      break;
    case PrimitiveType::kTrimmedCylinder:
      if constexpr (kTrimmed) return fn(s.trimmed_cylinders[i]);
      break;
    case PrimitiveType::kTrimmedCone:
      if constexpr (kTrimmed) return fn(s.trimmed_cones[i]);
      break;
    case PrimitiveType::kTrimmedTorus:
      if constexpr (kTrimmed) return fn(s.trimmed_tori[i]);
      break;
    case PrimitiveType::kTrimmedPatch:
      if constexpr (kTrimmed) return fn(s.trimmed_patches[i]);
      break;
  }
  return fallback;
}

}  // namespace scene_detail

// Intersection program for the shape types in kShapes; the others compile to nothing.
// Bounded shapes are found through the BVH (intersect / intersect_all per primitive);
// planes, which no box holds, are tested per ray by the *_unbounded queries that
// BvhTracer calls besides its traversal.
template <unsigned kShapes>
struct SceneIntersection {
  static constexpr unsigned kShapeMask = kShapes;
  static constexpr bool kHasUnbounded = (kShapes & kShapePlane) != 0;
  SceneShapes shapes;

  TESSERA_HD bool intersect(std::uint32_t primitive, const Ray& ray, float t_max,
                            HitRecord& hit) const {
    return scene_detail::dispatch<kShapes>(shapes, primitive, false, [&](const auto& shape) {
      return tessera::intersect(shape, ray, t_max, hit, primitive);
    });
  }

  // Every crossing of the primitive up to max_hits, nearest first.
  TESSERA_HD int intersect_all(std::uint32_t primitive, const Ray& ray, float t_max,
                               HitRecord* hits, int max_hits) const {
    if (max_hits <= 0) return 0;
    return scene_detail::dispatch<kShapes>(shapes, primitive, 0, [&](const auto& shape) {
      return tessera::intersect_all(shape, ray, t_max, hits, max_hits, primitive);
    });
  }

  // Nearest plane hit closer than hit.t (which it then replaces).
  TESSERA_HD bool intersect_unbounded(const Ray& ray, HitRecord& hit) const {
    bool found = false;
    if constexpr (kHasUnbounded) {
      for (std::uint32_t i = 0; i < shapes.plane_count; ++i)
        found |= tessera::intersect(shapes.planes[i], ray, hit.t, hit,
                                    make_primitive_ref(PrimitiveType::kPlane, i));
    }
    return found;
  }

  TESSERA_HD bool occluded_unbounded(const Ray& ray) const {
    if constexpr (kHasUnbounded) {
      HitRecord hit;
      for (std::uint32_t i = 0; i < shapes.plane_count; ++i)
        if (tessera::intersect(shapes.planes[i], ray, ray.t_max, hit,
                               make_primitive_ref(PrimitiveType::kPlane, i)))
          return true;
    }
    return false;
  }

  // Calls add(hit) for every plane crossing before t_max.
  template <typename Add>
  TESSERA_HD void intersect_all_unbounded(const Ray& ray, float t_max, Add&& add) const {
    if constexpr (kHasUnbounded) {
      for (std::uint32_t i = 0; i < shapes.plane_count; ++i) {
        HitRecord hit;
        if (tessera::intersect(shapes.planes[i], ray, t_max, hit,
                               make_primitive_ref(PrimitiveType::kPlane, i)))
          add(hit);
      }
    }
  }
};

template <unsigned kShapes>
TESSERA_HD SurfaceInteraction surface_at(const SceneView& scene, const Ray& ray,
                                         const HitRecord& hit) {
  if constexpr ((kShapes & kShapeTriangle) != 0) {
    if (scene.triangle_attributes != nullptr &&
        primitive_type(hit.primitive) == PrimitiveType::kTriangle) {
      const std::uint32_t i = primitive_index(hit.primitive);
      return surface_at(scene.triangles[i], scene.triangle_attributes[i], ray, hit);
    }
  }
  return scene_detail::dispatch<kShapes>(
      scene, hit.primitive, SurfaceInteraction{},
      [&](const auto& shape) { return surface_at(shape, ray, hit); });
}

}  // namespace tessera
