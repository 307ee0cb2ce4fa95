#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/huge_page_allocator.hpp"

namespace tessera {

// Eight-wide BVH for CPU traversal: one node holds the boxes of up to eight children in
// structure-of-arrays form, so one AVX2 instruction (or two SSE ones) tests a ray against
// all of them. It is collapsed from the binary BVH.
inline constexpr std::uint32_t kWideBvhWidth = 8;

// Child words. Bit 31 marks a leaf; a leaf holds `count` (bits 26..30) consecutive items
// (triangle blocks, or primitive references) from `first` (bits 0..25). A leaf of zero
// items is an empty slot.
inline constexpr std::uint32_t kWideLeafFlag = 0x80000000U;
inline constexpr std::uint32_t kWideLeafCountShift = 26;
inline constexpr std::uint32_t kWideMaxLeafItems = 31;
inline constexpr std::uint32_t kWideMaxLeafFirst = (1U << kWideLeafCountShift) - 1;
inline constexpr std::uint32_t kWideEmptyChild = kWideLeafFlag;

TESSERA_HD constexpr bool wide_is_leaf(std::uint32_t child) {
  return (child & kWideLeafFlag) != 0;
}
TESSERA_HD constexpr std::uint32_t wide_leaf_first(std::uint32_t child) {
  return child & kWideMaxLeafFirst;
}
TESSERA_HD constexpr std::uint32_t wide_leaf_count(std::uint32_t child) {
  return (child >> kWideLeafCountShift) & kWideMaxLeafItems;
}
TESSERA_HD constexpr std::uint32_t make_wide_leaf(std::uint32_t first, std::uint32_t count) {
  return kWideLeafFlag | (count << kWideLeafCountShift) | first;
}

// 256 bytes, four cache lines. bounds[2 * axis] holds the children's lower bounds on that
// axis, bounds[2 * axis + 1] the upper ones; a ray whose direction is negative on an axis
// reads them the other way round, so no per-child min/max is needed. Empty slots hold the
// inverted box (+inf, -inf), which no ray enters.
struct alignas(64) WideBvhNode {
  float bounds[6][kWideBvhWidth];
  std::uint32_t children[kWideBvhWidth];
  std::uint32_t unused[kWideBvhWidth];

  void clear();
  void set_child(std::uint32_t slot, const vec3& lower, const vec3& upper, std::uint32_t child);
};
static_assert(sizeof(WideBvhNode) == 256);

struct WideBvh {
  HugePageVector<WideBvhNode> nodes;  // node 0 is the root; empty when there is nothing to trace
  std::uint32_t depth = 0;            // nodes on the longest root-to-leaf path

  std::size_t bytes() const { return nodes.size() * sizeof(WideBvhNode); }
};

// The most stack entries a wide traversal can need: each level of the path to the current
// node leaves at most kWideBvhWidth - 1 siblings behind.
inline constexpr std::uint32_t kWideStackSize = (kWideBvhWidth - 1) * kMaxBvhDepth + 1;

// Leaf encoder: turns the binary leaf's primitive range [offset, offset + count) of
// Bvh::primitives into a wide child word (see make_wide_leaf).
using WideLeafEncoder = std::function<std::uint32_t(std::uint32_t offset, std::uint32_t count)>;

// The tree's expected cost for a ray that crosses its root box (surface area heuristic,
// in Embree's normalisation so the two builders' trees can be compared): `nodes` sums the
// areas of the interior nodes, `leaves` those of the leaves times their item count (triangle
// blocks), both relative to the root box's area. A random ray through the root box tests
// `nodes` wide nodes and `leaves` blocks on average, ignoring that a closest-hit walk
// stops early.
struct WideSahCost {
  double nodes = 0.0;
  double leaves = 0.0;
};
WideSahCost wide_sah_cost(const WideBvh& tree);

// Collapses a binary BVH: each wide node takes the children of a binary node and keeps
// opening its largest (by surface area) interior child until it has eight children or
// only leaves. The wide tree is never deeper than the binary one.
//
// A binary subtree of at most `merge_limit` primitives that is left over once a node is
// full becomes one leaf with all its primitives (they are contiguous in Bvh::primitives)
// rather than a wide node of its own: visiting a sparsely filled node costs more than
// testing a few more triangles. 0 keeps every binary leaf as it is.
WideBvh collapse_to_wide(const Bvh& binary, const WideLeafEncoder& encode_leaf,
                         std::uint32_t merge_limit = 0);

}  // namespace tessera
