// Parallel binned-SAH build of the binary BVH (Wald 2007, "On fast construction of
// SAH-based bounding volume hierarchies"): primitives are binned by centroid along each
// axis, the SAH is evaluated at the bin boundaries, and the two halves are built as
// separate TBB tasks. Nodes are first written in task order, then flattened depth-first so
// an interior node's first child directly follows it (the layout the GPU walks).
#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <stdexcept>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/huge_page_allocator.hpp"
#include "tessera/accel/triangle_bvh.hpp"

namespace tessera {
namespace {

// Box and reference of one primitive: 32 bytes, so two per cache line while binning.
struct alignas(16) PrimRef {
  vec3 lower;
  std::uint32_t reference;
  vec3 upper;
  std::uint32_t unused;

  vec3 centroid2() const { return lower + upper; }  // twice the centroid: saves a multiply
};

// Intermediate node in task order; `second` carries kLeafFlag | count for leaves.
struct TaskNode {
  vec3 lower;
  std::uint32_t first;  // left child, or first primitive of a leaf
  vec3 upper;
  std::uint32_t second;  // right child, or kLeafFlag | primitive count
};
constexpr std::uint32_t kLeafFlag = 0x80000000U;

struct Range {
  std::uint32_t begin, end;
  Aabb bounds;     // of the primitives
  Aabb centroids;  // of their doubled centroids
  std::uint32_t count() const { return end - begin; }
};

// Box of one bin in SSE registers (lanes 0-2; lane 3 carries whatever followed the
// coordinates and is ignored), so growing it is one min and one max.
struct BinBox {
  __m128 lower = _mm_set1_ps(kInfinity);
  __m128 upper = _mm_set1_ps(-kInfinity);

  void extend(const BinBox& b) {
    lower = _mm_min_ps(lower, b.lower);
    upper = _mm_max_ps(upper, b.upper);
  }
  float surface_area() const {
    alignas(16) float e[4];
    _mm_store_ps(e, _mm_sub_ps(upper, lower));
    if (!(e[0] >= 0.0f)) return 0.0f;  // empty
    return 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
  }
};

struct Bins {
  std::uint32_t bin_count;
  BinBox bounds[3][kMaxBvhBins];
  std::uint32_t counts[3][kMaxBvhBins];

  // Only the bins in use are initialised: most nodes are small and use few.
  explicit Bins(std::uint32_t n) : bin_count(n) {
    for (int axis = 0; axis < 3; ++axis)
      for (std::uint32_t b = 0; b < n; ++b) {
        bounds[axis][b] = BinBox{};
        counts[axis][b] = 0;
      }
  }
  void merge(const Bins& other) {
    for (int axis = 0; axis < 3; ++axis)
      for (std::uint32_t b = 0; b < bin_count; ++b) {
        bounds[axis][b].extend(other.bounds[axis][b]);
        counts[axis][b] += other.counts[axis][b];
      }
  }
};

// Maps doubled centroids to bins; an axis without extent gets scale 0 (all in bin 0).
struct BinMapping {
  vec3 origin;
  vec3 scale;
  std::uint32_t bin_count;

  BinMapping(const Aabb& centroids, std::uint32_t bins) : origin(centroids.lower), bin_count(bins) {
    const vec3 extent = centroids.extent();
    for (int axis = 0; axis < 3; ++axis)
      scale[axis] =
          extent[axis] > 0.0f ? static_cast<float>(bins) * (1.0f - 1e-6f) / extent[axis] : 0.0f;
  }
  std::uint32_t bin(const vec3& c2, int axis) const {
    const auto b = static_cast<std::int32_t>((c2[axis] - origin[axis]) * scale[axis]);
    return static_cast<std::uint32_t>(
        std::clamp<std::int32_t>(b, 0, static_cast<std::int32_t>(bin_count) - 1));
  }
};

struct Split {
  int axis = -1;
  std::uint32_t bin = 0;   // primitives in bins below this go left
  float cost = kInfinity;  // SAH cost, not normalised by the parent's area
};

class Builder {
 public:
  Builder(std::span<PrimRef> prims, const BvhBuildOptions& options)
      : prims_(prims),
        options_(options),
        node_capacity_(std::max<std::size_t>(1, 2 * prims.size())),
        nodes_(HugePageAllocator<TaskNode>().allocate(node_capacity_)) {}
  ~Builder() { HugePageAllocator<TaskNode>().deallocate(nodes_, node_capacity_); }
  Builder(const Builder&) = delete;
  Builder& operator=(const Builder&) = delete;

