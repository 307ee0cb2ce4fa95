#pragma once
// A mesh entry's triangles as the renderer stores them: baked into world triangles (this
// file), or shared in object space by several placements (mesh_sharing.hpp); both store the
// same per-vertex attributes.
#include <cstdint>
#include <span>
#include <vector>

#include "primitive_list.hpp"
#include "tessera/geometry/triangle.hpp"
#include "tessera/geometry/triangle_attributes.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// Whether the scene stores per-vertex attributes: only when some mesh has normals or uvs.
// The other meshes then get zero normals (they shade flat) and the uvs that reproduce
// barycentric uvs.
bool stores_triangle_attributes(std::span<const TriangleMeshDesc> meshes);

// The triangle of `mesh` with vertices a, b and c, in the mesh's own coordinates.
Triangle mesh_triangle(const TriangleMeshDesc& mesh, std::uint32_t a, std::uint32_t b,
                       std::uint32_t c, std::uint32_t material);

// Per-vertex shading data of that triangle; a mesh without normals gets zero normals (it
// shades flat), without uvs the uvs that reproduce barycentric uvs.
TriangleAttributes mesh_attributes(const TriangleMeshDesc& mesh, std::uint32_t a, std::uint32_t b,
                                   std::uint32_t c);

// Bakes `mesh`'s transform into its vertices and stores its triangles in `triangles` (and
// their attributes in `attributes` when `store_attributes`), each recorded in `primitives`.
void bake_mesh(const TriangleMeshDesc& mesh, bool store_attributes,
               std::vector<Triangle>& triangles, std::vector<TriangleAttributes>& attributes,
               PrimitiveList& primitives);

}  // namespace tessera
