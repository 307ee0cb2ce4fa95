#pragma once
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/geometry/aabb.hpp"

namespace tessera {

// Flattened binary BVH node, 32 bytes (two per cache line), depth-first order: an interior
// node's first child follows it directly and `offset` is the second child's index; a
// leaf's `offset` is the first entry of its primitive range and `count` > 0.
struct BvhNode {
  vec3 lower;
  std::uint32_t offset;
  vec3 upper;
  std::uint32_t count;

  TESSERA_HD bool is_leaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode) == 32);

// Traversal never needs more stack than the tree is deep; the builder caps the depth at
// this so a fixed-size stack can never drop a node.
inline constexpr std::uint32_t kMaxBvhDepth = 64;

// Whether a node at `depth` holding `count` references must be halved by median splits for
// its subtree to fit under kMaxBvhDepth with leaves of at most `max_leaf` (>= 1): it needs
// ceil(log2(leaves)) more levels below its children. The binned and spatial-split builders
// both ask it.
inline bool bvh_near_depth_cap(std::uint32_t depth, std::uint32_t count, std::uint32_t max_leaf) {
  const std::uint32_t leaves = (count + max_leaf - 1) / max_leaf;
  const auto levels = static_cast<std::uint32_t>(leaves <= 1 ? 0 : std::bit_width(leaves - 1));
  return depth + 1 + levels >= kMaxBvhDepth;
}

class TriangleAccel;
class InstanceAccel;
struct WideBvhNode;
struct CompressedWideNode;

struct BvhView {
  const BvhNode* nodes = nullptr;
  const std::uint32_t* primitives = nullptr;  // primitive references, leaf ranges index here
  std::uint32_t node_count = 0;
  // Host only: triangles kept out of this BVH in the CPU's SIMD structure; CPU tracers
  // (BvhTracer) trace them as well. Device code never reads it, so a GPU upload must put
  // those triangles into the BVH it uploads.
  const TriangleAccel* triangles = nullptr;
  // Host only, likewise: placements of shared mesh geometry (two-level), traced by CPU
  // tracers besides `triangles`; its hits name their triangles with the placement's ids.
  const InstanceAccel* instances = nullptr;
  // Host only, likewise: the same tree collapsed into eight-wide nodes
  // (accel/shape_wide_bvh.hpp), its leaves naming ranges of `primitives`; CPU tracers walk
  // it instead of `nodes` when it is set.
  const WideBvhNode* wide_nodes = nullptr;
  // The device layout's form of the same tree (accel/compressed_wide_bvh.hpp), its leaves
  // naming entries of `compressed_primitives`; tracers walk it instead of `nodes` for
  // closest and any hits when it is set. The CPU's own scenes leave it null.
  const CompressedWideNode* compressed_nodes = nullptr;
  const std::uint32_t* compressed_primitives = nullptr;
  // Shapes hidden from camera rays (`visible: false`): a binary tree of its own, walked by
  // every other ray (reflections, bounces, shadow rays), so a hidden light still shows in a
  // mirror, casts and receives light and is weighed by MIS like any emitter. Device code
  // walks it too (DeviceSceneSource uploads it).
  const BvhNode* hidden_nodes = nullptr;
  const std::uint32_t* hidden_primitives = nullptr;
  std::uint32_t hidden_node_count = 0;

  TESSERA_HD BvhView hidden() const {
    BvhView v;
    v.nodes = hidden_nodes;
    v.primitives = hidden_primitives;
    v.node_count = hidden_node_count;
    return v;
  }
};

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<std::uint32_t> primitives;
  std::uint32_t depth = 0;

  BvhView view() const {
    return BvhView{nodes.data(), primitives.data(), static_cast<std::uint32_t>(nodes.size())};
  }
};

struct BvhBuildOptions {
  // A node with more primitives than this is always split; up to this many may share a
  // leaf when the SAH says a split does not pay.
  std::uint32_t max_leaf_size = 4;
  // Leaves are intersected in blocks of this many primitives (4 for the SIMD triangle
  // blocks of the wide BVH), so the SAH counts a leaf's cost in whole blocks.
  std::uint32_t leaf_block_size = 1;
  float traversal_cost = 1.0f;  // relative to one block test
  float intersection_cost = 1.0f;
  std::uint32_t bin_count = 16;  // SAH bins per axis, at most kMaxBvhBins
  bool parallel = true;          // split subtrees (and large binning passes) over TBB workers
};
inline constexpr std::uint32_t kMaxBvhBins = 64;

// Binned SAH build. `references[i]` is stored in leaves for the primitive with `bounds[i]`.
// The tree is at most kMaxBvhDepth deep and no leaf holds more than max_leaf_size
// primitives (both guaranteed: near the depth cap the builder switches to median splits).
Bvh build_bvh(std::span<const Aabb> bounds, std::span<const std::uint32_t> references,
              const BvhBuildOptions& options = {});

}  // namespace tessera
