// Pre-splitting: the piece boxes bound the triangle's parts (checked on sampled points, with
// boxes from an independent clip), stay within the budget, and a wide BVH built from them
// answers exactly as the brute-force reference (triangle_accel_test runs every query on
// pre-split variants too). The automatic choice pre-splits a thin-triangle soup and leaves an
// evenly tessellated mesh alone; a given budget, 0 included, overrides it.
#include "tessera/accel/presplit.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/triangle_accel.hpp"

namespace tessera {
namespace {

// Within `box` grown by `slack` (sampled points are rounded to float, so they can lie an ulp
// off the exact triangle the boxes bound).
bool inside(const Aabb& box, const vec3& p, float slack = 0.0f) {
  for (int axis = 0; axis < 3; ++axis)
    if (!(p[axis] >= box.lower[axis] - slack && p[axis] <= box.upper[axis] + slack)) return false;
  return true;
}
constexpr float kSlack = 1e-6f;

// Points of the triangle: random barycentric ones, its vertices and edge midpoints (float).
std::vector<vec3> sample_points(const Triangle& t, std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<vec3> points{
      t.p0, t.p1, t.p2, 0.5f * (t.p0 + t.p1), 0.5f * (t.p1 + t.p2), 0.5f * (t.p2 + t.p0)};
  for (int i = 0; i < count; ++i) {
    float b1 = unit(rng), b2 = unit(rng);
    if (b1 + b2 > 1.0f) {
      b1 = 1.0f - b1;
      b2 = 1.0f - b2;
    }
    points.push_back(t.p0 + b1 * (t.p1 - t.p0) + b2 * (t.p2 - t.p0));
  }
  return points;
}

// Long, thin, diagonal triangles: the case pre-splitting is for.
std::vector<Triangle> slivers(std::uint32_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Triangle> tris;
  for (std::uint32_t i = 0; i < count; ++i) {
    const vec3 a = accel_test::random_point(rng, -1.0f, 1.0f);
    const vec3 b = accel_test::random_point(rng, -1.0f, 1.0f);
    const vec3 side = 0.02f * accel_test::random_direction(rng);
    tris.push_back(Triangle{a, b, 0.5f * (a + b) + side, 0});
  }
  return tris;
}

// Every triangle of `tris` as presplit_triangles takes it: its index, its box, and the
// scene's box.
struct PresplitInput {
  std::vector<std::uint32_t> ids;
  std::vector<Aabb> boxes;
  Aabb scene;
  explicit PresplitInput(const std::vector<Triangle>& tris) : ids(tris.size()), boxes(tris.size()) {
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
      ids[i] = i;
      boxes[i] = bounds(tris[i]);
      scene.extend(boxes[i]);
    }
  }
};

TEST(Presplit, ClippedBoundsHoldThePartOfTheTriangleInTheBox) {
  std::mt19937 rng(31);
  for (const Triangle& t : slivers(200, 32)) {
    const Aabb whole = bounds(t);
    EXPECT_EQ(clipped_triangle_bounds(t, whole).lower, whole.lower);  // nothing to clip
    EXPECT_EQ(clipped_triangle_bounds(t, whole).upper, whole.upper);
    Aabb box;
    box.extend(accel_test::random_point(rng, -1.0f, 1.0f));
    box.extend(accel_test::random_point(rng, -1.0f, 1.0f));
    const Aabb clipped = clipped_triangle_bounds(t, box);
    for (const vec3& p : sample_points(t, rng, 500)) {
      if (!inside(box, p)) continue;
      ASSERT_FALSE(clipped.empty());
      ASSERT_TRUE(inside(clipped, p, kSlack));
    }
    if (!clipped.empty()) {
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(clipped.lower[axis], box.lower[axis]);
        EXPECT_LE(clipped.upper[axis], box.upper[axis]);
      }
    }
  }
}

TEST(Presplit, PiecesCoverEachTriangleWithinTheBudget) {
  const auto tris = slivers(500, 33);
  const PresplitInput in(tris);
  const auto& [ids, boxes, scene] = in;
  for (const float budget : {0.25f, 1.0f, 4.0f}) {
    HugePageVector<Aabb> pieces;
    HugePageVector<std::uint32_t> piece_ids;
    presplit_triangles(tris, ids, boxes, scene, budget, pieces, piece_ids);
    ASSERT_EQ(pieces.size(), piece_ids.size());
    EXPECT_GT(pieces.size(), tris.size());
    EXPECT_LE(pieces.size(), tris.size() + static_cast<std::size_t>(budget * tris.size()));
    std::vector<std::vector<Aabb>> of(tris.size());
    float area_before = 0.0f, area_after = 0.0f;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      ASSERT_LT(piece_ids[k], tris.size());
      of[piece_ids[k]].push_back(pieces[k]);
      area_after += pieces[k].surface_area();
      for (int axis = 0; axis < 3; ++axis) {  // inside the triangle's own box
        ASSERT_GE(pieces[k].lower[axis], boxes[piece_ids[k]].lower[axis]);
        ASSERT_LE(pieces[k].upper[axis], boxes[piece_ids[k]].upper[axis]);
      }
    }
    for (const Aabb& b : boxes) area_before += b.surface_area();
    EXPECT_LT(area_after, area_before);  // the point of it: tighter boxes in total
    std::mt19937 rng(34);
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
      ASSERT_FALSE(of[i].empty());
      for (const vec3& p : sample_points(tris[i], rng, 200)) {
        bool covered = false;
        for (const Aabb& piece : of[i]) covered = covered || inside(piece, p, kSlack);
        ASSERT_TRUE(covered) << "triangle " << i;
      }
    }
  }
}