  Bvh build() {
    Bvh bvh;
    if (prims_.empty()) return bvh;
    Range root{0, static_cast<std::uint32_t>(prims_.size()), {}, {}};
    for (const PrimRef& p : prims_) {
      root.bounds.extend(Aabb{p.lower, p.upper});
      root.centroids.extend(p.centroid2());
    }
    next_node_.store(1);
    build_node(0, root, 1);
    bvh.nodes.resize(next_node_.load());
    std::uint32_t next = 0;
    bvh.depth = flatten(0, bvh.nodes, next, 1);
    bvh.primitives.resize(prims_.size());
    for (std::size_t i = 0; i < prims_.size(); ++i) bvh.primitives[i] = prims_[i].reference;
    return bvh;
  }

 private:
  std::uint32_t blocks(std::uint32_t count) const {
    return (count + options_.leaf_block_size - 1) / options_.leaf_block_size;
  }

  void make_leaf(std::uint32_t index, const Range& range) {
    nodes_[index] =
        TaskNode{range.bounds.lower, range.begin, range.bounds.upper, kLeafFlag | range.count()};
  }

  void build_node(std::uint32_t index, const Range& range, std::uint32_t depth) {
    const std::uint32_t count = range.count();
    const std::uint32_t max_leaf = options_.max_leaf_size;
    if (count == 1 || depth >= kMaxBvhDepth) return make_leaf(index, range);

    // Near the depth cap, median splits guarantee the remaining levels suffice.
    const bool force_median = bvh_near_depth_cap(depth, count, max_leaf);
    Range left, right;
    bool split_found = false;
    if (!force_median && !range.centroids.empty() && range.centroids.extent() != vec3(0.0f)) {
      // Few bins for small nodes (as Embree does): the SAH barely changes and most nodes
      // are small.
      const BinMapping mapping(range.centroids, std::min(options_.bin_count, 4 + count / 20));
      const Split split = find_split(range, mapping);
      if (split.axis >= 0) {
        const float leaf_cost = options_.intersection_cost * static_cast<float>(blocks(count));
        const float area = range.bounds.surface_area();
        const float split_cost =
            options_.traversal_cost +
            options_.intersection_cost * (area > 0.0f ? split.cost / area : 0.0f);
        if (count <= max_leaf && leaf_cost <= split_cost) return make_leaf(index, range);
        partition(range, mapping, split, left, right);
        split_found = left.count() > 0 && right.count() > 0;
      }
    }
    if (!split_found) {
      if (count <= max_leaf && !force_median) return make_leaf(index, range);
      median_split(range, left, right);
    }

    const std::uint32_t children = next_node_.fetch_add(2);
    nodes_[index] = TaskNode{range.bounds.lower, children, range.bounds.upper, children + 1};
    if (options_.parallel && count >= kParallelTaskSize) {
      tbb::parallel_invoke([&] { build_node(children, left, depth + 1); },
                           [&] { build_node(children + 1, right, depth + 1); });
    } else {
      build_node(children, left, depth + 1);
      build_node(children + 1, right, depth + 1);
    }
  }

