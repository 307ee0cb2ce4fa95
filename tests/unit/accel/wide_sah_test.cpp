// The wide tree's surface-area cost (wide_sah_cost), the figure compared with Embree's own
// statistics in bench/accel: checked on a hand-built tree whose cost is worked out by hand,
// and on built trees against a brute-force walk's invariants.
#include <gtest/gtest.h>

#include "accel_test_scenes.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "tessera/accel/wide_bvh.hpp"

namespace tessera {
namespace {

TEST(WideSahCost, EmptyTreeCostsNothing) {
  const WideSahCost cost = wide_sah_cost(WideBvh{});
  EXPECT_EQ(cost.nodes, 0.0);
  EXPECT_EQ(cost.leaves, 0.0);
}

// Root (box [0,1]^3, area 6) holds a leaf of 3 blocks with the root's box and an interior
// node B = [0,0.5]x[0,1]x[0,1] (area 4), which holds a leaf of 1 block C =
// [0,0.5]x[0,0.5]x[0,1] (area 2.5). Nodes: (6 + 4) / 6; leaves: (6 * 3 + 2.5 * 1) / 6.
TEST(WideSahCost, HandBuiltTreeMatchesTheWorkedOutCost) {
  WideBvh tree;
  tree.nodes.resize(2);
  tree.nodes[0].clear();
  tree.nodes[1].clear();
  tree.nodes[0].set_child(0, vec3(0.0f), vec3(1.0f), make_wide_leaf(0, 3));
  tree.nodes[0].set_child(1, vec3(0.0f), vec3(0.5f, 1.0f, 1.0f), 1);
  tree.nodes[1].set_child(0, vec3(0.0f), vec3(0.5f, 0.5f, 1.0f), make_wide_leaf(3, 1));
  tree.depth = 2;
  const WideSahCost cost = wide_sah_cost(tree);
  EXPECT_NEAR(cost.nodes, 10.0 / 6.0, 1e-6);
  EXPECT_NEAR(cost.leaves, 20.5 / 6.0, 1e-6);
}

// A built tree visits at least its root, and a ray through the root box must test at least
// one block; splitting a soup finer (smaller leaves) moves cost from blocks to nodes.
TEST(WideSahCost, BuiltTreesReportTheirCost) {
  const std::vector<Triangle> soup = accel_test::triangle_soup(4000, 7);
  AccelBuildOptions options;
  options.kind = AccelKind::kWide;
  const TriangleAccel merged = TriangleAccel::build(soup, options);
  options.wide_merge_limit = 0;
  const TriangleAccel unmerged = TriangleAccel::build(soup, options);
  for (const TriangleAccel* accel : {&merged, &unmerged}) {
    EXPECT_GE(accel->stats().sah.nodes, 1.0);
    EXPECT_GE(accel->stats().sah.leaves, 1.0);
  }
  EXPECT_LT(merged.stats().sah.nodes, unmerged.stats().sah.nodes);
  EXPECT_GT(merged.stats().sah.leaves, unmerged.stats().sah.leaves);
}

}  // namespace
}  // namespace tessera