// The cuts clip each piece's polygon by one plane at a time rather than the whole triangle by
// the piece's box; both are the same part of the triangle, so each piece must be as tight as
// an independent clip of the triangle to it (within the outward rounding: an ulp or so per
// bound). A piece left loose (its parent's box) would still cover the triangle, and the test
// above would pass; this one would not.
TEST(Presplit, PiecesAreTheBoxesOfTheTrianglesPartsInThem) {
  const auto tris = slivers(2000, 39);
  const PresplitInput in(tris);
  const auto& [ids, boxes, scene] = in;
  HugePageVector<Aabb> pieces;
  HugePageVector<std::uint32_t> piece_ids;
  presplit_triangles(tris, ids, boxes, scene, 4.0f, pieces, piece_ids);
  ASSERT_GT(pieces.size(), 3 * tris.size());
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Aabb fresh = clipped_triangle_bounds(tris[piece_ids[k]], pieces[k]);
    ASSERT_FALSE(fresh.empty()) << k;
    const float slack = 4e-7f * (glm::length(pieces[k].extent()) + 1.0f);
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_NEAR(pieces[k].lower[axis], fresh.lower[axis], slack) << k;
      ASSERT_NEAR(pieces[k].upper[axis], fresh.upper[axis], slack) << k;
    }
  }
}

// The cuts run in parallel over chunks of triangles: the pieces, their order included, must
// not depend on the thread count, or the tree (and a render's image) would not either.
TEST(Presplit, PiecesAreTheSameForAnyThreadCount) {
  const auto tris = slivers(10000, 38);  // several chunks of the parallel loop
  const PresplitInput in(tris);
  const auto& [ids, boxes, scene] = in;
  const auto pieces_with = [&](int threads, HugePageVector<Aabb>& pieces,
                               HugePageVector<std::uint32_t>& piece_ids) {
    tbb::task_arena arena(threads);
    arena.execute([&] { presplit_triangles(tris, ids, boxes, scene, 2.0f, pieces, piece_ids); });
  };
  HugePageVector<Aabb> one, four;
  HugePageVector<std::uint32_t> one_ids, four_ids;
  pieces_with(1, one, one_ids);
  pieces_with(4, four, four_ids);
  ASSERT_GT(one.size(), tris.size());
  ASSERT_EQ(one.size(), four.size());
  ASSERT_EQ(one_ids, four_ids);
  for (std::size_t k = 0; k < one.size(); ++k) {
    ASSERT_EQ(one[k].lower, four[k].lower) << k;
    ASSERT_EQ(one[k].upper, four[k].upper) << k;
  }
}

std::vector<std::uint32_t> all_ids(std::size_t count) {
  std::vector<std::uint32_t> ids(count);
  for (std::uint32_t i = 0; i < count; ++i) ids[i] = i;
  return ids;
}

double fill_ratio_of(const std::vector<Triangle>& tris) {
  std::vector<Aabb> boxes;
  for (const Triangle& t : tris) boxes.push_back(bounds(t));
  return box_fill_ratio(tris, all_ids(tris.size()), boxes);
}

TEST(Presplit, BoxFillRatioMeasuresHowPoorlyTrianglesFillTheirBoxes) {
  // A right triangle in an axis plane fills half of its flat box: box surface 2wh, twice
  // the triangle's area wh.
  EXPECT_DOUBLE_EQ(fill_ratio_of({Triangle{vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 3, 0), 0}}), 2.0);
  const double sphere = fill_ratio_of(accel_test::closed_sphere(4));
  EXPECT_GT(sphere, 2.0);
  EXPECT_LT(sphere, kAutoPresplitMinFillRatio);
  EXPECT_GT(fill_ratio_of(slivers(500, 35)), 4.0 * kAutoPresplitMinFillRatio);
  EXPECT_EQ(box_fill_ratio({}, {}, {}), 0.0);
}

