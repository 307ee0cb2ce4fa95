#pragma once
// The eight-wide node's box test in SSE2 (two four-lane halves) and the walks' stack keys,
// shared by the SIMD triangle kernels' SSE2 build (core/accel/triangle_kernels.inl) and the
// CPU walk of the shape BVH (accel/shape_wide_bvh.hpp). x86 host code only.
#include <emmintrin.h>

#include <cstdint>
#include <cstring>

#include "tessera/accel/wide_bvh.hpp"
#include "tessera/math/host_device.hpp"

namespace tessera::wide_node_sse {

// The far end of each box interval (the box's exit, or the closest hit so far if nearer)
// is widened by two ulps, folded into the far planes' reciprocals and into t_max, which
// with the subtract-then-multiply slab test keeps boxes from being missed through rounding
// (Ize, "Robust BVH ray traversal", JCGT 2013): a flat box holding an axis-aligned quad,
// or a box entered at the same distance, up to rounding, as the hit found so far.
inline constexpr float kFarScale = 1.0f + 2.0f * 1.1920929e-07f;

// Per-ray constants of the slab tests, four lanes each. Rows: bounds[2 * axis] holds the
// children's lower planes; near_row/far_row say which row is the near and which the far
// plane per axis (the upper row is near for a negative direction).
struct BoxRay {
  __m128 origin[3], inv_direction[3], inv_direction_far[3], t_min;
  std::uint32_t near_row[3], far_row[3];

  // From the ray's origin and reciprocal direction as (x, y, z, unused) lanes: shuffles and
  // one sign mask, where the per-axis form below takes ten broadcasts from memory.
  BoxRay(__m128 ray_origin, __m128 ray_inv_direction, float ray_t_min) {
    const __m128 inv_far = _mm_mul_ps(ray_inv_direction, _mm_set1_ps(kFarScale));
    origin[0] = _mm_shuffle_ps(ray_origin, ray_origin, _MM_SHUFFLE(0, 0, 0, 0));
    origin[1] = _mm_shuffle_ps(ray_origin, ray_origin, _MM_SHUFFLE(1, 1, 1, 1));
    origin[2] = _mm_shuffle_ps(ray_origin, ray_origin, _MM_SHUFFLE(2, 2, 2, 2));
    inv_direction[0] =
        _mm_shuffle_ps(ray_inv_direction, ray_inv_direction, _MM_SHUFFLE(0, 0, 0, 0));
    inv_direction[1] =
        _mm_shuffle_ps(ray_inv_direction, ray_inv_direction, _MM_SHUFFLE(1, 1, 1, 1));
    inv_direction[2] =
        _mm_shuffle_ps(ray_inv_direction, ray_inv_direction, _MM_SHUFFLE(2, 2, 2, 2));
    inv_direction_far[0] = _mm_shuffle_ps(inv_far, inv_far, _MM_SHUFFLE(0, 0, 0, 0));
    inv_direction_far[1] = _mm_shuffle_ps(inv_far, inv_far, _MM_SHUFFLE(1, 1, 1, 1));
    inv_direction_far[2] = _mm_shuffle_ps(inv_far, inv_far, _MM_SHUFFLE(2, 2, 2, 2));
    t_min = _mm_set1_ps(ray_t_min);
    // The upper row is the near plane where the reciprocal is negative (-0 gives -inf).
    const auto negative = static_cast<std::uint32_t>(
        _mm_movemask_ps(_mm_cmplt_ps(ray_inv_direction, _mm_setzero_ps())));
    for (std::uint32_t axis = 0; axis < 3; ++axis) {
      const std::uint32_t flip = (negative >> axis) & 1U;
      near_row[axis] = 2 * axis + flip;
      far_row[axis] = 2 * axis + 1 - flip;
    }
  }
  BoxRay(const float (&ray_origin)[3], const float (&ray_inv_direction)[3],
         const std::uint32_t (&near)[3], const std::uint32_t (&far)[3], float ray_t_min) {
    for (int axis = 0; axis < 3; ++axis) {
      origin[axis] = _mm_set1_ps(ray_origin[axis]);
      inv_direction[axis] = _mm_set1_ps(ray_inv_direction[axis]);
      inv_direction_far[axis] = _mm_set1_ps(ray_inv_direction[axis] * kFarScale);
      near_row[axis] = near[axis];
      far_row[axis] = far[axis];
    }
    t_min = _mm_set1_ps(ray_t_min);
  }
};

// Mask of the children whose box the ray enters within [t_min, t_max]; `entry` receives
// the bits of their entry distances clamped to >= +0, which order like the values (max
// returns its second operand for -0 and NaN). A zero direction component gives an infinite
// reciprocal, and an origin lying on that axis' plane gives 0 * inf = NaN: max/min take the
// plane distances first and the accumulated interval second, and return the second operand
// for a NaN, so a NaN plane leaves the interval unchanged (the ray counts as inside that
// slab, boundary included).
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

// Stack entries pack the child's entry distance (high half, as float bits) and the child
// word (low half) into one integer. Entry distances are clamped to >= 0 (test_node), where
// float bits order like the values, so sorting entries is sorting integers and compiles to
// conditional moves instead of unpredictable branches. A key of 0 stands for any entry
// distance <= 0, so a pop compares keys with max(t_max, 0): a ray with t_min < 0 whose best
// hit so far lies behind its origin must still visit them.
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

}  // namespace tessera::wide_node_sse
