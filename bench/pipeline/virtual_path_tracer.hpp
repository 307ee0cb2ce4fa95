#pragma once
// The baseline `tessera-bench specialise` measures against: the same path tracer written
// the conventional way, with shapes and BSDFs behind virtual interfaces, a BVH over
// Shape pointers, and features tested per ray at run time. Kept in bench/ only.
//
// It runs PathHit's algorithm (next-event estimation by the light interface, BSDF sampling
// in a shading frame, multiple importance sampling with the power heuristic, Russian
// roulette on white noise) and draws the same random numbers for the same decisions, so its
// images equal the pipeline's. Scope: untransformed spheres, quads and meshes without
// normals or uvs, the scenes bench_scenes.cpp makes.
#include <memory>
#include <span>
#include <vector>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera::bench {

class VirtualScene;

// Renders one tile of `scene` into RGBA floats, like PreparedScene::render_tile.
class VirtualPathTracer {
 public:
  // `light_tree`: pick among two or more lights by the light tree, as
  // PrepareOptions::light_tree does for the pipeline.
  explicit VirtualPathTracer(const SceneDescription& description, bool light_tree = true);
  ~VirtualPathTracer();
  TileStats render_tile(const TileRect& tile, std::span<float> rgba) const;

 private:
  std::unique_ptr<VirtualScene> scene_;
  RenderSettings settings_;
};

}  // namespace tessera::bench
