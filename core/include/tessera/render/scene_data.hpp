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
#include "tessera/math/alias_table.hpp"
#include "tessera/render/analytic_light.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/environment.hpp"
#include "tessera/render/light_tree.hpp"
#include "tessera/render/material.hpp"
#include "tessera/render/texture.hpp"
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
  // A triangle of a mesh geometry shared by several placements (two-level: InstanceAccel
  // over one object-space TriangleAccel per geometry). The index is virtual: placement p
  // names its triangles first_id .. first_id + count - 1 (MeshPlacement), so HitRecord
  // stays one tagged reference. Traced on the CPU only, like BvhView::triangles.
  kInstancedTriangle,
  // Not a shape and never in the BVH: a light-list entry for a light that is not a shape
  // (render/analytic_light.hpp); the index is into SceneView::analytic_lights.
  kAnalyticLight,
};
inline constexpr std::uint32_t kPrimitiveTypeShift = 27;
inline constexpr std::uint32_t kPrimitiveIndexMask = (1u << kPrimitiveTypeShift) - 1u;
static_assert(static_cast<std::uint32_t>(PrimitiveType::kAnalyticLight) <
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
         type == PrimitiveType::kTriangle || type == PrimitiveType::kDisk ||
         type == PrimitiveType::kCylinder || type == PrimitiveType::kCone;
}

// One placement of a shared mesh geometry: its virtual triangle ids start at first_id,
// its object-space triangles (and attributes, when stored) at first_triangle in
// SceneShapes::instanced_triangles. Placements are sorted by first_id.
struct MeshPlacement {
  std::uint32_t first_id = 0;
  std::uint32_t first_triangle = 0;
  std::uint32_t material = 0;
  AffineTransform object_to_world;
  AffineTransform world_to_object;
  double world_position_error_gain = 0.0;  // object_to_world.max_error_gain(), once per placement
};

// At most this many delta lights (points, spots, suns without extent) are sampled at every
// vertex (LightSource::every_vertex); a scene with more picks them among the others.
inline constexpr std::uint32_t kMaxEveryVertexLights = 4;

struct LightSource {
  std::uint32_t primitive;  // tagged reference
  float area;
  float pmf = 0.0f;  // the probability pick_light chooses it: its share of the power
  // False for lights no ray can hit (points, spots, delta suns): only light sampling finds
  // them, so their samples take no MIS weight. Emitting shapes are hit even when hidden
  // from the camera.
  bool hit_by_rays = true;
  // Sampled at every vertex instead of picked (a few delta lights: kMaxEveryVertexLights):
  // its pick probability is 0.
  bool every_vertex = false;
  std::uint32_t tree_depth = 0;  // its leaf's depth in the light tree (when there is one)
  std::uint64_t tree_path = 0;   // the child slot taken at each depth (light_tree.hpp)
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
  // The last this many planes are hidden from camera rays (`visible: false`).
  std::uint32_t hidden_plane_count = 0;
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
  // Shared mesh geometry (PrimitiveType::kInstancedTriangle): object-space triangles of
  // every shared geometry back to back, their attributes (null when no mesh has any) and
  // the placements.
  const Triangle* instanced_triangles = nullptr;
  const TriangleAttributes* instanced_attributes = nullptr;
  const MeshPlacement* mesh_placements = nullptr;
  std::uint32_t mesh_placement_count = 0;
};

// A shared mesh's vertex normal `n` in world space: by the placement's inverse transpose
// `normal_matrix` (transpose(world_to_object.linear)), renormalised; a zero normal (none
// stored) stays zero. Instanced hits and the device layout's baked placements
// (render/baked_placements.hpp) both place normals with it, as bake_mesh does a mesh entry's.
TESSERA_HD TESSERA_INLINE vec3 placed_vertex_normal(const glm::dmat3& normal_matrix,
                                                    const vec3& n) {
  const dvec3 w = normal_matrix * dvec3(n);
  const double len2 = glm::dot(w, w);
  return len2 > 0.0 ? vec3(w / std::sqrt(len2)) : vec3(0.0f);
}

