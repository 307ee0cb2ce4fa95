#include "tessera/accel/compressed_wide_bvh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/bvh_traversal.hpp"

namespace tessera {
namespace {

using accel_test::reference_closest;
using accel_test::test_rays;
using accel_test::triangle_soup;

struct Built {
  std::vector<Triangle> triangles;
  Bvh binary;
  CompressedWideBvh compressed;

  BvhView view() const {
    BvhView v = binary.view();
    v.compressed_nodes = compressed.nodes.data();
    v.compressed_primitives = compressed.primitives.data();
    return v;
  }
};

Built build(std::vector<Triangle> triangles, std::uint32_t max_leaf_size = 4) {
  Built b;
  b.triangles = std::move(triangles);
  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i = 0; i < b.triangles.size(); ++i) {
    boxes.push_back(bounds(b.triangles[i]));
    ids.push_back(i);
  }
  BvhBuildOptions options;
  options.max_leaf_size = max_leaf_size;
  b.binary = build_bvh(boxes, ids, options);
  b.compressed = compress_bvh(b.binary);
  return b;
}

// Moves and scales a soup: far from the origin, tiny or huge.
std::vector<Triangle> placed(std::vector<Triangle> tris, vec3 offset, float scale) {
  for (Triangle& t : tris) {
    t.p0 = t.p0 * scale + offset;
    t.p1 = t.p1 * scale + offset;
    t.p2 = t.p2 * scale + offset;
  }
  return tris;
}

// The union of the triangles' boxes below node `index`; checks on the way down that each
// slot's dequantised box holds everything below it.
Aabb check_subtree(const Built& b, std::uint32_t index, std::uint32_t& nodes_seen) {
  ++nodes_seen;
  const CompressedWideNode& node = b.compressed.nodes[index];
  Aabb all;
  std::uint32_t inner_rank = 0;
  for (std::uint32_t slot = 0; slot < 8; ++slot) {
    const bool inner = ((node.inner_mask >> slot) & 1U) != 0;
    if (!inner && node.leaf_count[slot] == 0) continue;
    Aabb below;
    if (inner) {
      EXPECT_EQ(node.leaf_count[slot], 0u);
      below = check_subtree(b, node.child_base + inner_rank++, nodes_seen);
    } else {
      const std::uint32_t first = compressed_detail::leaf_first(node, slot);
      for (std::uint32_t i = 0; i < node.leaf_count[slot]; ++i)
        below.extend(bounds(b.triangles[b.compressed.primitives[first + i]]));
    }
    vec3 lower, upper;
    compressed_detail::child_box(node, slot, lower, upper);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_LE(lower[axis], below.lower[axis]) << "node " << index << " slot " << slot;
      EXPECT_GE(upper[axis], below.upper[axis]) << "node " << index << " slot " << slot;
    }
    all.extend(below);
  }
  return all;
}

void expect_conservative_and_complete(const Built& b) {
  ASSERT_FALSE(b.compressed.nodes.empty());
  std::uint32_t nodes_seen = 0;
  check_subtree(b, 0, nodes_seen);
  EXPECT_EQ(nodes_seen, b.compressed.nodes.size()) << "every node reachable once";
  std::vector<std::uint32_t> binary(b.binary.primitives), compressed(b.compressed.primitives);
  std::sort(binary.begin(), binary.end());
  std::sort(compressed.begin(), compressed.end());
  EXPECT_EQ(compressed, binary) << "each reference once, as in the binary tree";
  EXPECT_LE(b.compressed.depth, b.binary.depth);
}

TEST(CompressedWideBvh, BoxesHoldEverythingBelowThemAtAnyScaleAndPlace) {
  const auto soup = triangle_soup(3000, 11);
  for (const auto& [offset, scale] :
       {std::pair{vec3(0.0f), 1.0f}, std::pair{vec3(3e5f, -1e5f, 2e4f), 1.0f},
        std::pair{vec3(0.1f, 0.2f, 0.3f), 1e-5f}, std::pair{vec3(-1e6f), 1e4f},
        std::pair{vec3(1e30f, 0.0f, -1e30f), 1e28f}}) {
    SCOPED_TRACE(testing::Message() << "offset " << offset.x << " scale " << scale);
    expect_conservative_and_complete(build(placed(soup, offset, scale)));
  }
}

TEST(CompressedWideBvh, FlatAndIdenticalTrianglesGiveValidBoxes) {
  // A grid on integer planes (every box flat on one axis) and a stack of identical triangles.
  expect_conservative_and_complete(build(accel_test::axis_aligned_grid(6)));
  std::vector<Triangle> same(200, Triangle{vec3(1, 2, 3), vec3(2, 2, 3), vec3(1, 3, 3), 0});
  expect_conservative_and_complete(build(same));
}

