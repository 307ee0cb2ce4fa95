#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Bit per shape type; a scene's mask picks the pipeline specialisation compiled for it.
enum ShapeBit : unsigned {
  kShapeSphere = 1u << 0,
  kShapeQuad = 1u << 1,
  kShapeTriangle = 1u << 2,
  kShapePlane = 1u << 3,
  kShapeDisk = 1u << 4,
  kShapeCylinder = 1u << 5,
  kShapeCone = 1u << 6,
  kShapeTorus = 1u << 7,
  kShapeSdf = 1u << 8,       // signed-distance box, rounded box, torus, capsule
  kShapeInstance = 1u << 9,  // any shape under a transform its own type cannot hold
  kShapePatch = 1u << 10,    // bicubic B-spline/NURBS patches (transforms baked in)
  kShapeTrimmed = 1u << 11,  // trimmed faces of any surface type, each an instance
};
inline constexpr unsigned kAllShapes = kShapeSphere | kShapeQuad | kShapeTriangle | kShapePlane |
                                       kShapeDisk | kShapeCylinder | kShapeCone | kShapeTorus |
                                       kShapeSdf | kShapeInstance | kShapePatch | kShapeTrimmed;

// True when a curved shape under `transform` stays a shape of its own type (translate,
// rotate and uniform scale: a similarity), so the renderer bakes the transform into its
// parameters; otherwise it becomes an Instance (ShapeBit kShapeInstance). Planes, quads and
// triangles bake under every affine map; signed-distance shapes are instanced whenever
// they have a transform.
inline bool transform_bakes_into_shape(const std::optional<TransformDesc>& transform) {
  return !transform || transform->uniform_scale();
}

// What a scene contains, so the renderer can leave out what it does not.
struct SceneFeatures {
  unsigned shapes = 0;               // ShapeBit mask of visible or emissive shapes
  std::uint32_t material_kinds = 0;  // bit per BsdfKind used by some shape
  std::uint32_t light_count = 0;     // emissive primitives sampled for direct light
  std::size_t primitive_count = 0;
  unsigned light_shapes = 0;    // ShapeBit mask of shape types that emit (the light types)
  bool emissive = false;        // some shape uses an emitting material
  bool transmissive = false;    // glass or thin film present
  bool depth_of_field = false;  // the pinhole camera has none yet
  std::uint32_t aovs = 0;       // AovBit mask asked for

  // Mirror, glass, thin-film or coated materials present: the specular BSDF code is needed.
  bool specular() const;

  static SceneFeatures of(const SceneDescription& scene);
  std::string summary() const;  // for logs: "spheres+quads, 3 lights, 12 primitives"
};

}  // namespace tessera
