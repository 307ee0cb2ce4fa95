// Pipeline specialisations for the shape class "all". Each shape class lives in its own
// translation unit so the variants compile in parallel.
#include "tile_loop.hpp"

namespace tessera::variants {

template <>
std::array<RenderVariant, 8> path_variants<kAllShapes>() {
  return make_path_variants<kAllShapes>();
}

template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kAllShapes>() {
  return make_preview_variants<kAllShapes>();
}

}  // namespace tessera::variants
