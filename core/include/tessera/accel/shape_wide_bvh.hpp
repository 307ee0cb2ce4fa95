#pragma once
// The CPU's walk of the shape BVH (every bounded shape but the triangles the SIMD triangle
// structure holds): the binary BVH collapsed into eight-wide nodes (accel/wide_bvh.hpp), so
// one node tests the boxes of up to eight children with two SSE instructions per plane
// instead of a scalar slab test per child. Its leaves are the binary leaves, ranges of
// Bvh::primitives, so the same intersection program tests the same references. GPUs walk
// their own tree in compressed nodes (accel/compressed_wide_bvh.hpp).
#include <cstddef>
#include <cstdint>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/wide_bvh.hpp"

#if !defined(__CUDACC__) && (defined(__SSE2__) || defined(_M_X64))
#define TESSERA_SHAPE_WIDE_WALK 1
#include "tessera/accel/wide_node_sse.hpp"
#else
#define TESSERA_SHAPE_WIDE_WALK 0
#endif

namespace tessera {

// Below this many primitives the binary walk is cheaper: its one or two box tests cost
// less than the wide walk's per-ray setup and eight-lane node test (measured: three quads
// beside a 250k-triangle mesh already favour the wide walk, mesh_250k -5.5% render
// instructions; a triangle scene with one quad light or none lost 1.5% to it).
inline constexpr std::size_t kShapeWideMinPrimitives = 3;

// The wide form of a shape BVH, its leaves naming `binary.primitives` ranges. Empty when
// the binary BVH holds fewer than kShapeWideMinPrimitives primitives or a leaf's range lies
// beyond what a wide leaf word can encode (kWideMaxLeafFirst); BvhView::wide_nodes is then
// left null and tracers walk the binary tree.
WideBvh collapse_shape_bvh(const Bvh& binary);

#if TESSERA_SHAPE_WIDE_WALK
namespace shape_walk_detail {

// A ray's origin or direction as (x, y, z, z) lanes, read one float at a time. Rays are usually
// written just before they are traced, by stores of whatever width the compiler chose; a 16-byte
// load across more than one of them cannot take its data from the store buffer and waits for the
// stores to reach the cache. The walk read the direction as one load at offset 12 of the ray, which
// spans both halves of a ray written as two 16-byte stores (store_ray) or copied as such: perf
// annotate of the converge scene two_lights (Zen 5) put 1.7% of the samples on it. Three scalar
// loads forward from any stores that cover them; the time per sample moved by less than the
// timing's noise (0.98-1.00x), as the other work of the walk's first node overlapped much of the
// wait. The triangle kernels keep their two 16-byte loads: read this way, elephant's rays in the
// Embree comparison (from memory, nothing to forward) ran 0.5-0.8% slower.
inline __m128 ray_lanes(const vec3& v) {
  return _mm_setr_ps(v.x, v.y, v.z, v.z);
}

// The node test's per-ray constants for `ray`: the near plane of each axis is the upper
// bound for a negative direction (an infinite reciprocal for a zero component keeps its
// sign). Formed on four lanes at once: per axis in scalar code (three divisions, ten
// broadcasts from memory, six row words) it was much of the walk's cost in a room of a few
// shapes, whose rays then test one node.
inline wide_node_sse::BoxRay box_ray_of(const Ray& ray) {
  const __m128 origin = ray_lanes(ray.origin);
  const __m128 inverse = _mm_div_ps(_mm_set1_ps(1.0f), ray_lanes(ray.direction));
  return wide_node_sse::BoxRay(origin, inverse, ray.t_min);
}

}  // namespace shape_walk_detail

// Closest-hit or any-hit walk of bvh.wide_nodes, with the contract of traverse_bvh:
// `intersect_primitive(ref, ray, t_max, hit)` tests one reference of bvh.primitives and
// returns true for a hit closer than t_max (filling hit); hit.t bounds the walk on entry.
// Closest-hit visits the children a node's test keeps nearest first (the others wait on
// the stack, sorted), so hit.t shrinks early and farther boxes are dropped when popped.
template <bool kAnyHit, typename IntersectPrimitive>
TESSERA_FORCE_INLINE bool traverse_shape_wide(const BvhView& bvh, const Ray& ray, HitRecord& hit,
                                              IntersectPrimitive&& intersect_primitive) {
  using namespace wide_node_sse;
  const BoxRay box_ray = shape_walk_detail::box_ray_of(ray);
  StackKey stack[kWideStackSize];
  std::uint32_t size = 0;
  std::uint32_t child = 0;  // the root, always an interior node
  bool found = false;
  alignas(16) std::uint32_t entry[kWideBvhWidth];
  for (;;) {
    if (!wide_is_leaf(child)) {
      const WideBvhNode& node = bvh.wide_nodes[child];
      std::uint32_t mask = test_node(node, box_ray, hit.t, entry);
      if (mask != 0) {
        const auto first = static_cast<std::uint32_t>(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {
          child = node.children[first];
          continue;
        }
        // Push every child but the one to visit now; closest-hit sorts the pushed ones
        // so the nearest is on top and visits the nearest of all first.
        const std::uint32_t base = size;
        stack[size++] = stack_key(entry[first], node.children[first]);
        do {
          const auto slot = static_cast<std::uint32_t>(__builtin_ctz(mask));
          mask &= mask - 1;
          const StackKey key = stack_key(entry[slot], node.children[slot]);
          if constexpr (kAnyHit) {
            stack[size++] = key;
          } else {
            // Insertion into the descending run stack[base, size): farthest at the bottom.
            std::uint32_t j = size++;
            for (; j > base && stack[j - 1] < key; --j) stack[j] = stack[j - 1];
            stack[j] = key;
          }
        } while (mask != 0);
        child = static_cast<std::uint32_t>(stack[--size]);
        continue;
      }
    } else {
      const std::uint32_t first = wide_leaf_first(child);
      const std::uint32_t count = wide_leaf_count(child);
      for (std::uint32_t i = 0; i < count; ++i) {
        if (intersect_primitive(bvh.primitives[first + i], ray, hit.t, hit)) {
          found = true;
          if constexpr (kAnyHit) return true;
        }
      }
    }
    // Pop; an entry whose box starts beyond the closest hit so far (widened like the box
    // test's far end) cannot hold a nearer hit.
    StackKey popped;
    do {
      if (size == 0) return found;
      popped = stack[--size];
    } while (!kAnyHit && key_distance(popped) > (hit.t > 0.0f ? hit.t : 0.0f) * kFarScale);
    child = static_cast<std::uint32_t>(popped);
  }
}
#endif

}  // namespace tessera
