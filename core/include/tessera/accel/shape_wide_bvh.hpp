#pragma once
// The CPU's walk of the shape BVH (every bounded shape but the triangles the SIMD triangle
// structure holds): the binary BVH collapsed into eight-wide nodes (accel/wide_bvh.hpp), so
// one node tests the boxes of up to eight children with two SSE instructions per plane
// instead of a scalar slab test per child. Its leaves are the binary leaves, ranges of
// Bvh::primitives, so the same intersection program tests the same references; the binary
// BVH stays the layout uploaded to GPUs, which walk it with traverse_bvh.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/wide_bvh.hpp"

#if !defined(__CUDACC__) && (defined(__SSE2__) || defined(_M_X64))
#define TESSERA_SHAPE_WIDE_WALK 1
#include <emmintrin.h>
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

// The far end of each box interval is widened by two ulps, as intersect_aabb does (Ize
// 2013), so rounding never drops a flat box (an axis-aligned quad's) or one entered at the
// distance of the hit found so far.
inline constexpr float kFarScale = 1.0f + 2.0f * 1.1920929e-07f;

// Per-ray constants of the slab tests, four lanes each. Rows: bounds[2 * axis] holds the
// children's lower planes; a negative direction reads the upper row as the near plane.
// A zero direction component gives an infinite reciprocal, and an origin lying on that
// axis' plane gives 0 * inf = NaN; max/min below take the accumulated interval as their
// second operand, which they return for a NaN plane, so the plane does not limit the
// interval, exactly as intersect_aabb treats it.
struct BoxRay {
  __m128 origin[3], inv_direction[3], inv_direction_far[3], t_min;
  std::uint32_t near_row[3], far_row[3];

  explicit BoxRay(const Ray& ray) {
    for (int axis = 0; axis < 3; ++axis) {
      const float inv = 1.0f / ray.direction[axis];
      origin[axis] = _mm_set1_ps(ray.origin[axis]);
      inv_direction[axis] = _mm_set1_ps(inv);
      inv_direction_far[axis] = _mm_set1_ps(inv * kFarScale);
      const std::uint32_t negative = inv < 0.0f ? 1U : 0U;
      near_row[axis] = 2 * static_cast<std::uint32_t>(axis) + negative;
      far_row[axis] = 2 * static_cast<std::uint32_t>(axis) + 1 - negative;
    }
    t_min = _mm_set1_ps(ray.t_min);
  }
};

// Mask of the children whose box the ray enters within [t_min, t_max]; `entry` receives
// the bits of their entry distances clamped to >= +0, which order like the values.
TESSERA_FORCE_INLINE std::uint32_t test_node(const WideBvhNode& node, const BoxRay& b, float t_max,
                                             std::uint32_t* entry) {
  std::uint32_t mask = 0;
  const __m128 far_limit = _mm_set1_ps(t_max * kFarScale);
  for (int half = 0; half < 2; ++half) {
    const int lane = 4 * half;
    const auto slab = [&](std::uint32_t row, int axis, const __m128* inv) {
      return _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.bounds[row] + lane), b.origin[axis]),
                        inv[axis]);
    };
    const __m128 near_x = slab(b.near_row[0], 0, b.inv_direction);
    const __m128 near_y = slab(b.near_row[1], 1, b.inv_direction);
    const __m128 near_z = slab(b.near_row[2], 2, b.inv_direction);
    const __m128 far_x = slab(b.far_row[0], 0, b.inv_direction_far);
    const __m128 far_y = slab(b.far_row[1], 1, b.inv_direction_far);
    const __m128 far_z = slab(b.far_row[2], 2, b.inv_direction_far);
    const __m128 t_near = _mm_max_ps(near_x, _mm_max_ps(near_y, _mm_max_ps(near_z, b.t_min)));
    const __m128 t_far = _mm_min_ps(far_x, _mm_min_ps(far_y, _mm_min_ps(far_z, far_limit)));
    _mm_storeu_ps(reinterpret_cast<float*>(entry + lane), _mm_max_ps(t_near, _mm_setzero_ps()));
    mask |= static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmple_ps(t_near, t_far))) << lane;
  }
  return mask;
}

// Stack entries: the child's entry distance bits (high half) and its child word (low
// half), so ordering entries is ordering integers.
using StackKey = std::uint64_t;
TESSERA_FORCE_INLINE StackKey stack_key(std::uint32_t distance_bits, std::uint32_t child) {
  return (static_cast<StackKey>(distance_bits) << 32) | child;
}
inline float key_distance(StackKey key) {
  const auto bits = static_cast<std::uint32_t>(key >> 32);
  float t;
  std::memcpy(&t, &bits, sizeof t);
  return t;
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
  using namespace shape_walk_detail;
  const BoxRay box_ray(ray);
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
