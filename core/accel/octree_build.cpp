#include "tessera/accel/octree.hpp"

#include <algorithm>
#include <numeric>

namespace tessera {
namespace {

bool overlaps(const Aabb& a, const Aabb& b) {
  return a.lower.x <= b.upper.x && b.lower.x <= a.upper.x && a.lower.y <= b.upper.y &&
         b.lower.y <= a.upper.y && a.lower.z <= b.upper.z && b.lower.z <= a.upper.z;
}

Aabb intersection(const Aabb& a, const Aabb& b) {
  return Aabb{glm::max(a.lower, b.lower), glm::min(a.upper, b.upper)};
}

class OctreeBuilder {
 public:
  OctreeBuilder(std::span<const Aabb> bounds, const OctreeLimits& limits,
                const OctreeLeafEncoder& encode_leaf, WideBvh& out)
      : bounds_(bounds), limits_(limits), encode_leaf_(encode_leaf), out_(out) {
    limits_.max_depth = std::min(limits_.max_depth, 48u);
    limits_.leaf_size = std::max(1u, limits_.leaf_size);
  }

  void run() {
    std::vector<std::uint32_t> all(bounds_.size());
    std::iota(all.begin(), all.end(), 0u);
    Aabb scene;
    for (const Aabb& b : bounds_) scene.extend(b);
    if (all.empty() || scene.empty()) return;
    // A cube around the scene, so cells stay cubes at every level.
    const vec3 center = scene.centroid();
    const float half = 0.5f * max_component(scene.extent()) * (1.0f + 1e-5f) + 1e-30f;
    const Aabb cube{center - vec3(half), center + vec3(half)};
    out_.nodes.emplace_back().clear();
    fill_node(0, cube, all, 1);
  }

 private:
  Aabb bounds_of(std::span<const std::uint32_t> ids, const Aabb& cell) const {
    Aabb box;
    for (std::uint32_t id : ids) box.extend(bounds_[id]);
    return intersection(box, cell);
  }

  std::uint32_t new_node(std::uint32_t depth) {
    out_.depth = std::max(out_.depth, depth);
    const auto index = static_cast<std::uint32_t>(out_.nodes.size());
    out_.nodes.emplace_back().clear();
    return index;
  }

  // Builds the subtree of `cell` and returns its child word.
  std::uint32_t build_cell(const Aabb& cell, const std::vector<std::uint32_t>& ids,
                           std::uint32_t depth) {
    if (ids.size() <= limits_.leaf_size || depth > limits_.max_depth)
      return leaf_group(cell, ids, depth);
    const std::uint32_t index = new_node(depth);
    if (!fill_node(index, cell, ids, depth)) {
      // No octant separates anything: stop subdividing here.
      out_.nodes.pop_back();
      return leaf_group(cell, ids, depth);
    }
    return index;
  }

  // Splits `cell` into octants under node `index`; false when every octant would hold
  // every primitive (splitting cannot help).
  bool fill_node(std::uint32_t index, const Aabb& cell, const std::vector<std::uint32_t>& ids,
                 std::uint32_t depth) {
    out_.depth = std::max(out_.depth, depth);
    const vec3 middle = cell.centroid();
    std::vector<std::uint32_t> octant_ids[8];
    Aabb octants[8];
    bool separates = false;
    std::size_t references = 0;
    for (int o = 0; o < 8; ++o) {
      for (int axis = 0; axis < 3; ++axis) {
        const bool high = (o >> axis) & 1;
        octants[o].lower[axis] = high ? middle[axis] : cell.lower[axis];
        octants[o].upper[axis] = high ? cell.upper[axis] : middle[axis];
      }
      for (std::uint32_t id : ids)
        if (overlaps(bounds_[id], octants[o])) octant_ids[o].push_back(id);
      separates |= octant_ids[o].size() < ids.size();
      references += octant_ids[o].size();
    }
    // Splitting pays only while it separates primitives; when they are large against the
    // cell, every octant repeats most of them and references multiply instead.
    if (depth > 1 && (!separates || references > kMaxGrowth * ids.size())) return false;
    std::uint32_t slot = 0;
    for (int o = 0; o < 8; ++o) {
      if (octant_ids[o].empty()) continue;
      const Aabb box = bounds_of(octant_ids[o], octants[o]);
      const std::uint32_t word = build_cell(octants[o], octant_ids[o], depth + 1);
      out_.nodes[index].set_child(slot++, box.lower, box.upper, word);
    }
    return true;
  }

  // A leaf, or when the cell holds more than one leaf can, a node over groups of them.
  std::uint32_t leaf_group(const Aabb& cell, std::span<const std::uint32_t> ids,
                           std::uint32_t depth) {
    if (ids.size() <= limits_.max_leaf_items) return encode_leaf_(ids);
    const std::uint32_t index = new_node(depth);
    const std::size_t groups = std::min<std::size_t>(
        kWideBvhWidth, (ids.size() + limits_.max_leaf_items - 1) / limits_.max_leaf_items);
    const std::size_t per_group = (ids.size() + groups - 1) / groups;
    for (std::size_t g = 0; g < groups; ++g) {
      const auto part = ids.subspan(g * per_group, std::min(per_group, ids.size() - g * per_group));
      const Aabb box = bounds_of(part, cell);
      const std::uint32_t word = leaf_group(cell, part, depth + 1);
      out_.nodes[index].set_child(static_cast<std::uint32_t>(g), box.lower, box.upper, word);
    }
    return index;
  }

  // Most references the octants of a cell may hold together, per reference of the cell.
  static constexpr std::size_t kMaxGrowth = 3;

  std::span<const Aabb> bounds_;
  OctreeLimits limits_;
  const OctreeLeafEncoder& encode_leaf_;
  WideBvh& out_;
};

}  // namespace

WideBvh build_octree(std::span<const Aabb> bounds, const OctreeLimits& limits,
                     const OctreeLeafEncoder& encode_leaf) {
  WideBvh octree;
  OctreeBuilder(bounds, limits, encode_leaf, octree).run();
  return octree;
}

}  // namespace tessera
