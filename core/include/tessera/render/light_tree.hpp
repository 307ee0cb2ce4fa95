#pragma once
// A light tree (after Conty Estevez and Kulla, "Importance Sampling of Many Lights with
// Adaptive Tree Splitting", 2018): a tree over the emitters whose nodes hold their bounds
// and total power. Picking descends from the root, choosing a child in proportion to an
// importance bound that falls with distance and with the angle below the receiving
// surface's horizon, so a shading point samples the lights near it and above it instead
// of every light by its share of the scene's power. Emitters are two-sided, so the
// emitters' orientation does not enter the bound.
//
// The tree is four-wide, and a node stores its children's bounds side by side: a step of
// the walk computes four importances at once (one SSE instruction each on the host) and
// the walk is half as deep as a binary tree's. A binary walk over 1,024 triangles cost
// about a third of the colour-bleed-style emissive scene's render time, more than the tree
// saved over picking by power.
#include <cmath>
#include <cstdint>

#include "tessera/math/sampling.hpp"
#include "tessera/math/vec.hpp"

#if !defined(__CUDA_ARCH__) && (defined(__SSE2__) || defined(_M_X64))
#include <emmintrin.h>
#define TESSERA_LIGHT_TREE_SSE 1
#endif

namespace tessera {

struct alignas(16) LightTreeNode {
  static constexpr std::uint32_t kWidth = 4;
  // Child k's bounding sphere (centre_x[k], ...; radius2[k] its squared radius) and total
  // power; an unused slot has power 0. The importance needs only the sphere, so it is stored
  // instead of the box it encloses: the walk's loads and arithmetic before the first square
  // root are shorter by an add and a multiply, and a node fits in 96 bytes instead of 128.
  float centre_x[kWidth], centre_y[kWidth], centre_z[kWidth];
  float radius2[kWidth];
  float power[kWidth];
  // Child k: the index of its node, or the light index with kLeaf set.
  std::uint32_t child[kWidth];
  static constexpr std::uint32_t kLeaf = 1u << 31;

  TESSERA_HD static bool is_leaf(std::uint32_t c) { return (c & kLeaf) != 0; }
  TESSERA_HD static std::uint32_t light_of(std::uint32_t c) { return c & ~kLeaf; }
};

// Bits of LightSource::tree_path per level: the child slot taken.
inline constexpr std::uint32_t kLightTreePathBits = 2;
// 64 path bits hold 32 levels.
inline constexpr std::uint32_t kLightTreeMaxDepth = 64 / kLightTreePathBits;

// Upper bounds on how much each child's emitters can light point `p` whose surface faces
// `n` (unit; only directions with dot(wi, n) > 0 receive), up to a common factor. The
// bounding sphere of a child's box subtends a cone of half-angle theta_u about the
// direction to its centre; the smallest angle between n and a direction in it is
// max(0, theta_n - theta_u). Inside the bounds the distance says little: it is clamped to
// the bounds' size, so a cluster around the point does not take every sample from the
// lights beside it.
//
// With d2 the squared distance to the centre, r2 the sphere's squared radius and
// t = dot(n, to centre): cos theta_u = sqrt(d2 - r2) / sqrt(d2), cos theta_n = t / sqrt(d2),
// so the cone narrows the bound where t < sqrt(d2 - r2), and then
// cos(theta_n - theta_u) d2 = t sqrt(d2 - r2) + sqrt((d2 - t^2) r2). Written so, a step
// takes two independent square roots and no division on the bound's path, where the
// angles' cosines and sines took four square roots and two divisions mostly one after
// another: the same instructions, 2-4% less render time on scenes with a tree
// (bench/converge/README.md).
// A child is far when its sphere is small for its distance (d2 > kLightTreeFarDistance2 r2)
// and wholly above the horizon with cosines that vary little across it: the cosine at the
// cone's edge farthest from n, cos(theta_n + theta_u) d2 = t sqrt(d2 - r2) -
// sqrt((d2 - t^2) r2), is at least 1 / kLightTreeFarCosineSpread of the one at its nearest
// edge. Below a far child every light's importance is its power times a factor that differs
// from light to light by at most the spread times ((1 + 1/sqrt(K)) / (1 - 1/sqrt(K)))^2, so
// the walk picks below it by power alone: no square roots or divisions for the importance,
// the same pick for any (p, n), and nothing below the horizon. Measured on the 1,024-emitter
// scene and eight others (bench/converge/README.md, "Far clusters by power").
inline constexpr float kLightTreeFarDistance2 = 6.0f;
inline constexpr float kLightTreeFarCosineSpread = 3.0f;

// The host's SSE path and light_tree_importance_portable compute the same IEEE operations
// in the same order, so light_tree_pick and light_tree_pmf agree bit for bit on either.
// `far_slots` gets bit k set when child k is far.
TESSERA_HD TESSERA_INLINE void light_tree_importance_portable(const LightTreeNode& node,
                                                              const vec3& p, const vec3& n,
                                                              float importance[4],
                                                              std::uint32_t& far_slots) {
  far_slots = 0;
  for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) {
    const float radius2 = node.radius2[k];
    const float tx = node.centre_x[k] - p.x;
    const float ty = node.centre_y[k] - p.y;
    const float tz = node.centre_z[k] - p.z;
    const float distance2 = (tx * tx + ty * ty) + tz * tz;
    const float n_dot = (n.x * tx + n.y * ty) + n.z * tz;
    const float power = node.power[k];
    const float tangent = std::sqrt(fmaxf(0.0f, distance2 - radius2));
    const float along = n_dot * tangent;
    const float across = std::sqrt(fmaxf(0.0f, distance2 - n_dot * n_dot) * radius2);
    float value = power / fmaxf(distance2, radius2);
    bool lit = power > 0.0f;
    if (distance2 > radius2 && n_dot < tangent) {
      const float cos_bound_d2 = along + across;
      const float inverse2 = 1.0f / distance2;
      value = ((power * inverse2) * cos_bound_d2) * inverse2;
      lit = lit && cos_bound_d2 > 0.0f;
    }
    importance[k] = lit ? value : 0.0f;
    if (distance2 > kLightTreeFarDistance2 * radius2 &&
        (kLightTreeFarCosineSpread - 1.0f) * along >= (kLightTreeFarCosineSpread + 1.0f) * across)
      far_slots |= 1u << k;
  }
}

