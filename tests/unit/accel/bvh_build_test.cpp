// Structural invariants of the binary BVH builder and the wide collapse: every primitive
// in exactly one leaf, boxes that contain their contents, leaf sizes and depth within
// their limits (also on inputs built to defeat the SAH), the same tree shape rules for
// the parallel and sequential builds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/bvh.hpp"
#include "tessera/accel/triangle_bvh.hpp"
#include "tessera/accel/wide_bvh.hpp"

namespace tessera {
namespace {

bool contains(const vec3& lower, const vec3& upper, const Aabb& box) {
  return lower.x <= box.lower.x && lower.y <= box.lower.y && lower.z <= box.lower.z &&
         upper.x >= box.upper.x && upper.y >= box.upper.y && upper.z >= box.upper.z;
}

struct Checked {
  std::uint32_t depth = 0;
  std::uint32_t max_leaf = 0;
};

// Walks the flattened tree; returns the deepest level and largest leaf seen.
Checked check_subtree(const Bvh& bvh, const std::vector<Aabb>& boxes, std::uint32_t index,
                      std::uint32_t depth, std::vector<int>& seen) {
  const BvhNode& node = bvh.nodes[index];
  if (node.is_leaf()) {
    for (std::uint32_t i = node.offset; i < node.offset + node.count; ++i) {
      const std::uint32_t prim = bvh.primitives[i];
      EXPECT_TRUE(contains(node.lower, node.upper, boxes[prim]));
      ++seen[prim];
    }
    return Checked{depth, node.count};
  }
  const std::uint32_t left = index + 1, right = node.offset;
  EXPECT_GT(right, left);
  EXPECT_LT(right, bvh.nodes.size());
  for (std::uint32_t child : {left, right})
    EXPECT_TRUE(
        contains(node.lower, node.upper, Aabb{bvh.nodes[child].lower, bvh.nodes[child].upper}));
  const Checked a = check_subtree(bvh, boxes, left, depth + 1, seen);
  const Checked b = check_subtree(bvh, boxes, right, depth + 1, seen);
  return Checked{std::max(a.depth, b.depth), std::max(a.max_leaf, b.max_leaf)};
}

void check_bvh(const Bvh& bvh, const std::vector<Aabb>& boxes, std::uint32_t max_leaf_size) {
  ASSERT_FALSE(bvh.nodes.empty());
  std::vector<int> seen(boxes.size(), 0);
  const Checked c = check_subtree(bvh, boxes, 0, 1, seen);
  EXPECT_EQ(c.depth, bvh.depth);
  EXPECT_LE(bvh.depth, kMaxBvhDepth);
  EXPECT_LE(c.max_leaf, max_leaf_size);
  for (int count : seen) ASSERT_EQ(count, 1);
}

std::vector<Aabb> boxes_of(const std::vector<Triangle>& tris) {
  std::vector<Aabb> boxes;
  for (const Triangle& t : tris) boxes.push_back(bounds(t));
  return boxes;
}

std::vector<std::uint32_t> iota(std::size_t n) {
  std::vector<std::uint32_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<std::uint32_t>(i);
  return ids;
}

TEST(BvhBuild, ParallelAndSequentialBuildsAreValid) {
  const auto boxes = boxes_of(accel_test::triangle_soup(20000, 1));
  for (bool parallel : {false, true})
    for (std::uint32_t leaf : {1u, 4u, 8u}) {
      BvhBuildOptions options;
      options.parallel = parallel;
      options.max_leaf_size = leaf;
      options.leaf_block_size = leaf == 8 ? 4 : 1;
      check_bvh(build_bvh(boxes, iota(boxes.size()), options), boxes, leaf);
    }
}

TEST(BvhBuild, IdenticalCentroidsAreSplitByCount) {
  // The SAH cannot separate boxes with one centroid; the builder must still bound leaves.
  std::vector<Aabb> boxes(1000, Aabb{vec3(-1.0f), vec3(1.0f)});
  check_bvh(build_bvh(boxes, iota(boxes.size())), boxes, 4);
}

TEST(BvhBuild, DepthStaysWithinTheCapOnNestedBoxes) {
  // Boxes nested around one corner, each much larger than the next: the SAH prefers to peel
  // off one box per level, which would make the tree as deep as there are boxes.
  std::vector<Aabb> boxes;
  for (int i = 0; i < 3000; ++i) {
    const float size = std::pow(0.97f, static_cast<float>(i));
    boxes.push_back(Aabb{vec3(0.0f), vec3(size, size * 0.5f, size * 0.25f)});
  }
  const Bvh bvh = build_bvh(boxes, iota(boxes.size()));
  check_bvh(bvh, boxes, 4);
  EXPECT_LE(bvh.depth, kMaxBvhDepth);
}

TEST(BvhBuild, EmptyInputGivesEmptyTree) {
  const Bvh bvh = build_bvh({}, {});
  EXPECT_TRUE(bvh.nodes.empty());
  EXPECT_EQ(bvh.depth, 0u);
}

TEST(WideBvh, CollapseKeepsEveryLeafOnceAndIsNoDeeper) {
  const auto boxes = boxes_of(accel_test::triangle_soup(5000, 2));
  const Bvh binary = build_bvh(boxes, iota(boxes.size()));
  std::vector<int> seen(boxes.size(), 0);
  const WideBvh wide = collapse_to_wide(binary, [&](std::uint32_t offset, std::uint32_t count) {
    return make_wide_leaf(offset, count);
  });
  EXPECT_LE(wide.depth, binary.depth);
  EXPECT_LT(wide.nodes.size(), binary.nodes.size() / 3);
  // Walk the wide tree: child boxes contain their primitives and every slot is either a
  // real child or the empty (inverted) box.
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const WideBvhNode& node = wide.nodes[stack.back()];
    stack.pop_back();
    for (std::uint32_t slot = 0; slot < kWideBvhWidth; ++slot) {
      const std::uint32_t child = node.children[slot];
      const vec3 lower(node.bounds[0][slot], node.bounds[2][slot], node.bounds[4][slot]);
      const vec3 upper(node.bounds[1][slot], node.bounds[3][slot], node.bounds[5][slot]);
      if (child == kWideEmptyChild) {
        EXPECT_EQ(lower.x, kInfinity);
        EXPECT_EQ(upper.x, -kInfinity);
        continue;
      }
      if (!wide_is_leaf(child)) {
        stack.push_back(child);
        continue;
      }
      for (std::uint32_t i = wide_leaf_first(child);
           i < wide_leaf_first(child) + wide_leaf_count(child); ++i) {
        EXPECT_TRUE(contains(lower, upper, boxes[binary.primitives[i]]));
        ++seen[binary.primitives[i]];
      }
    }
  }
  for (int count : seen) ASSERT_EQ(count, 1);
}

TEST(TriangleBvh, EveryTriangleButTheDegenerateOnesByItsIndex) {
  std::vector<Triangle> tris = accel_test::triangle_soup(50, 8);
  tris[7] = Triangle{vec3(0), vec3(1, 1, 1), vec3(2, 2, 2), 0};  // collinear: no area
  tris[30].p2 = tris[30].p1;                                     // two corners the same
  const Bvh bvh = build_triangle_bvh(tris);
  std::vector<std::uint32_t> refs(bvh.primitives);
  std::sort(refs.begin(), refs.end());
  std::vector<std::uint32_t> expected;
  for (std::uint32_t i = 0; i < 50; ++i)
    if (i != 7 && i != 30) expected.push_back(i);
  EXPECT_EQ(refs, expected);
}

}  // namespace
}  // namespace tessera