  void bin_range(std::uint32_t begin, std::uint32_t end, const BinMapping& mapping,
                 Bins& bins) const {
    for (std::uint32_t i = begin; i < end; ++i) {
      const PrimRef& p = prims_[i];
      const vec3 c2 = p.centroid2();
      const BinBox box{_mm_load_ps(&p.lower.x), _mm_load_ps(&p.upper.x)};
      for (int axis = 0; axis < 3; ++axis) {
        const std::uint32_t b = mapping.bin(c2, axis);
        bins.bounds[axis][b].extend(box);
        ++bins.counts[axis][b];
      }
    }
  }

  Split find_split(const Range& range, const BinMapping& mapping) const {
    const std::uint32_t n = mapping.bin_count;
    Bins bins(n);
    if (options_.parallel && range.count() >= kParallelBinningSize) {
      bins = tbb::parallel_reduce(
          tbb::blocked_range<std::uint32_t>(range.begin, range.end, kParallelBinningSize / 4),
          Bins(n),
          [&](const tbb::blocked_range<std::uint32_t>& r, Bins acc) {
            bin_range(r.begin(), r.end(), mapping, acc);
            return acc;
          },
          [&](Bins a, const Bins& b) {
            a.merge(b);
            return a;
          });
    } else {
      bin_range(range.begin, range.end, mapping, bins);
    }

    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      if (mapping.scale[axis] == 0.0f) continue;
      float right_cost[kMaxBvhBins];
      BinBox accumulated;
      std::uint32_t accumulated_count = 0;
      for (std::uint32_t b = n - 1; b > 0; --b) {
        accumulated.extend(bins.bounds[axis][b]);
        accumulated_count += bins.counts[axis][b];
        right_cost[b] = accumulated.surface_area() * static_cast<float>(blocks(accumulated_count));
      }
      accumulated = BinBox{};
      accumulated_count = 0;
      for (std::uint32_t b = 1; b < n; ++b) {
        accumulated.extend(bins.bounds[axis][b - 1]);
        accumulated_count += bins.counts[axis][b - 1];
        if (accumulated_count == 0 || accumulated_count == range.count()) continue;
        const float cost =
            accumulated.surface_area() * static_cast<float>(blocks(accumulated_count)) +
            right_cost[b];
        if (cost < best.cost) best = Split{axis, b, cost};
      }
    }
    return best;
  }

  // In-place partition that gathers both sides' bounds on the way (in SSE registers).
  void partition(const Range& range, const BinMapping& mapping, const Split& split, Range& left,
                 Range& right) const {
    struct Side {
      BinBox bounds, centroids;
      void add(const PrimRef& p) {
        const __m128 lower = _mm_load_ps(&p.lower.x), upper = _mm_load_ps(&p.upper.x);
        bounds.extend(BinBox{lower, upper});
        const __m128 c2 = _mm_add_ps(lower, upper);
        centroids.extend(BinBox{c2, c2});
      }
      static Aabb to_aabb(const BinBox& box) {
        alignas(16) float lo[4], hi[4];
        _mm_store_ps(lo, box.lower);
        _mm_store_ps(hi, box.upper);
        return Aabb{vec3(lo[0], lo[1], lo[2]), vec3(hi[0], hi[1], hi[2])};
      }
    };
    Side l, r;
    const float scale = mapping.scale[split.axis], origin = mapping.origin[split.axis];
    const auto goes_left = [&](const PrimRef& p) {
      const float c2 = p.lower[split.axis] + p.upper[split.axis];
      const auto b = static_cast<std::int32_t>((c2 - origin) * scale);
      return std::clamp<std::int32_t>(b, 0, static_cast<std::int32_t>(mapping.bin_count) - 1) <
             static_cast<std::int32_t>(split.bin);
    };
    std::uint32_t i = range.begin, j = range.end;
    for (;;) {
      while (i < j && goes_left(prims_[i])) l.add(prims_[i++]);
      while (i < j && !goes_left(prims_[j - 1])) r.add(prims_[--j]);
      if (i >= j) break;
      std::swap(prims_[i], prims_[j - 1]);
      l.add(prims_[i++]);
      r.add(prims_[--j]);
    }
    left = Range{range.begin, i, Side::to_aabb(l.bounds), Side::to_aabb(l.centroids)};
    right = Range{i, range.end, Side::to_aabb(r.bounds), Side::to_aabb(r.centroids)};
  }

