#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_error.hpp"
#include "tessera/v1/render.pb.h"
#include "tessera/v1/scene.pb.h"

namespace tessera {

// The scene as the public API describes it. Geometry is emitted in input order
// (`source_index`), so the server's field paths (`geometry[3].radius`) name the entry the
// user wrote and its shape arrays come out in the same order as a local load. Every field
// the proto treats as "0 means default" is written explicitly, so the server renders
// exactly the scene the client loaded. Meshes travel inline; a one-triangle mesh that did
// not come from a file is sent as a Triangle.
v1::Scene scene_to_proto(const SceneDescription& scene);

v1::MaterialType material_type_to_proto(MaterialType type);

// Width, height, spp, depth, tile size, seed, integrator and AOVs, all written explicitly.
v1::RenderSettings render_settings_to_proto(const RenderSettings& settings);

// The AovBit mask of settings the server sent back (the inverse of the AOV part above).
std::uint32_t aov_mask_from_proto(const v1::RenderSettings& settings);

v1::SubmitJobRequest make_submit_request(const SceneDescription& scene, const std::string& name,
                                         std::int32_t priority);

}  // namespace tessera
