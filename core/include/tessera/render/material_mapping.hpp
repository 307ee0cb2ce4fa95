#pragma once
// Scene materials (MaterialDesc, as the user wrote them) mapped onto the BSDF families the
// renderer evaluates (Material). Public because scene feature analysis and the benchmarks
// classify materials the way the renderer will.
#include "tessera/render/material.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Maps a scene material onto the renderer's BSDF families.
Material make_material(const MaterialDesc& desc);

}  // namespace tessera