TEST(CompressedWideBvh, ClosestAndAnyHitsMatchTheBinaryWalk) {
  const auto intersect_with = [](const Built& b) {
    return [&b](std::uint32_t ref, const Ray& r, float t_max, HitRecord& h) {
      return intersect(b.triangles[ref], r, t_max, h, ref);
    };
  };
  for (const auto& [tris, extent] :
       {std::pair{triangle_soup(2000, 5), 1.5f}, std::pair{accel_test::closed_sphere(4), 1.5f},
        std::pair{accel_test::axis_aligned_grid(5), 6.0f},
        std::pair{placed(triangle_soup(1000, 9), vec3(0.0f), 1.0f), 0.5f}}) {
    const Built b = build(tris);
    const BvhView view = b.view();
    std::uint32_t hits = 0;
    for (const Ray& ray : test_rays(3000, 21, extent)) {
      HitRecord compressed_hit, binary_hit;
      compressed_hit.t = binary_hit.t = ray.t_max;
      const bool found_compressed =
          traverse_compressed_wide<false>(view, ray, compressed_hit, intersect_with(b));
      const bool found_binary = traverse_bvh<false>(view, ray, binary_hit, intersect_with(b));
      const accel_test::ReferenceHit reference = reference_closest(b.triangles, ray);
      ASSERT_EQ(found_compressed, reference.hit);
      ASSERT_EQ(found_binary, reference.hit);
      if (reference.hit) {
        ++hits;
        ASSERT_EQ(compressed_hit.t, reference.record.t);
        ASSERT_EQ(compressed_hit.t, binary_hit.t);
      }
      HitRecord any;
      any.t = ray.t_max;
      ASSERT_EQ(traverse_compressed_wide<true>(view, ray, any, intersect_with(b)), reference.hit);
      if (reference.hit) {
        ASSERT_LT(any.t, ray.t_max);
      }
    }
    EXPECT_GT(hits, 300u) << "the rays should hit the scene often";
  }
}

TEST(CompressedWideBvh, ASingleLeafIsARootWithOneChild) {
  const Built b = build(triangle_soup(3, 2));
  ASSERT_EQ(b.compressed.nodes.size(), 1u);
  EXPECT_EQ(b.compressed.nodes[0].inner_mask, 0u);
  expect_conservative_and_complete(b);
}

// A binary tree whose every level hangs a small deep branch beside a large one of eight
// leaves, each level an eighth of the size of the one above: the collapse opens the large
// branch (the largest child) until its node is full and leaves the deep one a level further
// down, so the wide tree is about as deep as the binary one.
struct DeepTree {
  Bvh bvh;
  std::uint32_t add_leaf(const Aabb& box) {
    const auto index = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back(
        BvhNode{box.lower, static_cast<std::uint32_t>(bvh.primitives.size()), box.upper, 1});
    bvh.primitives.push_back(static_cast<std::uint32_t>(bvh.primitives.size()));
    return index;
  }
  // `levels` levels of halves along x of the cube [x, x + size] x [0, size]^2.
  std::uint32_t add_balanced(int levels, float x, float size) {
    if (levels == 0) return add_leaf(Aabb{vec3(x, 0, 0), vec3(x + size, size, size)});
    const auto index = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back({});
    add_balanced(levels - 1, x, size / 2);
    const std::uint32_t second = add_balanced(levels - 1, x + size / 2, size / 2);
    bvh.nodes[index] = BvhNode{vec3(x, 0, 0), second, vec3(x + size, size, size), 0};
    return index;
  }
  // The deep branch in [0, size]^3.
  std::uint32_t add_chain(int length, float size) {
    if (length == 0) return add_leaf(Aabb{vec3(0.0f), vec3(size)});
    const auto index = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back({});
    add_chain(length - 1, size / 8);
    const std::uint32_t second = add_balanced(3, 0.0f, size);
    bvh.nodes[index] = BvhNode{vec3(0.0f), second, vec3(size), 0};
    return index;
  }
  explicit DeepTree(int length) {
    add_chain(length, 1e18f);  // surface areas from 1e36 stay above float underflow
    bvh.depth = static_cast<std::uint32_t>(length) + 4;
  }
};

TEST(CompressedWideBvh, TreesTooDeepForTheWalksStackAreLeftToTheBinaryWalk) {
  const CompressedWideBvh shallow = compress_bvh(DeepTree(kCompressedMaxDepth - 8).bvh);
  ASSERT_FALSE(shallow.nodes.empty());
  EXPECT_GT(shallow.depth, kCompressedMaxDepth - 10) << "the construction keeps its depth";
  EXPECT_TRUE(compress_bvh(DeepTree(kCompressedMaxDepth + 8).bvh).nodes.empty());
}

TEST(CompressedWideBvh, TreesItCannotEncodeAreLeftToTheBinaryWalk) {
  EXPECT_TRUE(compress_bvh(Bvh{}).nodes.empty());
  // A leaf of more primitives than a wide leaf word holds (identical ones: no split pays).
  Built b =
      build(std::vector<Triangle>(40, Triangle{vec3(0), vec3(1, 0, 0), vec3(0, 1, 0), 0}), 64);
  ASSERT_EQ(b.binary.nodes.size(), 1u) << "one leaf of 40";
  EXPECT_TRUE(b.compressed.nodes.empty());
  // A box that is not finite.
  Bvh infinite = build(triangle_soup(100, 4)).binary;
  infinite.nodes[0].upper.x = kInfinity;
  EXPECT_TRUE(compress_bvh(infinite).nodes.empty());
}

}  // namespace
}  // namespace tessera
