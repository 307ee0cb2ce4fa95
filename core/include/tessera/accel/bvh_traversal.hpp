#pragma once
#include "tessera/accel/bvh.hpp"
#include "tessera/accel/nearest_hits.hpp"

namespace tessera {

// Closest-hit or any-hit traversal of a BvhView. `intersect_primitive(ref, ray, t_max, hit)`
// tests one primitive and returns true if it found a hit closer than t_max (filling hit).
// With kAnyHit the walk stops at the first hit, which is all a shadow ray needs.
template <bool kAnyHit, typename IntersectPrimitive>
TESSERA_HD bool traverse_bvh(const BvhView& bvh, const Ray& ray, HitRecord& hit,
                             IntersectPrimitive&& intersect_primitive) {
  if (bvh.node_count == 0) return false;
  const TraversalRay tray(ray);
  std::uint32_t stack[kMaxBvhDepth];
  std::uint32_t stack_size = 0;
  std::uint32_t node_index = 0;
  bool found = false;
  float t_entry;
  if (!intersect_aabb(bvh.nodes[0].lower, bvh.nodes[0].upper, tray, ray.t_min, hit.t, t_entry))
    return false;
  for (;;) {
    const BvhNode& node = bvh.nodes[node_index];
    if (node.is_leaf()) {
      for (std::uint32_t i = 0; i < node.count; ++i) {
        if (intersect_primitive(bvh.primitives[node.offset + i], ray, hit.t, hit)) {
          found = true;
          if constexpr (kAnyHit) return true;
        }
      }
    } else {
      const std::uint32_t left = node_index + 1;
      const std::uint32_t right = node.offset;
      float t_left, t_right;
      const bool hit_left = intersect_aabb(bvh.nodes[left].lower, bvh.nodes[left].upper, tray,
                                           ray.t_min, hit.t, t_left);
      const bool hit_right = intersect_aabb(bvh.nodes[right].lower, bvh.nodes[right].upper, tray,
                                            ray.t_min, hit.t, t_right);
      if (hit_left && hit_right) {
        // Visit the nearer child first; the farther one waits on the stack.
        const bool left_first = t_left <= t_right;
        stack[stack_size++] = left_first ? right : left;
        node_index = left_first ? left : right;
        continue;
      }
      if (hit_left) {
        node_index = left;
        continue;
      }
      if (hit_right) {
        node_index = right;
        continue;
      }
    }
    if (stack_size == 0) break;
    node_index = stack[--stack_size];
  }
  return found;
}

}  // namespace tessera

namespace tessera {

// All-hits traversal of a BvhView: keeps the `capacity` nearest hits in (t_min, t_max),
// sorted by t, in `hits`; returns how many. Once `capacity` hits are kept the farthest of
// them bounds the walk. `intersect_primitive` is called as for traverse_bvh, with the
// current bound as t_max; each primitive is met once, so it is recorded at most once.
template <typename IntersectPrimitive>
TESSERA_HD std::uint32_t traverse_bvh_all(const BvhView& bvh, const Ray& ray, HitRecord* hits,
                                          std::uint32_t capacity,
                                          IntersectPrimitive&& intersect_primitive) {
  if (bvh.node_count == 0 || capacity == 0) return 0;
  const TraversalRay tray(ray);
  std::uint32_t stack[kMaxBvhDepth];
  std::uint32_t stack_size = 0;
  std::uint32_t node_index = 0;
  std::uint32_t count = 0;
  float t_max = ray.t_max;
  float t_entry;
  if (!intersect_aabb(bvh.nodes[0].lower, bvh.nodes[0].upper, tray, ray.t_min, t_max, t_entry))
    return 0;
  for (;;) {
    const BvhNode& node = bvh.nodes[node_index];
    if (node.is_leaf()) {
      for (std::uint32_t i = 0; i < node.count; ++i) {
        HitRecord hit;
        if (!intersect_primitive(bvh.primitives[node.offset + i], ray, t_max, hit)) continue;
        if (insert_nearest(hits, count, capacity, hit)) t_max = hits[capacity - 1].t;
      }
    } else {
      const std::uint32_t left = node_index + 1;
      const std::uint32_t right = node.offset;
      float t_left, t_right;
      const bool hit_left = intersect_aabb(bvh.nodes[left].lower, bvh.nodes[left].upper, tray,
                                           ray.t_min, t_max, t_left);
      const bool hit_right = intersect_aabb(bvh.nodes[right].lower, bvh.nodes[right].upper, tray,
                                            ray.t_min, t_max, t_right);
      if (hit_left && hit_right) {
        const bool left_first = t_left <= t_right;
        stack[stack_size++] = left_first ? right : left;
        node_index = left_first ? left : right;
        continue;
      }
      if (hit_left || hit_right) {
        node_index = hit_left ? left : right;
        continue;
      }
    }
    if (stack_size == 0) break;
    node_index = stack[--stack_size];
  }
  return count;
}

}  // namespace tessera
