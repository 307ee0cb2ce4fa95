#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "tessera/geometry/triangle.hpp"

namespace tessera::bench {

struct IndexedMesh {
  std::vector<vec3> positions;
  std::vector<std::uint32_t> indices;  // three per triangle

  std::size_t triangle_count() const { return indices.size() / 3; }
};

// Loads any format assimp reads through the project's mesh loader (the path tesserad uses).
IndexedMesh load_mesh_with_assimp(const std::filesystem::path& path);

// Minimal reader for binary little-endian PLY with float x y z vertices (other vertex
// properties skipped) and uchar/int-count face lists of uint/int indices, triangulated as
// fans. Exists only to measure what assimp costs; throws std::runtime_error otherwise.
IndexedMesh load_binary_ply_direct(const std::filesystem::path& path);

void write_binary_ply(const std::filesystem::path& path, const IndexedMesh& mesh);

std::vector<Triangle> to_triangles(const IndexedMesh& mesh);

}  // namespace tessera::bench
