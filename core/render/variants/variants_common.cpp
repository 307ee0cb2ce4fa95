// Pipeline specialisations for the shape class "common" (spheres, rectangles, triangles). Each
// shape class lives in its own translation unit so the variants compile in parallel.
#include "tile_loop.hpp"

namespace tessera::variants {

template <>
std::array<RenderVariant, 8> path_variants<kCommonShapes>() {
  return make_path_variants<kCommonShapes>();
}

template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kCommonShapes>() {
  return make_preview_variants<kCommonShapes>();
}

}  // namespace tessera::variants
