// Pipeline specialisations for the shape class "triangles". Each shape class lives in its own
// translation unit so the variants compile in parallel.
#include "tile_loop.hpp"

namespace tessera::variants {

template <>
std::array<RenderVariant, 8> path_variants<kShapeTriangle>() {
  return make_path_variants<kShapeTriangle>();
}

template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kShapeTriangle>() {
  return make_preview_variants<kShapeTriangle>();
}

}  // namespace tessera::variants
