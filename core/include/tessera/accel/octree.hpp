#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "tessera/accel/wide_bvh.hpp"

namespace tessera {

// Leaf encoder for the octree: turns the primitives of one cell into a wide child word
// (make_wide_leaf) holding at most kWideMaxLeafItems items.
using OctreeLeafEncoder = std::function<std::uint32_t(std::span<const std::uint32_t> primitives)>;

struct OctreeLimits {
  std::uint32_t max_depth = 14;  // subdivisions below the root cube, at most 48
  // Cells with more primitives are subdivided. 32 measured best on suzanne-sub5 diffuse
  // rays (8: 1.5, 16: 1.9, 32: 2.2 Mrays/s; 7.6, 4.6, 2.8 references per triangle).
  std::uint32_t leaf_size = 32;
  std::uint32_t max_leaf_items = kWideMaxLeafItems * 4;  // primitives one encoded leaf can take
};

// Octree over the bounding cube of `bounds`: a cell with more than leaf_size primitives is
// cut into its eight octants and each primitive is referenced by every octant its box
// overlaps. Cells are stored as wide BVH nodes (one slot per non-empty octant, its box
// shrunk to the primitives it holds), so the SIMD wide traversal walks it unchanged; a
// primitive can be met in several leaves. Cells at the depth cap that hold more than
// max_leaf_items primitives are split into groups under an extra node.
WideBvh build_octree(std::span<const Aabb> bounds, const OctreeLimits& limits,
                     const OctreeLeafEncoder& encode_leaf);

}  // namespace tessera