  // Object median along the widest centroid axis: always halves the range.
  void median_split(const Range& range, Range& left, Range& right) const {
    const int axis = range.centroids.largest_axis();
    const std::uint32_t middle = range.begin + range.count() / 2;
    std::nth_element(prims_.begin() + range.begin, prims_.begin() + middle,
                     prims_.begin() + range.end, [axis](const PrimRef& a, const PrimRef& b) {
                       return a.centroid2()[axis] < b.centroid2()[axis];
                     });
    left = Range{range.begin, middle, {}, {}};
    right = Range{middle, range.end, {}, {}};
    for (Range* side : {&left, &right})
      for (std::uint32_t i = side->begin; i < side->end; ++i) {
        side->bounds.extend(Aabb{prims_[i].lower, prims_[i].upper});
        side->centroids.extend(prims_[i].centroid2());
      }
  }

  // Depth-first copy; returns the depth of the subtree below `index` (a leaf is 1 deep
  // at depth `depth`).
  std::uint32_t flatten(std::uint32_t index, std::vector<BvhNode>& out, std::uint32_t& next,
                        std::uint32_t depth) const {
    const TaskNode& node = nodes_[index];
    const std::uint32_t at = next++;
    if (node.second & kLeafFlag) {
      out[at] = BvhNode{node.lower, node.first, node.upper, node.second & ~kLeafFlag};
      return depth;
    }
    const std::uint32_t left_depth = flatten(node.first, out, next, depth + 1);
    const std::uint32_t right_index = next;
    const std::uint32_t right_depth = flatten(node.second, out, next, depth + 1);
    out[at] = BvhNode{node.lower, right_index, node.upper, 0};
    return std::max(left_depth, right_depth);
  }

  static constexpr std::uint32_t kParallelTaskSize = 4096;
  static constexpr std::uint32_t kParallelBinningSize = 65536;

  std::span<PrimRef> prims_;
  const BvhBuildOptions& options_;
  // Written once each, in task order: allocated, not initialised, and in huge pages where
  // the kernel gives them (page faults were a tenth of a large build on a virtual machine).
  std::size_t node_capacity_;
  TaskNode* nodes_;
  std::atomic<std::uint32_t> next_node_{0};
};

}  // namespace

Bvh build_bvh(std::span<const Aabb> bounds, std::span<const std::uint32_t> references,
              const BvhBuildOptions& options) {
  if (bounds.size() != references.size())
    throw std::invalid_argument("build_bvh: bounds and references differ in size");
  if (bounds.size() >= kLeafFlag) throw std::invalid_argument("build_bvh: too many primitives");
  BvhBuildOptions checked = options;
  checked.max_leaf_size = std::max(1u, checked.max_leaf_size);
  checked.leaf_block_size = std::max(1u, checked.leaf_block_size);
  checked.bin_count = std::clamp(checked.bin_count, 2u, kMaxBvhBins);
  HugePageVector<PrimRef> prims(bounds.size());
  for (std::size_t i = 0; i < bounds.size(); ++i)
    prims[i] = PrimRef{bounds[i].lower, references[i], bounds[i].upper, 0};
  return Builder(prims, checked).build();
}

Bvh build_triangle_bvh(std::span<const Triangle> triangles, const BvhBuildOptions& options) {
  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i = 0; i < triangles.size(); ++i) {
    if (is_degenerate(triangles[i])) continue;
    boxes.push_back(bounds(triangles[i]));
    ids.push_back(i);
  }
  return build_bvh(boxes, ids, options);
}

}  // namespace tessera
