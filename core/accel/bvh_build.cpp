#include <algorithm>
#include <array>
#include <numeric>

#include "tessera/accel/bvh.hpp"

namespace tessera {
namespace {

constexpr int kBinCount = 16;

struct BuildItem {
  Aabb bounds;
  vec3 centroid;
  std::uint32_t reference;
};

class Builder {
 public:
  Builder(std::vector<BuildItem>& items, const BvhBuildOptions& options, Bvh& out)
      : items_(items), options_(options), out_(out) {}

  void build() {
    out_.nodes.reserve(items_.empty() ? 0 : 2 * items_.size());
    if (!items_.empty()) build_node(0, static_cast<std::uint32_t>(items_.size()), 1);
    out_.primitives.resize(items_.size());
    for (std::size_t i = 0; i < items_.size(); ++i) out_.primitives[i] = items_[i].reference;
  }

 private:
  struct Split {
    int axis = -1;
    float position = 0.0f;
    float cost = kInfinity;
  };

  std::uint32_t build_node(std::uint32_t begin, std::uint32_t end, std::uint32_t depth) {
    out_.depth = std::max(out_.depth, depth);
    const auto node_index = static_cast<std::uint32_t>(out_.nodes.size());
    out_.nodes.push_back(BvhNode{});
    Aabb bounds, centroid_bounds;
    for (std::uint32_t i = begin; i < end; ++i) {
      bounds.extend(items_[i].bounds);
      centroid_bounds.extend(items_[i].centroid);
    }
    const std::uint32_t count = end - begin;
    const auto make_leaf = [&] {
      out_.nodes[node_index] = BvhNode{bounds.lower, begin, bounds.upper, count};
      return node_index;
    };
    if (count <= 1 || depth >= kMaxBvhDepth) return make_leaf();

    const Split split = find_split(begin, end, centroid_bounds);
    const float leaf_cost = options_.intersection_cost * static_cast<float>(count);
    std::uint32_t middle;
    if (split.axis < 0) {
      // All centroids coincide: SAH cannot separate them, so halve the range.
      if (count <= options_.max_leaf_size) return make_leaf();
      middle = begin + count / 2;
    } else {
      const float split_cost =
          options_.traversal_cost + options_.intersection_cost * split.cost / bounds.surface_area();
      if (count <= options_.max_leaf_size && split_cost >= leaf_cost) return make_leaf();
      auto* first = items_.data() + begin;
      auto* mid = std::partition(first, items_.data() + end, [&](const BuildItem& item) {
        return item.centroid[split.axis] < split.position;
      });
      middle = static_cast<std::uint32_t>(mid - items_.data());
      if (middle == begin || middle == end) middle = begin + count / 2;
    }
    build_node(begin, middle, depth + 1);
    const std::uint32_t right = build_node(middle, end, depth + 1);
    out_.nodes[node_index] = BvhNode{bounds.lower, right, bounds.upper, 0};
    return node_index;
  }

  // Evaluates the SAH at the kBinCount - 1 bin boundaries of each axis.
  Split find_split(std::uint32_t begin, std::uint32_t end, const Aabb& centroid_bounds) const {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = centroid_bounds.lower[axis];
      const float extent = centroid_bounds.upper[axis] - lo;
      if (!(extent > 0.0f)) continue;
      std::array<Aabb, kBinCount> bins;
      std::array<std::uint32_t, kBinCount> counts{};
      const float scale = kBinCount / extent;
      for (std::uint32_t i = begin; i < end; ++i) {
        const int bin =
            std::min(kBinCount - 1, static_cast<int>((items_[i].centroid[axis] - lo) * scale));
        bins[bin].extend(items_[i].bounds);
        ++counts[bin];
      }
      std::array<float, kBinCount> left_cost{};
      Aabb accumulated;
      std::uint32_t accumulated_count = 0;
      for (int b = 0; b < kBinCount - 1; ++b) {
        accumulated.extend(bins[b]);
        accumulated_count += counts[b];
        left_cost[b] = accumulated.surface_area() * static_cast<float>(accumulated_count);
      }
      accumulated = Aabb{};
      accumulated_count = 0;
      for (int b = kBinCount - 1; b > 0; --b) {
        accumulated.extend(bins[b]);
        accumulated_count += counts[b];
        const float cost =
            left_cost[b - 1] + accumulated.surface_area() * static_cast<float>(accumulated_count);
        if (cost < best.cost) {
          best.cost = cost;
          best.axis = axis;
          best.position = lo + extent * static_cast<float>(b) / kBinCount;
        }
      }
    }
    return best;
  }

  std::vector<BuildItem>& items_;
  const BvhBuildOptions& options_;
  Bvh& out_;
};

}  // namespace

Bvh build_bvh(std::span<const Aabb> bounds, std::span<const std::uint32_t> references,
              const BvhBuildOptions& options) {
  std::vector<BuildItem> items(bounds.size());
  for (std::size_t i = 0; i < bounds.size(); ++i)
    items[i] = BuildItem{bounds[i], bounds[i].centroid(), references[i]};
  Bvh bvh;
  Builder(items, options, bvh).build();
  return bvh;
}

}  // namespace tessera
