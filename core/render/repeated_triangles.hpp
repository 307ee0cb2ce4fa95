#pragma once
// Exact repeats of a triangle within one mesh. A mesh that repeats a triangle many times
// (50 million copies of one triangle fit in a 150 MB request) gives the BVH primitives it
// cannot separate: every ray near them tests every copy, so a tile took minutes. A repeat
// adds nothing to the image (a ray hits one of the copies at the same distance, with the
// same shading), so the renderer stores the first and drops the rest.
#include <cstddef>
#include <vector>

#include "tessera/scene/scene_description.hpp"

namespace tessera {

// For each triangle of `mesh` (indices / 3), whether an earlier triangle of the mesh has
// the same three vertices (positions, and normals and uvs where the mesh has them, compared
// bit for bit) in the same winding, starting at any corner. O(n log n) time, 16 bytes per
// triangle while it runs. Empty when the mesh repeats nothing.
std::vector<bool> repeated_triangles(const TriangleMeshDesc& mesh);

}  // namespace tessera
