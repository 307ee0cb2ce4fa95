#pragma once
// A light tree (after Conty Estevez and Kulla, "Importance Sampling of Many Lights with
// Adaptive Tree Splitting", 2018): a binary tree over the emitters whose nodes hold their
// bounds and total power. Picking descends from the root, choosing a child in proportion
// to an importance bound that falls with distance and with the angle below the receiving
// surface's horizon, so a shading point samples the lights near it and above it instead
// of every light by its share of the scene's power. Emitters are two-sided, so the
// emitters' orientation does not enter the bound.
#include <cmath>
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

struct LightTreeNode {
  vec3 lower{0.0f}, upper{0.0f};  // bounds of every emitter below
  float power = 0.0f;             // their total
  // Interior: the right child's index (the left child follows the node). Leaf: the light
  // index, with kLeaf set.
  std::uint32_t child_or_light = 0;
  static constexpr std::uint32_t kLeaf = 1u << 31;

  TESSERA_HD bool leaf() const { return (child_or_light & kLeaf) != 0; }
  TESSERA_HD std::uint32_t light() const { return child_or_light & ~kLeaf; }
};

// An upper bound on how much the node's emitters can light point `p` whose surface faces
// `n` (unit; only directions with dot(wi, n) > 0 receive), up to the common factor.
TESSERA_HD TESSERA_INLINE float light_tree_importance(const LightTreeNode& node, const vec3& p,
                                                      const vec3& n) {
  if (!(node.power > 0.0f)) return 0.0f;
  const vec3 center = 0.5f * (node.lower + node.upper);
  const vec3 half = 0.5f * (node.upper - node.lower);
  const float radius2 = glm::dot(half, half);
  const vec3 to_center = center - p;
  const float distance2 = glm::dot(to_center, to_center);
  float cos_bound = 1.0f;
  if (distance2 > radius2) {
    // The bounding sphere subtends a cone of half-angle theta_u about to_center; the
    // smallest angle between n and a direction in it is max(0, theta_n - theta_u).
    const float distance = std::sqrt(distance2);
    const float cos_n = glm::dot(n, to_center) / distance;
    const float sin_u2 = radius2 / distance2;
    const float cos_u = std::sqrt(1.0f - sin_u2);
    if (cos_n < cos_u) {
      const float sin_n = std::sqrt(glm::max(0.0f, 1.0f - cos_n * cos_n));
      cos_bound = cos_n * cos_u + sin_n * std::sqrt(sin_u2);
      if (!(cos_bound > 0.0f)) return 0.0f;
    }
  }
  // Inside the bounds the distance says little: clamp it to the bounds' size, so a cluster
  // around the point does not take every sample from the lights beside it.
  return node.power * cos_bound / glm::max(distance2, radius2);
}

struct TreePick {
  std::uint32_t light = 0;
  float pmf = 0.0f;  // 0: no emitter can light p
};

// Descends from the root with `u` in [0, 1), reusing it at each level.
TESSERA_HD TESSERA_INLINE TreePick light_tree_pick(const LightTreeNode* nodes, const vec3& p,
                                                   const vec3& n, float u) {
  std::uint32_t at = 0;
  float pmf = 1.0f;
  while (!nodes[at].leaf()) {
    const std::uint32_t left = at + 1, right = nodes[at].child_or_light;
    const float il = light_tree_importance(nodes[left], p, n);
    const float ir = light_tree_importance(nodes[right], p, n);
    const float total = il + ir;
    if (!(total > 0.0f)) return TreePick{0, 0.0f};
    const float pl = il / total;
    if (u < pl) {
      u = glm::min(u / pl, 0x1.fffffep-1f);
      pmf *= pl;
      at = left;
    } else {
      u = glm::min((u - pl) / (1.0f - pl), 0x1.fffffep-1f);
      pmf *= 1.0f - pl;
      at = right;
    }
  }
  return TreePick{nodes[at].light(), pmf};
}

// The probability light_tree_pick gives the light whose root-to-leaf path is `path` (bit i
// set: right child at depth i) of `depth` steps.
TESSERA_HD TESSERA_INLINE float light_tree_pmf(const LightTreeNode* nodes, const vec3& p,
                                               const vec3& n, std::uint64_t path,
                                               std::uint32_t depth) {
  std::uint32_t at = 0;
  float pmf = 1.0f;
  for (std::uint32_t level = 0; level < depth; ++level) {
    const std::uint32_t left = at + 1, right = nodes[at].child_or_light;
    const float il = light_tree_importance(nodes[left], p, n);
    const float ir = light_tree_importance(nodes[right], p, n);
    const float total = il + ir;
    if (!(total > 0.0f)) return 0.0f;
    const bool go_right = ((path >> level) & 1u) != 0;
    pmf *= (go_right ? ir : il) / total;
    at = go_right ? right : left;
  }
  return pmf;
}

}  // namespace tessera
