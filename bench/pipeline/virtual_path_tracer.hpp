#pragma once
// The baseline `tessera-bench specialise` measures against: the same path tracer written
// the conventional way, with shapes and materials behind virtual interfaces, a BVH over
// Shape pointers, and features tested per ray at run time. Kept in bench/ only.
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
  explicit VirtualPathTracer(const SceneDescription& description);
  ~VirtualPathTracer();
  TileStats render_tile(const TileRect& tile, std::span<float> rgba) const;

 private:
  std::unique_ptr<VirtualScene> scene_;
  RenderSettings settings_;
};

}  // namespace tessera::bench
