#pragma once
#include <array>

#include "tessera/render/prepared_scene.hpp"

namespace tessera {

using RenderTileFunction = TileStats (*)(const SceneView&, const RenderSettings&, const TileRect&,
                                         float*);

// The specialisation compiled for exactly the shape types in `shape_mask`.
RenderTileFunction select_render_tile(unsigned shape_mask);

}  // namespace tessera
