#pragma once
// Scene descriptions to and from the public API's messages: the one conversion library that
// tesserad, the tessera CLI and the tests link. Both directions are driven by the kind
// declarations (core: tessera/scene/schema/kinds.hpp) through protobuf reflection, so a field
// declared there is read and written under the same name as in YAML.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_error.hpp"
#include "tessera/v1/render.pb.h"
#include "tessera/v1/scene.pb.h"

namespace tessera {

// The outcome of converting a request: the scene when every check passed, otherwise every
// issue found, in input order. Field paths follow the protobuf messages: scene fields
// relative to `Scene` (`geometry[3].sphere.radius`, `materials[1].type`,
// `camera.fov_degrees`), render settings under `settings.` (`settings.tile_size`).
struct SceneConversion {
  std::optional<SceneDescription> scene;
  std::vector<SceneIssue> issues;

  bool ok() const { return scene.has_value(); }
};

// Zero fields take the declared defaults (RenderSettings' member initialisers); no range
// checks (validate_scene has them).
RenderSettings settings_from_proto(const v1::RenderSettings& settings);
// Width, height, spp, depth, tile size, seed, integrator, AOVs, sampler and light strategy,
// all written explicitly.
v1::RenderSettings settings_to_proto(const RenderSettings& settings);

// Converts and validates a scene and its render settings: structure here (shape set,
// material names and types, finite numbers, presence of required fields, mesh layout), then
// validate_scene() in protobuf path style for the rules shared with the YAML loader.
SceneConversion scene_from_proto(const v1::Scene& scene, const v1::RenderSettings& settings,
                                 const SceneLimits& limits = {});

// The scene as the API describes it. Geometry is emitted in input order (`source_index`), so
// the server's field paths (`geometry[3].radius`) name the entry the user wrote. Every
// field is written explicitly, so the server renders exactly the scene the client loaded.
// Meshes travel inline; a one-triangle mesh that did not come from a file is a Triangle.
v1::Scene scene_to_proto(const SceneDescription& scene);

v1::MaterialType material_type_to_proto(MaterialType type);

// The AovBit mask of settings (unknown values ignored).
std::uint32_t aov_mask_from_proto(const v1::RenderSettings& settings);

// A SubmitJobRequest for the scene and its render settings.
v1::SubmitJobRequest make_submit_request(const SceneDescription& scene, const std::string& name,
                                         std::int32_t priority);

// `geometry[3].sphere.radius: must be > 0, got -1`; several issues are joined with "; ".
std::string describe_issues(const std::vector<SceneIssue>& issues);

}  // namespace tessera