TESSERA_HD TESSERA_INLINE void light_tree_importance(const LightTreeNode& node, const vec3& p,
                                                     const vec3& n, float importance[4],
                                                     std::uint32_t& far_slots) {
#if defined(TESSERA_LIGHT_TREE_SSE)
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 power = _mm_load_ps(node.power);
  const __m128 radius2 = _mm_load_ps(node.radius2);
  const __m128 tx = _mm_sub_ps(_mm_load_ps(node.centre_x), _mm_set1_ps(p.x));
  const __m128 ty = _mm_sub_ps(_mm_load_ps(node.centre_y), _mm_set1_ps(p.y));
  const __m128 tz = _mm_sub_ps(_mm_load_ps(node.centre_z), _mm_set1_ps(p.z));
  const __m128 distance2 =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(tx, tx), _mm_mul_ps(ty, ty)), _mm_mul_ps(tz, tz));
  const __m128 n_dot =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(n.x), tx), _mm_mul_ps(_mm_set1_ps(n.y), ty)),
                 _mm_mul_ps(_mm_set1_ps(n.z), tz));
  // fmaxf(0, x) as _mm_max_ps(x, 0) (max returns its second operand for NaN, as fmaxf
  // returns the number).
  const __m128 tangent = _mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(distance2, radius2), zero));
  const __m128 along = _mm_mul_ps(n_dot, tangent);
  const __m128 across = _mm_sqrt_ps(
      _mm_mul_ps(_mm_max_ps(_mm_sub_ps(distance2, _mm_mul_ps(n_dot, n_dot)), zero), radius2));
  const __m128 inverse2 = _mm_div_ps(one, distance2);
  const __m128 wide_value = _mm_div_ps(power, _mm_max_ps(distance2, radius2));
  const __m128 narrow = _mm_and_ps(_mm_cmpgt_ps(distance2, radius2), _mm_cmplt_ps(n_dot, tangent));
  const __m128 cos_bound_d2 = _mm_add_ps(along, across);
  const __m128 narrow_value =
      _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(power, inverse2), cos_bound_d2), inverse2);
  const __m128 value =
      _mm_or_ps(_mm_and_ps(narrow, narrow_value), _mm_andnot_ps(narrow, wide_value));
  // Lit: some power, and not narrowed to a bound of zero or less.
  const __m128 dark = _mm_andnot_ps(_mm_cmpgt_ps(cos_bound_d2, zero), narrow);
  const __m128 lit = _mm_andnot_ps(dark, _mm_cmpgt_ps(power, zero));
  _mm_storeu_ps(importance, _mm_and_ps(lit, value));
  const __m128 far =
      _mm_and_ps(_mm_cmpgt_ps(distance2, _mm_mul_ps(_mm_set1_ps(kLightTreeFarDistance2), radius2)),
                 _mm_cmpge_ps(_mm_mul_ps(_mm_set1_ps(kLightTreeFarCosineSpread - 1.0f), along),
                              _mm_mul_ps(_mm_set1_ps(kLightTreeFarCosineSpread + 1.0f), across)));
  far_slots = static_cast<std::uint32_t>(_mm_movemask_ps(far));
