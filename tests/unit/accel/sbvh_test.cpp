// The spatial-split builder (accel/sbvh.hpp): every triangle reachable, boxes that hold
// what they claim (each reference's box the true part of its triangle, sampled), the
// reference budget kept, spatial splits made where triangles straddle and lowering the
// surface-area cost, none where they would not pay. Hits against brute force are checked by
// the `_sbvh` variants of TriangleAccelTest.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/presplit.hpp"
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

// A field of grass: blades of three long thin slanted triangles (a base quad and a tip),
// 1-2 cm wide and 10-50 cm tall, leaning up to their height, scattered over `side` metres.
std::vector<Triangle> grass(int blades, float side, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Triangle> tris;
  for (int i = 0; i < blades; ++i) {
    const vec3 base(side * unit(rng), 0.0f, side * unit(rng));
    const float height = 0.1f + 0.4f * unit(rng), width = 0.01f + 0.01f * unit(rng);
    const float face = 6.2832f * unit(rng), lean_angle = 6.2832f * unit(rng);
    const vec3 across = 0.5f * width * vec3(std::cos(face), 0.0f, std::sin(face));
    const vec3 lean = unit(rng) * height * vec3(std::cos(lean_angle), 0.0f, std::sin(lean_angle));
    const vec3 middle = base + vec3(0.0f, 0.55f * height, 0.0f) + 0.3f * lean;
    const vec3 tip = base + vec3(0.0f, height, 0.0f) + lean;
    tris.push_back(Triangle{base - across, base + across, middle + 0.7f * across, 0});
    tris.push_back(Triangle{base - across, middle + 0.7f * across, middle - 0.7f * across, 0});
    tris.push_back(Triangle{middle - 0.7f * across, middle + 0.7f * across, tip, 0});
  }
  return tris;
}

// The binary tree's expected cost for a ray through its root box (surface area heuristic,
// four-triangle blocks as the builder counts them).
double binary_sah(const Bvh& bvh) {
  const auto area = [](const BvhNode& n) {
    const vec3 e = n.upper - n.lower;
    return 2.0 * (static_cast<double>(e.x) * e.y + static_cast<double>(e.y) * e.z +
                  static_cast<double>(e.z) * e.x);
  };
  double cost = 0.0;
  for (const BvhNode& n : bvh.nodes)
    cost += area(n) * (n.is_leaf() ? static_cast<double>((n.count + 3) / 4) : 1.0);
  return cost / area(bvh.nodes[0]);
}

// One slanted tube of 64 strips 2 long and 2 mm wide, each running the tube's whole length
// (as a CAD tessellator emits a cylinder): every strip crosses every plane a spatial search
// tries, so the only split that shrinks any box cuts all of them, leaving each side with
// every reference; object splits only halve the ring around, to boxes as long as before.
TEST(Sbvh, StripsRunningTheWholeNodeAreCutTogether) {
  const vec3 along = glm::normalize(vec3(1.0f, 0.8f, 0.6f));
  const vec3 u = glm::normalize(glm::cross(along, vec3(0.0f, 0.0f, 1.0f)));
  const vec3 v = glm::cross(along, u);
  constexpr int kStrips = 64;
  constexpr float kRadius = 0.02f, kLength = 2.0f;
  std::vector<Triangle> tube;
  for (int i = 0; i < kStrips; ++i) {
    const float a0 = 6.2832f * static_cast<float>(i) / kStrips;
    const float a1 = 6.2832f * static_cast<float>(i + 1) / kStrips;
    const vec3 p0 = kRadius * (std::cos(a0) * u + std::sin(a0) * v);
    const vec3 p1 = kRadius * (std::cos(a1) * u + std::sin(a1) * v);
    tube.push_back(Triangle{p0, p1, p1 + kLength * along, 0});
    tube.push_back(Triangle{p0, p1 + kLength * along, p0 + kLength * along, 0});
  }
  SpatialSplitOptions options;
  options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
  options.max_extra_references = 4.0f;
  const Bvh cut = build_sbvh(tube, all_ids(tube.size()), options);
  options.max_extra_references = 0.0f;
  const Bvh whole = build_sbvh(tube, all_ids(tube.size()), options);
  check_tree(cut, tube, 4.0f);
  EXPECT_GT(cut.primitives.size(), 2 * tube.size());
  EXPECT_LT(binary_sah(cut), 0.5 * binary_sah(whole))
      << binary_sah(cut) << " against " << binary_sah(whole);
}

