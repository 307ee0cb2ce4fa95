#pragma once
#include <cstdint>

#include "tessera/scene/scene_features.hpp"

namespace tessera {

// The compile-time feature set of one pipeline specialisation. Code for a feature that is
// off is removed with `if constexpr`; the renderer picks, per job, the smallest compiled
// set that covers the scene (see select_render_variant).
struct PipelineFeatures {
  unsigned shapes = kAllShapes;  // ShapeBit mask the intersection program handles
  bool direct_lighting = true;   // emitters exist: next-event estimation with shadow rays
  bool specular = true;          // mirror, glass, thin-film or coated materials exist
  bool aovs = true;              // AOV planes were asked for

  friend constexpr bool operator==(const PipelineFeatures&, const PipelineFeatures&) = default;

  constexpr bool covers(const PipelineFeatures& need) const {
    return (need.shapes & ~shapes) == 0 && (direct_lighting || !need.direct_lighting) &&
           (specular || !need.specular) && (aovs || !need.aovs);
  }
};

inline constexpr PipelineFeatures kAllFeatures{};

// Shape classes compiled, smallest first: a scene gets the first one covering its shapes.
// Classes rather than every subset keep the variant count (and build time) flat as shape
// types are added: "all" holds every ShapeBit (planes, disks, cylinders, cones, tori,
// signed-distance shapes and instances too), so a new shape type adds code to the "all"
// variants only, not new variants.
//
// Spheres, rectangles and triangles together are what most scenes hold (a room of
// rectangles with spheres and meshes in it); without their own class a mesh beside a
// rectangle light fell to "all", whose intersection program dispatches over every shape
// list (8% of the emissive-triangle converge scene's instructions). Spheres and
// rectangles alone keep theirs: the triangle case would cost them 1.7%.
inline constexpr unsigned kCommonShapes = kShapeSphere | kShapeQuad | kShapeTriangle;
inline constexpr unsigned kShapeClasses[] = {kShapeTriangle, kShapeSphere | kShapeQuad,
                                             kCommonShapes, kAllShapes};

}  // namespace tessera
