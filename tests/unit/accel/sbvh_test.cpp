// The spatial-split builder (accel/sbvh.hpp): every triangle reachable, boxes that hold
// what they claim (each reference's box the true part of its triangle, sampled), the
// reference budget kept, spatial splits made where triangles straddle and lowering the
// surface-area cost, none where they would not pay. Hits against brute force are checked by
// the `_sbvh` variants of TriangleAccelTest.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/sbvh.hpp"
#include "tessera/accel/triangle_accel.hpp"

namespace tessera {
namespace {

bool contains(const BvhNode& node, const vec3& p, float tolerance = 0.0f) {
  return p.x >= node.lower.x - tolerance && p.y >= node.lower.y - tolerance &&
         p.z >= node.lower.z - tolerance && p.x <= node.upper.x + tolerance &&
         p.y <= node.upper.y + tolerance && p.z <= node.upper.z + tolerance;
}

bool contains(const BvhNode& outer, const BvhNode& inner) {
  return contains(outer, inner.lower) && contains(outer, inner.upper);
}

// Long thin triangles crossing each other: the case spatial splits are for.
std::vector<Triangle> slivers(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Triangle> tris;
  for (int i = 0; i < count; ++i) {
    const vec3 a = accel_test::random_point(rng, -1.0f, 1.0f);
    const vec3 b = accel_test::random_point(rng, -1.0f, 1.0f);
    tris.push_back(Triangle{a, b, 0.5f * (a + b) + 0.02f * accel_test::random_direction(rng), 0});
  }
  return tris;
}

std::vector<std::uint32_t> all_ids(std::size_t count) {
  std::vector<std::uint32_t> ids(count);
  for (std::uint32_t i = 0; i < count; ++i) ids[i] = i;
  return ids;
}

struct Walk {
  const Bvh& bvh;
  std::vector<int> leaves_per_triangle;
  // Which triangles have a point inside a leaf box: each triangle's sampled points must all
  // lie in the union of its leaves' boxes.
  std::vector<std::vector<std::uint32_t>> leaves_of;

