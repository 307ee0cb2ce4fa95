#pragma once
#include <filesystem>

#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Loads every mesh in a file through assimp (OBJ, PLY, glTF, STL, ...), triangulated and
// merged into one mesh. Throws SceneError naming the file and assimp's reason.
TriangleMeshDesc load_mesh_file(const std::filesystem::path& path);

// True when `path` lies inside one of `roots` after resolving `..` and symlinks.
bool path_is_within(const std::filesystem::path& path,
                    const std::vector<std::filesystem::path>& roots);

}  // namespace tessera