// The surface of a shared-geometry triangle hit, in world space: the placement holding the
// virtual id is found by binary search, the object-space ray gives the mesh triangle's
// surface (shading normal and uv interpolated when stored), and position and normals go
// back by the placement (normals by the inverse transpose).
TESSERA_HD inline SurfaceInteraction instanced_triangle_surface(const SceneShapes& s,
                                                                const Ray& ray,
                                                                const HitRecord& hit) {
  const std::uint32_t id = primitive_index(hit.primitive);
  std::uint32_t lo = 0, hi = s.mesh_placement_count;  // last placement with first_id <= id
  while (hi - lo > 1) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    if (s.mesh_placements[mid].first_id <= id)
      lo = mid;
    else
      hi = mid;
  }
  const MeshPlacement& placement = s.mesh_placements[lo];
  const std::uint32_t triangle = placement.first_triangle + (id - placement.first_id);
  // Only the object-space ray is wanted: its gains stay 0 (to_float_ray drops the origin
  // error they would scale, and the position error below uses the placement's own gain).
  Instance<Triangle> instance{s.instanced_triangles[triangle], placement.object_to_world,
                              placement.world_to_object};
  const Ray object = to_float_ray(to_object_ray(instance, ray));
  SurfaceInteraction si = surface_at(instance.shape, object, hit);
  si.position = vec3(placement.object_to_world.point(dvec3(si.position)));
  si.position_error = transformed_position_error(si.position_error,
                                                 placement.world_position_error_gain, si.position);
  const glm::dmat3 normal_matrix = glm::transpose(placement.world_to_object.linear);
  si.geometric_normal = vec3(glm::normalize(normal_matrix * dvec3(si.geometric_normal)));
  si.shading_normal = si.geometric_normal;
  if (s.instanced_attributes != nullptr) {
    // Vertex normals go to world space one by one (renormalised) before they are
    // interpolated, as baking them does, so both give the same shading.
    const TriangleAttributes& a = s.instanced_attributes[triangle];
    apply_attributes(
        si,
        TriangleAttributes{placed_vertex_normal(normal_matrix, a.n0),
                           placed_vertex_normal(normal_matrix, a.n1),
                           placed_vertex_normal(normal_matrix, a.n2), a.uv0, a.uv1, a.uv2},
        hit);
  }
  si.material = placement.material;
  return si;
}

// Read-only view of the render scene: plain pointers into arrays that live for the job,
// valid on the host or, once uploaded, on a device.
struct SceneView : SceneShapes {
  const Material* materials = nullptr;
  // Some material is a thin film: shadow rays then look through films (film_transmittance).
  bool thin_films = false;
  const Texture* textures = nullptr;          // Material::albedo_texture, roughness_texture
  const vec3* texels = nullptr;               // the textures' mip pyramids
  const LightSource* lights = nullptr;        // sorted by primitive reference (find_light)
  const AliasSlot* light_alias = nullptr;     // light_count slots, by power (pick_light)
  const LightTreeNode* light_tree = nullptr;  // null: pick by power alone
  std::uint32_t light_count = 0;
  BvhView bvh;
  Camera camera;
  vec3 background{0.0f};  // what the preview integrators show on a miss
  // Lights that are not shapes, in the light list after every emissive shape (their
  // references sort last): point and spot lights, then distant lights, then the
  // environment when it is not black. Light-list index = first_analytic_light + index.
  const AnalyticLight* analytic_lights = nullptr;
  std::uint32_t analytic_light_count = 0;
  std::uint32_t first_analytic_light = 0;
  // Lights at infinity (distant lights and the environment) are the light list's tail from
  // first_infinite_light; the light tree holds only the others, and pick_light chooses
  // among these with probability infinite_pick (uniformly) when there is a tree.
  std::uint32_t first_infinite_light = 0;
  float infinite_pick = 0.0f;
  // The delta lights next-event estimation samples at every vertex (LightSource::
  // every_vertex), by light-list index, and whether any light is left to pick.
  std::uint32_t every_vertex_lights[kMaxEveryVertexLights] = {};
  std::uint32_t every_vertex_count = 0;
  bool pick_lights = true;
  Environment environment;
  std::uint32_t environment_light = 0;  // its light-list index; light_count when it has none
  // offset_ray_origin's scale for this scene's extent (spawn_scale_for_extent): 1 unless
  // the scene is smaller than a few units.
  float spawn_scale = 1.0f;
};

