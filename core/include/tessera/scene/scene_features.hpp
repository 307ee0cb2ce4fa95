#pragma once
#include <cstdint>
#include <string>

#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Bit per shape type; a scene's mask picks the pipeline specialisation compiled for it.
enum ShapeBit : unsigned {
  kShapeSphere = 1u << 0,
  kShapeQuad = 1u << 1,
  kShapeTriangle = 1u << 2,
};
inline constexpr unsigned kAllShapes = kShapeSphere | kShapeQuad | kShapeTriangle;

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
