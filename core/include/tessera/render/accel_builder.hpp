#pragma once
#include <string_view>

#include "tessera/accel/triangle_accel.hpp"

namespace tessera {

// The triangle structure's build options for a scene's `render.accel_builder`: "auto" or
// empty (every choice left to TriangleAccel: spatial splits, pre-splitting where triangles
// fill their boxes poorly, the binned build alone above kAutoSpatialSplitMaxTriangles),
// "spatial" (spatial splits at kAutoSpatialSplitBudget for every mesh, never pre-splitting:
// on three held-out heads of hair, whose ribbons the automatic choice pre-splits, diffuse
// rays measured 0.99-1.05x Embree's high-quality build with them against 0.81-0.98x
// pre-split, bench/accel/README.md) or "binned" (the binned surface-area build alone, 2-7
// times shorter, for previews and scenes rendered for seconds). Throws std::invalid_argument naming the field for any other value (the scene
// validation rejects those first).
AccelBuildOptions accel_build_options(std::string_view accel_builder);

}  // namespace tessera