namespace scene_detail {

// One stored primitive type: its tag, the ShapeBit that compiles it into a pipeline
// variant, and its flat array in SceneShapes. StoredPrimitives lists every type once; the
// dispatch below is generated from it, so a new primitive type is one line here (and its
// array in SceneShapes), not a case in each switch.
template <PrimitiveType kTag, unsigned kShapeBit, auto kArray>
struct StoredPrimitive {
  static constexpr PrimitiveType tag = kTag;
  static constexpr unsigned shape_bit = kShapeBit;
  static constexpr auto array = kArray;
};
template <typename... Primitives>
struct PrimitiveList {};

using StoredPrimitives = PrimitiveList<
    StoredPrimitive<PrimitiveType::kSphere, kShapeSphere, &SceneShapes::spheres>,
    StoredPrimitive<PrimitiveType::kQuad, kShapeQuad, &SceneShapes::quads>,
    StoredPrimitive<PrimitiveType::kTriangle, kShapeTriangle, &SceneShapes::triangles>,
    StoredPrimitive<PrimitiveType::kPlane, kShapePlane, &SceneShapes::planes>,
    StoredPrimitive<PrimitiveType::kDisk, kShapeDisk, &SceneShapes::disks>,
    StoredPrimitive<PrimitiveType::kCylinder, kShapeCylinder, &SceneShapes::cylinders>,
    StoredPrimitive<PrimitiveType::kCone, kShapeCone, &SceneShapes::cones>,
    StoredPrimitive<PrimitiveType::kTorus, kShapeTorus, &SceneShapes::tori>,
    StoredPrimitive<PrimitiveType::kSdfBox, kShapeSdf, &SceneShapes::sdf_boxes>,
    StoredPrimitive<PrimitiveType::kSdfTorus, kShapeSdf, &SceneShapes::sdf_tori>,
    StoredPrimitive<PrimitiveType::kSdfCapsule, kShapeSdf, &SceneShapes::sdf_capsules>,
    StoredPrimitive<PrimitiveType::kSphereInstance, kShapeInstance, &SceneShapes::sphere_instances>,
    StoredPrimitive<PrimitiveType::kDiskInstance, kShapeInstance, &SceneShapes::disk_instances>,
    StoredPrimitive<PrimitiveType::kCylinderInstance, kShapeInstance,
                    &SceneShapes::cylinder_instances>,
    StoredPrimitive<PrimitiveType::kConeInstance, kShapeInstance, &SceneShapes::cone_instances>,
    StoredPrimitive<PrimitiveType::kTorusInstance, kShapeInstance, &SceneShapes::torus_instances>,
    StoredPrimitive<PrimitiveType::kSdfBoxInstance, kShapeInstance,
                    &SceneShapes::sdf_box_instances>,
    StoredPrimitive<PrimitiveType::kSdfTorusInstance, kShapeInstance,
                    &SceneShapes::sdf_torus_instances>,
    StoredPrimitive<PrimitiveType::kSdfCapsuleInstance, kShapeInstance,
                    &SceneShapes::sdf_capsule_instances>,
    StoredPrimitive<PrimitiveType::kSplinePatch, kShapePatch, &SceneShapes::patches>,
    StoredPrimitive<PrimitiveType::kTrimmedPlane, kShapeTrimmed, &SceneShapes::trimmed_planes>,
    StoredPrimitive<PrimitiveType::kTrimmedDisk, kShapeTrimmed, &SceneShapes::trimmed_disks>,
    StoredPrimitive<PrimitiveType::kTrimmedQuad, kShapeTrimmed, &SceneShapes::trimmed_quads>,
    StoredPrimitive<PrimitiveType::kTrimmedSphere, kShapeTrimmed, &SceneShapes::trimmed_spheres>,
    StoredPrimitive<PrimitiveType::kTrimmedCylinder, kShapeTrimmed,
                    &SceneShapes::trimmed_cylinders>,
    StoredPrimitive<PrimitiveType::kTrimmedCone, kShapeTrimmed, &SceneShapes::trimmed_cones>,
    StoredPrimitive<PrimitiveType::kTrimmedTorus, kShapeTrimmed, &SceneShapes::trimmed_tori>,
    StoredPrimitive<PrimitiveType::kTrimmedPatch, kShapeTrimmed, &SceneShapes::trimmed_patches>>;

// Every primitive type but kInstancedTriangle (never in the BVH; surface_at handles it) is
// listed, each once, in tag order.
template <typename... P>
constexpr bool lists_every_type_in_order(PrimitiveList<P...>) {
  std::uint32_t expected = 0;
  return ((static_cast<std::uint32_t>(P::tag) == expected++) && ...) &&
         expected == static_cast<std::uint32_t>(PrimitiveType::kInstancedTriangle);
}
static_assert(lists_every_type_in_order(StoredPrimitives{}));

// The switch over the listed types: a case for each type in kShapes, calling fn(shape).
// Written as a chain of tests on the tag that the compiler folds into one jump table, with
// the types a variant leaves out removed at compile time.
template <unsigned kShapes, typename R, typename Fn, typename... P>
TESSERA_HD TESSERA_INLINE R dispatch_listed(PrimitiveList<P...>, const SceneShapes& s,
                                            std::uint32_t primitive, R fallback, Fn&& fn) {
  const std::uint32_t i = primitive_index(primitive);
  const PrimitiveType type = primitive_type(primitive);
  R result = fallback;
  const auto try_one = [&](auto primitive_kind) {
    using Kind = decltype(primitive_kind);
    if constexpr ((kShapes & Kind::shape_bit) != 0) {
      if (type == Kind::tag) {
        result = fn((s.*Kind::array)[i]);
        return true;
      }
    }
    return false;
  };
  (try_one(P{}) || ...);
  return result;
}

// Calls `fn(shape)` with the shape `primitive` names, for the types in kShapes; returns
// `fallback` for the others (they compile to nothing).
template <unsigned kShapes, typename R, typename Fn>
TESSERA_HD R dispatch(const SceneShapes& s, std::uint32_t primitive, R fallback, Fn&& fn) {
  return dispatch_listed<kShapes>(StoredPrimitives{}, s, primitive, fallback,
                                  static_cast<Fn&&>(fn));
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
  // The scene's shape arrays (272 bytes), the caller's, which outlives the tracer. A copy
  // would put them on every GPU thread's stack (local memory); by reference the kernel reads
  // its __grid_constant__ parameter through the constant cache.
  const SceneShapes& shapes;

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

  // Nearest plane hit closer than hit.t (which it then replaces); a camera ray skips the
  // hidden planes.
  TESSERA_HD bool intersect_unbounded(const Ray& ray, HitRecord& hit, bool camera = false) const {
    bool found = false;
    if constexpr (kHasUnbounded) {
      const std::uint32_t count =
          camera ? shapes.plane_count - shapes.hidden_plane_count : shapes.plane_count;
      for (std::uint32_t i = 0; i < count; ++i)
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
  TESSERA_HD void intersect_all_unbounded(const Ray& ray, float t_max, Add&& add,
                                          bool camera = false) const {
    if constexpr (kHasUnbounded) {
      const std::uint32_t count =
          camera ? shapes.plane_count - shapes.hidden_plane_count : shapes.plane_count;
      for (std::uint32_t i = 0; i < count; ++i) {
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
    if (primitive_type(hit.primitive) == PrimitiveType::kInstancedTriangle)
      return instanced_triangle_surface(scene, ray, hit);
  }
  return scene_detail::dispatch<kShapes>(
      scene, hit.primitive, SurfaceInteraction{},
      [&](const auto& shape) { return surface_at(shape, ray, hit); });
}

}  // namespace tessera
