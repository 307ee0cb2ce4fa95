#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/accel/huge_page_allocator.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera {

// Four triangles' vertices in structure-of-arrays form, the leaf layout of the wide BVH,
// octree and brute-force tracers: the watertight test runs on all four lanes at once, and
// the ray's axis permutation becomes a choice of which rows to load. 160 bytes. Unused
// lanes hold NaN vertices (no ray can hit them) and kInvalidIndex.
struct alignas(16) TriangleBlock4 {
  float vertices[3][3][4];  // [vertex][axis][lane]
  std::uint32_t ids[4];     // the triangle's index in the caller's array
};
static_assert(sizeof(TriangleBlock4) == 160);

// Appends ceil(ids.size() / 4) blocks holding triangles[ids[i]], labelled ids[i], or
// references[ids[i]] when references are given; returns the first block's index.
std::uint32_t append_triangle_blocks(std::span<const Triangle> triangles,
                                     std::span<const std::uint32_t> ids,
                                     HugePageVector<TriangleBlock4>& blocks,
                                     std::span<const std::uint32_t> references = {});

}  // namespace tessera