#else
  light_tree_importance_portable(node, p, n, importance, far_slots);
#endif
}

// What the walk weighs node's children by: their importances from (p, n), or, below a far
// child (`far`), their powers.
TESSERA_HD TESSERA_INLINE void light_tree_weights(const LightTreeNode& node, const vec3& p,
                                                  const vec3& n, bool far, float weight[4],
                                                  std::uint32_t& far_slots) {
  if (far) {
    for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) weight[k] = node.power[k];
    far_slots = 0;
  } else {
    light_tree_importance(node, p, n, weight, far_slots);
  }
}

struct TreePick {
  std::uint32_t light = 0;
  float pmf = 0.0f;  // 0: no emitter can light p
  float u = 0.0f;    // the pick's u stretched back to [0, 1) within the light's share
};

// Descends from the root with `u` in [0, 1), reusing it at each level: at a node, child
// k is taken when u falls in its share of the summed importances, and u is rescaled to
// that share (what is left of it at the leaf is TreePick::u).
TESSERA_HD TESSERA_INLINE TreePick light_tree_pick(const LightTreeNode* nodes, const vec3& p,
                                                   const vec3& n, float u) {
  std::uint32_t at = 0;
  float pmf = 1.0f;
  bool far = false;
  for (;;) {
    const LightTreeNode& node = nodes[at];
    float importance[4];
    std::uint32_t far_slots;
    light_tree_weights(node, p, n, far, importance, far_slots);
    // below[k]: the sum of the weights before slot k, added in the order `total` adds them.
    const float below[4] = {0.0f, importance[0], importance[0] + importance[1],
                            (importance[0] + importance[1]) + importance[2]};
    const float total = below[3] + importance[3];
    if (!(total > 0.0f)) return TreePick{0, 0.0f};
    const float target = u * total;
    // The first slot whose running sum passes the target, counted without branches: where
    // sibling weights are alike (equal emitters, or any subtree picked by power) the slot is
    // as random as u and a branch per slot mispredicted most of the time. A slot with no
    // weight adds nothing to the sums, so it is never the one reached while the target is
    // below the total (u < 1 keeps it there); the loop after is a guard that would take the
    // last slot with any weight.
    std::uint32_t slot = static_cast<std::uint32_t>(target >= below[1]) +
                         static_cast<std::uint32_t>(target >= below[2]) +
                         static_cast<std::uint32_t>(target >= below[3]);
    if (!(importance[slot] > 0.0f)) [[unlikely]] {  // one predictable test, not one on slot
      while (slot > 0 && !(importance[slot] > 0.0f)) --slot;
    }
    const float before = below[slot];
    pmf *= importance[slot] / total;
    u = clamp_below_one((target - before) / importance[slot]);
    far = far || ((far_slots >> slot) & 1u) != 0;
    const std::uint32_t child = node.child[slot];
    if (LightTreeNode::is_leaf(child)) return TreePick{LightTreeNode::light_of(child), pmf, u};
    at = child;
  }
}

// The probability light_tree_pick gives the light whose root-to-leaf path is `path`
// (kLightTreePathBits per level: the slot taken at that depth) of `depth` steps.
TESSERA_HD TESSERA_INLINE float light_tree_pmf(const LightTreeNode* nodes, const vec3& p,
                                               const vec3& n, std::uint64_t path,
                                               std::uint32_t depth) {
  std::uint32_t at = 0;
  float pmf = 1.0f;
  bool far = false;
  for (std::uint32_t level = 0; level < depth; ++level) {
    const LightTreeNode& node = nodes[at];
    float importance[4];
    std::uint32_t far_slots;
    light_tree_weights(node, p, n, far, importance, far_slots);
    const float total = ((importance[0] + importance[1]) + importance[2]) + importance[3];
    if (!(total > 0.0f)) return 0.0f;
    const auto slot = static_cast<std::uint32_t>((path >> (kLightTreePathBits * level)) & 3u);
    pmf *= importance[slot] / total;
    far = far || ((far_slots >> slot) & 1u) != 0;
    at = node.child[slot];
  }
  return pmf;
}

}  // namespace tessera
