// Pipeline specialisations for the shape class "analytic" (spheres and rectangles). Each
// shape class lives in its own translation unit so the variants compile in parallel.
#include "tile_loop.hpp"

namespace tessera::variants {

template <>
std::array<RenderVariant, 8> path_variants<kShapeSphere | kShapeQuad>() {
  return make_path_variants<kShapeSphere | kShapeQuad>();
}

template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kShapeSphere | kShapeQuad>() {
  return make_preview_variants<kShapeSphere | kShapeQuad>();
}

}  // namespace tessera::variants
