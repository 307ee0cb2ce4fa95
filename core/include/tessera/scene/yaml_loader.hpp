#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_error.hpp"

namespace tessera {

struct SceneLoadOptions {
  // Mesh files may only be read from inside these directories. Empty: any path the
  // process can read (the CLI on a user's own machine); the daemon always sets it.
  std::vector<std::filesystem::path> allowed_roots;
  SceneLimits limits;
  // Unknown keys are warnings instead of errors (the CLI's --lenient).
  bool lenient = false;
};

struct LoadedScene {
  SceneDescription scene;
  std::vector<SceneIssue> warnings;  // unknown keys, approximated features
  std::size_t mesh_files_read = 0;   // distinct mesh files parsed: each once per scene
};

// Reads Tessera's YAML scene format, a superset of RayON's. Throws SceneError naming the
// file, line and field of the first error.
LoadedScene load_scene_file(const std::filesystem::path& path,
                            const SceneLoadOptions& options = {});

// The same from text; `display_name` appears in messages and `base_directory` resolves
// relative mesh paths.
LoadedScene load_scene_yaml(std::string_view text, const std::string& display_name,
                            const std::filesystem::path& base_directory,
                            const SceneLoadOptions& options = {});

}  // namespace tessera