TEST(Presplit, BudgetGrowsWithTheFillRatioUpToTheCap) {
  constexpr std::size_t kSmall = 1000;  // spatial splits are the alternative
  EXPECT_EQ(choose_presplit_budget(0.0, kSmall), 0.0f);
  EXPECT_EQ(choose_presplit_budget(5.0, kSmall), 0.0f);
  EXPECT_EQ(choose_presplit_budget(std::nan(""), kSmall), 0.0f);
  // Spatial splits below the threshold; from it, one reference per step of the ratio.
  EXPECT_EQ(choose_presplit_budget(std::nextafter(kAutoPresplitMinFillRatio, 0.0), kSmall), 0.0f);
  EXPECT_EQ(choose_presplit_budget(kAutoPresplitMinFillRatio, kSmall),
            static_cast<float>(kAutoPresplitMinFillRatio / kAutoPresplitFillRatioPerReference));
  EXPECT_EQ(choose_presplit_budget(3.0 * kAutoPresplitFillRatioPerReference, kSmall), 3.0f);
  EXPECT_EQ(choose_presplit_budget(1000.0 * kAutoPresplitMinFillRatio, kSmall),
            kAutoPresplitMaxBudget);
}

TEST(Presplit, MeshesTooLargeForSpatialSplitsPreSplitFromALowerRatio) {
  // Past kAutoSpatialSplitMaxTriangles the binned builder is the alternative, which
  // pre-splitting beats from a lower ratio than it beats spatial splits.
  constexpr std::size_t kLarge = kAutoSpatialSplitMaxTriangles + 1;
  static_assert(kAutoPresplitMinFillRatioWithoutSpatialSplits < kAutoPresplitMinFillRatio);
  EXPECT_EQ(choose_presplit_budget(
                std::nextafter(kAutoPresplitMinFillRatioWithoutSpatialSplits, 0.0), kLarge),
            0.0f);
  EXPECT_EQ(choose_presplit_budget(kAutoPresplitMinFillRatioWithoutSpatialSplits, kLarge),
            static_cast<float>(kAutoPresplitMinFillRatioWithoutSpatialSplits /
                               kAutoPresplitFillRatioPerReference));
  EXPECT_EQ(choose_presplit_budget(kAutoPresplitMinFillRatioWithoutSpatialSplits,
                                   kAutoSpatialSplitMaxTriangles),
            0.0f);
}

// Pre-splitting belongs to the binned builder: spatial splits stay off unless asked for.
AccelStats build_stats(const std::vector<Triangle>& tris, std::optional<float> budget,
                       std::optional<float> spatial_budget = 0.0f) {
  AccelBuildOptions options;
  options.kind = AccelKind::kWide;
  options.presplit_budget = budget;
  options.spatial_split_budget = spatial_budget;
  return TriangleAccel::build(tris, options).stats();
}

TEST(Presplit, ChosenForThinTrianglesAndNotForAnEvenMesh) {
  const auto thin = slivers(2000, 36);
  const AccelStats thin_auto = build_stats(thin, std::nullopt, std::nullopt);
  EXPECT_TRUE(thin_auto.presplit_chosen);
  EXPECT_TRUE(thin_auto.spatial_split_chosen);
  EXPECT_EQ(thin_auto.spatial_split_budget, 0.0f);  // pre-split instead
  EXPECT_EQ(thin_auto.presplit_budget, choose_presplit_budget(thin_auto.fill_ratio, thin.size()));
  EXPECT_GE(thin_auto.presplit_budget, 1.0f);
  EXPECT_GT(thin_auto.fill_ratio, kAutoPresplitMinFillRatio);
  EXPECT_GT(thin_auto.leaf_references, thin.size());  // pieces of one triangle in several leaves

  const auto even = accel_test::closed_sphere(5);  // 8,192 triangles
  const AccelStats even_auto = build_stats(even, std::nullopt, std::nullopt);
  EXPECT_TRUE(even_auto.presplit_chosen);
  EXPECT_EQ(even_auto.presplit_budget, 0.0f);
  EXPECT_LT(even_auto.fill_ratio, kAutoPresplitMinFillRatio);
  EXPECT_TRUE(even_auto.spatial_split_chosen);  // spatial splits instead, within their budget
  EXPECT_EQ(even_auto.spatial_split_budget, kAutoSpatialSplitBudget);
  EXPECT_LE(even_auto.leaf_references, 2 * even.size());
  EXPECT_EQ(build_stats(even, std::nullopt).leaf_references, even.size());  // binned: one each
}

TEST(Presplit, AGivenBudgetOverridesTheChoice) {
  const auto thin = slivers(2000, 37);
  const AccelStats off = build_stats(thin, 0.0f);
  EXPECT_FALSE(off.presplit_chosen);
  EXPECT_EQ(off.presplit_budget, 0.0f);
  EXPECT_EQ(off.leaf_references, thin.size());

  const auto even = accel_test::closed_sphere(5);
  const AccelStats on = build_stats(even, 0.5f);
  EXPECT_FALSE(on.presplit_chosen);
  EXPECT_EQ(on.presplit_budget, 0.5f);
  EXPECT_GT(on.leaf_references, even.size());
}

}  // namespace
}  // namespace tessera
