#pragma once
// The BVH as device code walks it: eight children per node, their boxes quantised to eight
// bits per plane against the node's box (after Ylitie, Karras and Laine 2017, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs"). A node is 80 bytes where
// the binary tree spends 32 per child, and a ray reads one node per level of a tree a third
// as deep. The children are ordered for the ray's octant when the tree is built, so the walk
// visits them roughly front to back without sorting, and its stack holds one four-byte
// entry per level (a node and the children of it still to visit), 128 bytes per thread.
//
// The CPU walks the SIMD structures instead; it runs this walk only when it renders through
// the device layout (PreparedScene::render_tile_device_layout), which is how the walk is
// tested on machines without a GPU.
#include <cstdint>
#include <cstring>
#include <vector>

#include "tessera/accel/bvh.hpp"

namespace tessera {

// Child slot s of a node is an interior node when bit s of inner_mask is set (its index is
// child_base plus the number of interior slots before s), a leaf when leaf_count[s] > 0 (its
// primitives follow those of the leaves in lower slots from primitive_base in
// CompressedWideBvh::primitives), and empty otherwise. A child's box on axis a is
// origin[a] + q * 2^exponent[a] for q = lower[a][s] and upper[a][s]; the products are
// exact, so the one rounding of the sum is the same on every device, and the builder keeps
// each box around everything below it after that rounding.
struct alignas(16) CompressedWideNode {
  float origin[3];
  std::int8_t exponent[3];
  std::uint8_t inner_mask;
  std::uint32_t child_base;
  std::uint32_t primitive_base;
  std::uint8_t leaf_count[8];
  std::uint8_t lower[3][8];
  std::uint8_t upper[3][8];
};
static_assert(sizeof(CompressedWideNode) == 80);

// Exponents stay within the normal floats', so 2^e and q * 2^e are exact.
inline constexpr int kCompressedMinExponent = -126;
inline constexpr int kCompressedMaxExponent = 127;

// The walk's stack entry packs a node index below kCompressedMaxNodes with the eight bits
// of its children still to visit, and the stack has a slot per level: trees with more nodes
// (a scene of some hundred million primitives) or more levels (a binary tree of 32 levels
// or more in every branch collapsed) keep the binary walk.
inline constexpr std::uint32_t kCompressedMaxNodes = 1U << 24;
inline constexpr std::uint32_t kCompressedMaxDepth = 32;

struct CompressedWideBvh {
  std::vector<CompressedWideNode> nodes;  // node 0 is the root; empty: walk the binary tree
  std::vector<std::uint32_t> primitives;  // references, each node's leaves in slot order
  std::uint32_t depth = 0;
};

// The compressed form of `binary` (collapsed as collapse_to_wide does, binary leaves kept).
// Empty when the binary tree is, when a leaf lies beyond what a wide leaf word encodes
// (accel/wide_bvh.hpp), when a box is not finite, or beyond kCompressedMaxNodes or
// kCompressedMaxDepth: the device then walks the binary tree.
CompressedWideBvh compress_bvh(const Bvh& binary);

namespace compressed_detail {

TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t lowest_bit(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  return static_cast<std::uint32_t>(__ffs(x) - 1);
#else
  return static_cast<std::uint32_t>(__builtin_ctz(x));
#endif
}

TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t bit_count(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  return static_cast<std::uint32_t>(__popc(x));
#else
  return static_cast<std::uint32_t>(__builtin_popcount(x));
#endif
}

// 2^e for kCompressedMinExponent <= e <= kCompressedMaxExponent, built from its bits.
TESSERA_HD TESSERA_FORCE_INLINE float power_of_two(int e) {
  const auto bits = static_cast<std::uint32_t>(e + 127) << 23;
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

// The dequantised plane: exact product, one rounding in the sum.
TESSERA_HD TESSERA_FORCE_INLINE float plane(float origin, float scale, std::uint8_t q) {
  return origin + static_cast<float>(q) * scale;
}

// The box of slot `slot`.
TESSERA_HD TESSERA_FORCE_INLINE void child_box(const CompressedWideNode& node, std::uint32_t slot,
                                               vec3& lower, vec3& upper) {
  for (int axis = 0; axis < 3; ++axis) {
    const float scale = power_of_two(node.exponent[axis]);
    lower[axis] = plane(node.origin[axis], scale, node.lower[axis][slot]);
    upper[axis] = plane(node.origin[axis], scale, node.upper[axis][slot]);
  }
}

// The first primitive of leaf slot `slot`: primitive_base plus the counts of the slots below,
// summed as the bytes of one word (the builder keeps a node's total under 256).
TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t leaf_first(const CompressedWideNode& node,
                                                         std::uint32_t slot) {
  std::uint64_t counts;
  std::memcpy(&counts, node.leaf_count, sizeof(counts));
  const std::uint64_t below = slot == 0 ? 0 : counts & ((std::uint64_t{1} << (8 * slot)) - 1);
  return node.primitive_base + static_cast<std::uint32_t>((below * 0x0101010101010101ULL) >> 56);
}

// The children of `node` the ray enters within [t_min, t_max], as bits in visiting order:
// bit k stands for slot k ^ octant.
TESSERA_HD TESSERA_FORCE_INLINE std::uint32_t enter_children(const CompressedWideNode& node,
                                                             const TraversalRay& ray, float t_min,
                                                             float t_max, std::uint32_t octant) {
  std::uint32_t entered = 0;
  // Not unrolled on the device: eight copies of the slab test raised the path tracer's
  // registers and stack.
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (std::uint32_t slot = 0; slot < 8; ++slot) {
    if (node.leaf_count[slot] == 0 && ((node.inner_mask >> slot) & 1U) == 0) continue;
    vec3 lower, upper;
    child_box(node, slot, lower, upper);
    float t_entry;
    if (intersect_aabb(lower, upper, ray, t_min, t_max, t_entry)) entered |= 1U << (slot ^ octant);
  }
  return entered;
}

}  // namespace compressed_detail

// Closest-hit or any-hit walk of bvh.compressed_nodes with the contract of traverse_bvh:
// `intersect_primitive(ref, ray, t_max, hit)` tests one reference of bvh.compressed_primitives
// and returns true for a hit closer than t_max (filling hit); hit.t bounds the walk on entry.
// Children wait on the stack as the bits of their parent's entry, and an interior child
// taken from it tests its own children against the nearest hit found by then.
template <bool kAnyHit, typename IntersectPrimitive>
TESSERA_HD bool traverse_compressed_wide(const BvhView& bvh, const Ray& ray, HitRecord& hit,
                                         IntersectPrimitive&& intersect_primitive) {
  using namespace compressed_detail;
  const CompressedWideNode* nodes = bvh.compressed_nodes;
  const TraversalRay tray(ray);
  // The octant whose children the builder put first: a negative reciprocal (as the slab
  // test reads the near plane) sets the axis' bit.
  const std::uint32_t octant = (tray.inv_direction.x < 0.0f ? 1U : 0U) |
                               (tray.inv_direction.y < 0.0f ? 2U : 0U) |
                               (tray.inv_direction.z < 0.0f ? 4U : 0U);
  // Entries: a node's index in the low 24 bits, its children still to visit in the high 8.
  // Each is an ancestor of the node being visited, so the tree's depth bounds them.
  std::uint32_t stack[kCompressedMaxDepth];
  std::uint32_t size = 0;
  std::uint32_t node_index = 0;
  std::uint32_t pending = enter_children(nodes[0], tray, ray.t_min, hit.t, octant);
  bool found = false;
  for (;;) {
    while (pending != 0) {
      const std::uint32_t slot = lowest_bit(pending) ^ octant;
      pending &= pending - 1;
      const CompressedWideNode& node = nodes[node_index];
      if (((node.inner_mask >> slot) & 1U) != 0) {
        if (pending != 0) stack[size++] = (pending << 24) | node_index;
        node_index = node.child_base + bit_count(node.inner_mask & ((1U << slot) - 1U));
        pending = enter_children(nodes[node_index], tray, ray.t_min, hit.t, octant);
        continue;
      }
      const std::uint32_t first = leaf_first(node, slot);
      const std::uint32_t count = node.leaf_count[slot];
      for (std::uint32_t i = 0; i < count; ++i) {
        if (intersect_primitive(bvh.compressed_primitives[first + i], ray, hit.t, hit)) {
          found = true;
          if constexpr (kAnyHit) return true;
        }
      }
    }
    if (size == 0) return found;
    const std::uint32_t entry = stack[--size];
    node_index = entry & (kCompressedMaxNodes - 1U);
    pending = entry >> 24;
  }
}

}  // namespace tessera