  void node(std::uint32_t index, std::uint32_t depth) {
    ASSERT_LE(depth, kMaxBvhDepth);
    const BvhNode& n = bvh.nodes[index];
    if (n.is_leaf()) {
      for (std::uint32_t i = n.offset; i < n.offset + n.count; ++i) {
        ++leaves_per_triangle[bvh.primitives[i]];
        leaves_of[bvh.primitives[i]].push_back(index);
      }
      return;
    }
    EXPECT_TRUE(contains(n, bvh.nodes[index + 1]));
    EXPECT_TRUE(contains(n, bvh.nodes[n.offset]));
    node(index + 1, depth + 1);
    node(n.offset, depth + 1);
  }
};

void check_tree(const Bvh& bvh, const std::vector<Triangle>& tris, float budget) {
  Walk walk{bvh, std::vector<int>(tris.size(), 0), {}};
  walk.leaves_of.resize(tris.size());
  walk.node(0, 1);
  std::size_t references = 0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    ASSERT_GE(walk.leaves_per_triangle[t], 1) << "triangle " << t << " in no leaf";
    references += static_cast<std::size_t>(walk.leaves_per_triangle[t]);
    // Points spread over the triangle (vertices and edges included) lie in some leaf box of
    // that triangle: clipped boxes never cut a part of it off.
    for (int s = 0; s < 64; ++s) {
      float u = unit(rng), v = unit(rng);
      if (s < 3) u = s == 1 ? 1.0f : 0.0f, v = s == 2 ? 1.0f : 0.0f;
      if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
      const vec3 p = tris[t].p0 + u * (tris[t].p1 - tris[t].p0) + v * (tris[t].p2 - tris[t].p0);
      bool inside = false;
      // The sample's own rounding (a few ulps of coordinates up to 8) is all the slack.
      for (std::uint32_t leaf : walk.leaves_of[t]) inside |= contains(bvh.nodes[leaf], p, 1e-5f);
      ASSERT_TRUE(inside) << "triangle " << t << " point " << s << " outside its leaves";
    }
  }
  EXPECT_EQ(references, bvh.primitives.size());
  EXPECT_LE(references, tris.size() + static_cast<std::size_t>(budget * tris.size()) + 1);
}

TEST(Sbvh, SliversGetSpatialSplitsWithinTheBudgetAndBoxesHoldTheirParts) {
  const auto tris = slivers(600, 5);
  for (float budget : {0.0f, 0.25f, 1.0f}) {
    SpatialSplitOptions options;
    options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
    options.max_extra_references = budget;
    options.min_spatial_references = 0;  // 600 slivers split only in small nodes
    const Bvh bvh = build_sbvh(tris, all_ids(tris.size()), options);
    check_tree(bvh, tris, budget);
    if (budget == 0.0f) {
      EXPECT_EQ(bvh.primitives.size(), tris.size());
    } else {
      EXPECT_GT(bvh.primitives.size(), tris.size()) << "budget " << budget;
    }
  }
}

// Nodes of fewer references than min_spatial_references get no spatial search: above the
// input's size, none at all, so no extra references whatever the budget; the default still
// splits a larger sliver soup.
TEST(Sbvh, SmallNodesGetNoSpatialSearch) {
  const auto tris = slivers(600, 5);
  SpatialSplitOptions options;
  options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
  options.max_extra_references = 1.0f;
  options.min_spatial_references = 601;
  const Bvh none = build_sbvh(tris, all_ids(tris.size()), options);
  check_tree(none, tris, 1.0f);
  EXPECT_EQ(none.primitives.size(), tris.size());
  const auto more = slivers(6000, 6);
  const Bvh split = build_sbvh(more, all_ids(more.size()), SpatialSplitOptions{});
  check_tree(split, more, SpatialSplitOptions{}.max_extra_references);
  EXPECT_GT(split.primitives.size(), more.size());
}

TEST(Sbvh, EvenMeshAndGridStayValid) {
  for (const auto& tris : {accel_test::closed_sphere(4), accel_test::axis_aligned_grid(8),
                           accel_test::triangle_soup(500, 9)}) {
    SpatialSplitOptions options;
    options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
    options.max_extra_references = 1.0f;
    check_tree(build_sbvh(tris, all_ids(tris.size()), options), tris, 1.0f);
  }
}

// Inputs that defeat the heuristic: every triangle the same (no split separates them), and
// coordinates so large that surface areas overflow to infinity. The tree must still hold
// every triangle within the depth limit.
TEST(Sbvh, IdenticalTrianglesAndHugeCoordinatesStillGiveValidTrees) {
  const Triangle one{vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0};
  const std::vector<Triangle> same(300, one);
  auto huge = slivers(300, 4);
  for (Triangle& t : huge) {
    t.p0 *= 1e19f;
    t.p1 *= 1e19f;
    t.p2 *= 1e19f;
  }
  const std::vector<Triangle>* inputs[] = {&same, &huge};
  for (const std::vector<Triangle>* tris : inputs) {
    SpatialSplitOptions options;
    options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
    const Bvh bvh = build_sbvh(*tris, all_ids(tris->size()), options);
    ASSERT_LE(bvh.depth, kMaxBvhDepth);
    Walk walk{bvh, std::vector<int>(tris->size(), 0), {}};
    walk.leaves_of.resize(tris->size());
    walk.node(0, 1);
    for (int leaves : walk.leaves_per_triangle) EXPECT_GE(leaves, 1);
  }
}

TEST(Sbvh, SpatialSplitsLowerTheTreeCostOfSlivers) {
  const auto tris = slivers(3000, 11);
  AccelBuildOptions options;
  options.kind = AccelKind::kWide;
  options.presplit_budget = 0.0f;
  options.spatial_split_budget = 0.0f;
  const TriangleAccel plain = TriangleAccel::build(tris, options);
  options.spatial_split_budget = 1.0f;
  const TriangleAccel spatial = TriangleAccel::build(tris, options);
  const double plain_cost = plain.stats().sah.nodes + plain.stats().sah.leaves;
  const double spatial_cost = spatial.stats().sah.nodes + spatial.stats().sah.leaves;
  EXPECT_LT(spatial_cost, 0.9 * plain_cost);
  EXPECT_GT(spatial.stats().leaf_references, tris.size());
}

TEST(Sbvh, SubsetOfIdsAndEmptyInput) {
  const auto tris = slivers(50, 2);
  const std::vector<std::uint32_t> ids = {3, 9, 27, 31, 49};
  const Bvh bvh = build_sbvh(tris, ids, SpatialSplitOptions{});
  for (std::uint32_t id : bvh.primitives)
    EXPECT_TRUE(id == 3 || id == 9 || id == 27 || id == 31 || id == 49);
  EXPECT_TRUE(build_sbvh(tris, {}, SpatialSplitOptions{}).nodes.empty());
  const std::vector<std::uint32_t> bad = {50};
  EXPECT_THROW(build_sbvh(tris, bad, SpatialSplitOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

// Large nodes build their children in parallel; the budget is shared out in proportion, so
// the tree is the same as the sequential build's, node for node.
TEST(Sbvh, ParallelBuildGivesTheSequentialTree) {
  std::vector<Triangle> tris = accel_test::closed_sphere(5);  // 8,192 even triangles
  const auto thin = slivers(4000, 21);
  tris.insert(tris.end(), thin.begin(), thin.end());
  SpatialSplitOptions options;
  options.max_extra_references = 0.5f;
  options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, true};
  const Bvh parallel = build_sbvh(tris, all_ids(tris.size()), options);
  options.bvh.parallel = false;
  const Bvh sequential = build_sbvh(tris, all_ids(tris.size()), options);
  ASSERT_EQ(parallel.nodes.size(), sequential.nodes.size());
  ASSERT_EQ(parallel.primitives, sequential.primitives);
  EXPECT_EQ(parallel.depth, sequential.depth);
  for (std::size_t i = 0; i < parallel.nodes.size(); ++i) {
    EXPECT_EQ(parallel.nodes[i].offset, sequential.nodes[i].offset);
    EXPECT_EQ(parallel.nodes[i].count, sequential.nodes[i].count);
    EXPECT_EQ(parallel.nodes[i].lower, sequential.nodes[i].lower);
    EXPECT_EQ(parallel.nodes[i].upper, sequential.nodes[i].upper);
  }
  EXPECT_GT(parallel.primitives.size(), tris.size());
  check_tree(parallel, tris, 0.5f);
}

TEST(Sbvh, ChosenForEvenMeshesUpToTheSizeCapAndNotWithPresplitting) {
  EXPECT_EQ(choose_spatial_split_budget(1000, 0.0f), kAutoSpatialSplitBudget);
  EXPECT_EQ(choose_spatial_split_budget(kAutoSpatialSplitMaxTriangles, 0.0f),
            kAutoSpatialSplitBudget);
  EXPECT_EQ(choose_spatial_split_budget(kAutoSpatialSplitMaxTriangles + 1, 0.0f), 0.0f);
  EXPECT_EQ(choose_spatial_split_budget(1000, 1.0f), 0.0f);
}

}  // namespace
}  // namespace tessera