// A field of 250,000 blades is too large for a unit test: the tests below take 4,000 blades
// on 2.5 m (the same density) with min_overlap raised to 5e-2, which leaves the same few top
// levels to the root's rule.
SpatialSplitOptions dense_field_options() {
  SpatialSplitOptions options;
  options.bvh = BvhBuildOptions{4, 4, 1.0f, 1.0f, 16, false};
  options.max_extra_references = 1.0f;
  options.min_overlap = 5e-2f;
  return options;
}

// Grass blades overlap at the scale of a few blades, far below min_overlap of a field's root
// box: only the rule for references that fill their boxes poorly searches there, and its
// splits make the tree cheaper.
TEST(Sbvh, GrassGetsSpatialSplitsFarBelowTheRootScaleWhereBoxesFitPoorly) {
  const auto field = grass(4000, 2.5f, 31);
  const SpatialSplitOptions deep = dense_field_options();
  SpatialSplitOptions shallow = deep;
  shallow.min_fill_ratio_deep = std::numeric_limits<float>::infinity();
  const Bvh with = build_sbvh(field, all_ids(field.size()), deep);
  const Bvh without = build_sbvh(field, all_ids(field.size()), shallow);
  check_tree(with, field, deep.max_extra_references);
  EXPECT_GT(with.primitives.size(), without.primitives.size() + field.size() / 10);
  EXPECT_LT(binary_sah(with), 0.95 * binary_sah(without));

  // The rule follows the references' fill ratio, node by node: a threshold above the
  // field's own leaves fewer nodes to it.
  std::vector<Aabb> boxes;
  for (const Triangle& t : field) boxes.push_back(bounds(t));
  const double fill = box_fill_ratio(field, all_ids(field.size()), boxes);
  ASSERT_GT(fill, 2.0 * deep.min_fill_ratio_deep);
  SpatialSplitOptions strict = deep;
  strict.min_fill_ratio_deep = static_cast<float>(1.5 * fill);
  const Bvh fewer = build_sbvh(field, all_ids(field.size()), strict);
  EXPECT_LT(fewer.primitives.size(), with.primitives.size());
  EXPECT_GT(fewer.primitives.size(), without.primitives.size());
}

// Below the root's rule only the references that fill their boxes poorly are cut: a ground
// quad under the grass stays in as many pieces as the top levels cut it into, where cutting
// it into every leaf of the blades above slowed camera rays over a held-out meadow by a
// fifth. The blades are still cut.
TEST(Sbvh, DeepSearchesCutTheBladesButNotTheGroundBeneathThem) {
  auto field = grass(4000, 2.5f, 32);
  const auto blade_triangles = static_cast<std::uint32_t>(field.size());
  field.push_back(
      Triangle{vec3(-0.1f, -0.01f, -0.1f), vec3(2.6f, -0.01f, -0.1f), vec3(2.6f, -0.01f, 2.6f), 0});
  field.push_back(
      Triangle{vec3(-0.1f, -0.01f, -0.1f), vec3(2.6f, -0.01f, 2.6f), vec3(-0.1f, -0.01f, 2.6f), 0});
  const SpatialSplitOptions deep = dense_field_options();
  SpatialSplitOptions shallow = deep;
  shallow.min_fill_ratio_deep = std::numeric_limits<float>::infinity();
  const auto count = [&](const Bvh& bvh, bool ground) {
    std::size_t n = 0;
    for (std::uint32_t id : bvh.primitives) n += (id >= blade_triangles) == ground ? 1 : 0;
    return n;
  };
  const Bvh with = build_sbvh(field, all_ids(field.size()), deep);
  const Bvh without = build_sbvh(field, all_ids(field.size()), shallow);
  check_tree(with, field, deep.max_extra_references);
  EXPECT_GT(count(with, false), count(without, false) + blade_triangles / 10);
  EXPECT_LE(count(with, true), count(without, true));
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
