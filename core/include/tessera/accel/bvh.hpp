#pragma once
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

struct BvhView {
  const BvhNode* nodes = nullptr;
  const std::uint32_t* primitives = nullptr;  // primitive references, leaf ranges index here
  std::uint32_t node_count = 0;
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
  std::uint32_t max_leaf_size = 4;
  float traversal_cost = 1.0f;  // relative to one primitive test
  float intersection_cost = 1.0f;
};

// Binned SAH build. `references[i]` is stored in leaves for the primitive with `bounds[i]`.
Bvh build_bvh(std::span<const Aabb> bounds, std::span<const std::uint32_t> references,
              const BvhBuildOptions& options = {});

}  // namespace tessera
