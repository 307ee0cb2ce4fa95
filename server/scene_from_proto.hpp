#pragma once
#include <optional>
#include <string>
#include <vector>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_error.hpp"
#include "tessera/v1/render.pb.h"
#include "tessera/v1/scene.pb.h"

namespace tessera::server {

// Server defaults for RenderSettings fields left at zero.
inline constexpr std::uint32_t kDefaultWidth = 320;
inline constexpr std::uint32_t kDefaultHeight = 240;
inline constexpr std::uint32_t kDefaultSamplesPerPixel = 16;
inline constexpr std::uint32_t kDefaultMaxDepth = 6;
inline constexpr std::uint32_t kDefaultTileSize = 32;

// The outcome of converting a request: the scene when every check passed, otherwise every
// issue found. Field paths follow the protobuf messages: scene fields relative to `Scene`
// (`geometry[3].sphere.radius`, `materials[1].type`, `camera.fov_degrees`), render settings
// under `settings.` (`settings.tile_size`).
struct SceneConversion {
  std::optional<SceneDescription> scene;
  std::vector<SceneIssue> issues;

  bool ok() const { return scene.has_value(); }
};

// Fills zero fields with the server defaults; does not range-check.
RenderSettings settings_from_proto(const v1::RenderSettings& settings);
v1::RenderSettings settings_to_proto(const RenderSettings& settings);

// Converts and validates a scene and its render settings: structural checks here (shape
// set, material names and types, finite numbers, mesh layout), then validate_scene() for
// the semantic checks shared with the YAML loader, its paths translated to protobuf ones.
SceneConversion scene_from_proto(const v1::Scene& scene, const v1::RenderSettings& settings,
                                 const SceneLimits& limits = {});

// `geometry[3].sphere.radius: must be positive, got -1`; several issues are joined with "; ".
std::string describe_issues(const std::vector<SceneIssue>& issues);

}  // namespace tessera::server
