// Every structure (binary BVH, wide BVH, octree, brute force), on every instruction set the
// machine has, against the brute-force reference (tessera::intersect on each triangle):
// same hits, same t, for closest, any and all-hits queries.
#include "tessera/accel/triangle_accel.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <tuple>

#include "accel_test_scenes.hpp"

namespace tessera {
namespace {

using accel_test::ReferenceHit;

struct Variant {
  AccelKind kind;
  KernelIsa isa;
  float presplit = 0.0f;  // AccelBuildOptions::presplit_budget (wide BVH only)
  float sbvh = 0.0f;      // AccelBuildOptions::spatial_split_budget (wide BVH only)
};

std::string describe(const Variant& v) {
  return std::string(accel_kind_name(v.kind)) + "_" + std::string(kernel_isa_name(v.isa)) +
         (v.presplit > 0.0f ? "_presplit" : "") + (v.sbvh > 0.0f ? "_sbvh" : "");
}

std::string variant_name(const testing::TestParamInfo<Variant>& info) {
  return describe(info.param);
}

// Without it GoogleTest prints a parameter's bytes, the padding after the two enums
// included, which valgrind reports as uninitialised reads.
void PrintTo(const Variant& v, std::ostream* out) {
  *out << describe(v);
}

class TriangleAccelTest : public testing::TestWithParam<Variant> {
 protected:
  void SetUp() override {
    // The binary BVH is walked by scalar code on every processor.
    if (GetParam().kind != AccelKind::kBvh && !cpu_supports_kernels(GetParam().isa))
      GTEST_SKIP() << "this processor does not run the " << kernel_isa_name(GetParam().isa)
                   << " kernels";
  }

  TriangleAccel build(const std::vector<Triangle>& tris) const {
    AccelBuildOptions options;
    options.kind = GetParam().kind;
    options.max_isa = GetParam().isa;
    options.presplit_budget = GetParam().presplit;
    options.spatial_split_budget = GetParam().sbvh;
    options.octree.leaf_size = 4;  // deep octrees: more duplicated references
    TriangleAccel accel = TriangleAccel::build(tris, options);
    EXPECT_EQ(accel.stats().kind, GetParam().kind);
    if (GetParam().kind != AccelKind::kBvh) {
      EXPECT_EQ(accel.stats().isa, kernel_isa_name(GetParam().isa));
    }
    return accel;
  }

  // Closest and any-hit against the reference, ray by ray.
  static void expect_same_hits(const std::vector<Triangle>& tris, const TriangleAccel& accel,
                               const std::vector<Ray>& rays) {
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Ray& ray = rays[i];
      const ReferenceHit expected = accel_test::reference_closest(tris, ray);
      HitRecord got;
      const bool hit = accel.closest(ray, got);
      ASSERT_EQ(hit, expected.hit) << "ray " << i;
      ASSERT_EQ(accel.occluded(ray), expected.hit) << "ray " << i;
      if (!hit) continue;
      ++hits;
      ASSERT_EQ(got.t, expected.record.t) << "ray " << i;
      if (got.primitive != expected.record.primitive) {
        // A tie: another triangle at exactly the same distance (shared edges, coplanar
        // overlaps). The one reported must itself be hit there.
        HitRecord own;
        ASSERT_LT(got.primitive, tris.size());
        ASSERT_TRUE(intersect(tris[got.primitive], ray, kInfinity, own, got.primitive))
            << "ray " << i;
        ASSERT_EQ(own.t, got.t) << "ray " << i;
      } else {
        ASSERT_EQ(got.u, expected.record.u) << "ray " << i;
        ASSERT_EQ(got.v, expected.record.v) << "ray " << i;
      }
    }
    // The scenes are built so that a good share of the rays hit something.
    EXPECT_GT(hits, rays.size() / 10);
  }

  static void expect_same_all_hits(const std::vector<Triangle>& tris, const TriangleAccel& accel,
                                   const std::vector<Ray>& rays, std::uint32_t capacity) {
    std::vector<HitRecord> got(capacity);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const std::vector<HitRecord> all = accel_test::reference_all(tris, rays[i]);
      const std::uint32_t count = accel.all_hits(rays[i], got.data(), capacity);
      ASSERT_EQ(count, std::min<std::size_t>(capacity, all.size())) << "ray " << i;
      for (std::uint32_t k = 0; k < count; ++k) {
        ASSERT_EQ(got[k].t, all[k].t) << "ray " << i << " hit " << k;
        if (k > 0) {
          ASSERT_LE(got[k - 1].t, got[k].t);
        }
        for (std::uint32_t j = 0; j < k; ++j)
          ASSERT_NE(got[j].primitive, got[k].primitive) << "duplicate";
        // The triangle named must be hit at that t (ties may order equal t differently).
        HitRecord own;
        ASSERT_TRUE(intersect(tris[got[k].primitive], rays[i], kInfinity, own, got[k].primitive));
        ASSERT_EQ(own.t, got[k].t);
      }
    }
  }
};

TEST_P(TriangleAccelTest, TriangleSoupMatchesBruteForce) {
  const auto tris = accel_test::triangle_soup(600, 7);
  const TriangleAccel accel = build(tris);
  expect_same_hits(tris, accel, accel_test::test_rays(1500, 11, 1.5f));
}

// Eight clusters of 9 to 16 triangles at the corners of a cube: the wide BVH's root takes
// the clusters as its eight children, and each cluster's subtree becomes one leaf of three
// to five blocks, which the AVX-512 kernels test up to four at a time in one sixteen-lane
// pass (three-block passes with the third block's copy masked off).
TEST_P(TriangleAccelTest, LeavesOfSeveralBlocksMatchBruteForce) {
  for (std::uint32_t per_cluster = 9; per_cluster <= 16; ++per_cluster) {
    SCOPED_TRACE(per_cluster);
    std::mt19937 rng(40 + per_cluster);
    std::vector<Triangle> tris;
    for (int corner = 0; corner < 8; ++corner) {
      const vec3 centre(corner & 1 ? 1.0f : -1.0f, corner & 2 ? 1.0f : -1.0f,
                        corner & 4 ? 1.0f : -1.0f);
      for (const Triangle& t : accel_test::triangle_soup(per_cluster, rng()))
        tris.push_back(
            Triangle{centre + 0.3f * t.p0, centre + 0.3f * t.p1, centre + 0.3f * t.p2, 0});
    }
    const TriangleAccel accel = build(tris);
    // Rays from around the scene towards points near its triangles (some just outside), so
    // most of them hit, often several triangles of one cluster.
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays = accel_test::test_rays(200, 80 + per_cluster, 1.5f);
    for (std::size_t i = 0; i < 4 * tris.size(); ++i) {
      const Triangle& t = tris[i % tris.size()];
      const float a = 1.2f * unit(rng), b = (1.2f - a) * unit(rng);
      const vec3 target = t.p0 + a * (t.p1 - t.p0) + b * (t.p2 - t.p0);
      const vec3 origin = 4.0f * accel_test::random_direction(rng);
      rays.push_back(Ray{origin, glm::normalize(target - origin), 0.0f, kInfinity});
    }
    expect_same_hits(tris, accel, rays);
  }
}

TEST_P(TriangleAccelTest, LongThinTrianglesMatchBruteForce) {
  // Slivers spanning the cube diagonally (what pre-splitting cuts into several references,
  // several of which can meet in one leaf): closest, any and all hits as brute force.
  std::mt19937 rng(25);
  std::vector<Triangle> tris;
  for (int i = 0; i < 400; ++i) {
    const vec3 a = accel_test::random_point(rng, -1.0f, 1.0f);
    const vec3 b = accel_test::random_point(rng, -1.0f, 1.0f);
    tris.push_back(Triangle{a, b, 0.5f * (a + b) + 0.03f * accel_test::random_direction(rng), 0});
  }
  const TriangleAccel accel = build(tris);
  if (GetParam().presplit > 0.0f || GetParam().sbvh > 0.0f) {
    EXPECT_GT(accel.stats().leaf_references, tris.size());
  }
  const auto rays = accel_test::test_rays(1500, 26, 1.5f);
  expect_same_hits(tris, accel, rays);
  expect_same_all_hits(tris, accel, rays, 16);
}

TEST_P(TriangleAccelTest, AxisAlignedGridMatchesBruteForce) {
  // Flat boxes, rays running along box faces and triangle edges, +0.0 and -0.0 directions.
  const auto tris = accel_test::axis_aligned_grid(6);
  const TriangleAccel accel = build(tris);
  expect_same_hits(tris, accel, accel_test::test_rays(1500, 12, 6.0f));
}

TEST_P(TriangleAccelTest, AllHitsMatchBruteForce) {
  const auto tris = accel_test::triangle_soup(400, 8);
  const TriangleAccel accel = build(tris);
  const auto rays = accel_test::test_rays(400, 13, 1.5f);
  for (std::uint32_t capacity : {1u, 3u, 64u}) expect_same_all_hits(tris, accel, rays, capacity);
  const auto grid = accel_test::axis_aligned_grid(4);
  const TriangleAccel grid_accel = build(grid);
  expect_same_all_hits(grid, grid_accel, accel_test::test_rays(400, 14, 4.0f), 8);
}

TEST_P(TriangleAccelTest, ClosedMeshIsWatertight) {
  // From inside a closed mesh every ray hits, including rays aimed exactly at vertices
  // and along edges, where a non-watertight test lets rays slip between triangles.
  const auto tris = accel_test::closed_sphere(4);
  const TriangleAccel accel = build(tris);
  std::vector<Ray> rays;
  for (const Triangle& t : tris)
    for (const vec3& target : {t.p0, t.p1, t.p2, 0.5f * (t.p0 + t.p1)})
      rays.push_back(Ray{vec3(0.0f), target});
  for (const Ray& ray : accel_test::test_rays(500, 15, 0.5f))
    if (ray.t_max == kInfinity && glm::length(ray.origin) < 0.5f) rays.push_back(ray);  // inside
  for (std::size_t i = 0; i < rays.size(); ++i) {
    HitRecord hit;
    ASSERT_TRUE(accel.closest(rays[i], hit)) << "ray " << i;
    ASSERT_TRUE(accel.occluded(rays[i])) << "ray " << i;
  }
  expect_same_hits(tris, accel, rays);
}

TEST_P(TriangleAccelTest, BounceRaysFromTheSurfaceMatchBruteForce) {
  // Rays that start on the surface, as bounce rays do: the origin lies inside (or on) most
  // boxes the ray enters, so entry distances are zero or negative (t_min = 0 and t_min < 0)
  // and the origin's own triangle is tested at t near 0. A closed sphere and a soup
  // around it, origins at random points of random triangles, t compared exactly.
  auto tris = accel_test::closed_sphere(4);
  for (const Triangle& t : accel_test::triangle_soup(800, 21)) tris.push_back(t);
  const TriangleAccel accel = build(tris);
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
  std::vector<Ray> rays;
  for (int i = 0; i < 1500; ++i) {
    const Triangle& t = tris[pick(rng)];
    float b1 = unit(rng), b2 = unit(rng);
    if (b1 + b2 > 1.0f) {
      b1 = 1.0f - b1;
      b2 = 1.0f - b2;
    }
    const vec3 origin = t.p0 + b1 * (t.p1 - t.p0) + b2 * (t.p2 - t.p0);
    const float t_min = i % 3 == 0 ? -0.25f : 0.0f;
    rays.push_back(Ray{origin, accel_test::random_direction(rng), t_min, kInfinity});
  }
  expect_same_hits(tris, accel, rays);
}

// The wide structures reject a ray that misses the root's box before the walk's set-up.
// A flat structure (one plane of triangles: a root box of zero thickness) and rays from
// outside it that only just reach it: in its plane with +0.0 and -0.0 normal components
// (origin on the box's flat faces), at its corners and edges, and with t_max ending at the
// edge they aim for. Every one must agree with the brute-force reference.
TEST_P(TriangleAccelTest, RaysThatOnlyJustReachTheStructuresBoxMatchBruteForce) {
  std::vector<Triangle> tris;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const vec3 p00(static_cast<float>(i), static_cast<float>(j), 0.0f);
      const vec3 p10 = p00 + vec3(1, 0, 0), p01 = p00 + vec3(0, 1, 0), p11 = p00 + vec3(1, 1, 0);
      tris.push_back(Triangle{p00, p10, p11, 0});
      tris.push_back(Triangle{p00, p11, p01, 0});
    }
  const TriangleAccel accel = build(tris);
  std::vector<Ray> rays;
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> along(-1.0f, 7.0f);
  for (int i = 0; i < 600; ++i) {
    // A target on the structure's boundary (edge or corner) or inside it, and an origin
    // outside its box.
    vec3 target(along(rng), along(rng), 0.0f);
    if (i % 3 == 0) target.x = (i % 2) ? 0.0f : 6.0f;
    if (i % 5 == 0) target.y = (i % 2) ? 6.0f : 0.0f;
    const vec3 origin = target + vec3(along(rng) - 3.0f, along(rng) - 3.0f,
                                      (i % 4 == 0) ? 0.0f : along(rng) - 3.0f);
    vec3 direction = target - origin;
    if (direction == vec3(0.0f)) continue;
    if (i % 4 == 0) direction.z = (i % 8 == 0) ? -0.0f : 0.0f;  // in the plane, either zero
    const float reach = glm::length(target - origin) / glm::length(direction);
    rays.push_back(Ray{origin, direction, 0.0f, kInfinity});
    rays.push_back(Ray{origin, direction, 0.0f, reach});       // ends where it reaches the target
    rays.push_back(Ray{origin, -direction, 0.0f, kInfinity});  // away from it: no hit
  }
  // Along the box's faces and edges exactly: axis-parallel rays from outside on its
  // boundary lines, each sign of zero.
  for (float y : {0.0f, 3.0f, 6.0f})
    for (float zero : {0.0f, -0.0f}) {
      rays.push_back(Ray{vec3(-2.0f, y, 0.0f), vec3(1.0f, zero, zero)});
      rays.push_back(Ray{vec3(8.0f, y, 0.0f), vec3(-1.0f, zero, zero)});
      rays.push_back(Ray{vec3(y, -2.0f, 0.0f), vec3(zero, 1.0f, zero)});
      rays.push_back(Ray{vec3(y, 3.0f, 2.0f), vec3(zero, zero, -1.0f)});
    }
  expect_same_hits(tris, accel, rays);
  expect_same_all_hits(tris, accel, rays, 4);
}

TEST_P(TriangleAccelTest, DegenerateRaysNeverHit) {
  const auto tris = accel_test::triangle_soup(50, 9);
  const TriangleAccel accel = build(tris);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const Ray& ray :
       {Ray{vec3(0.0f), vec3(0.0f)}, Ray{vec3(nan, 0, 0), vec3(0, 0, 1)},
        Ray{vec3(0.0f), vec3(nan, 0, 1)}, Ray{vec3(kInfinity, 0, 0), vec3(-1, 0, 0)},
        Ray{vec3(-5, 0, 0), vec3(1, 0, 0), 2.0f, 1.0f},
        Ray{vec3(-5, 0, 0), vec3(1, 0, 0), nan, 10.0f}}) {
    HitRecord hit;
    EXPECT_FALSE(accel.closest(ray, hit));
    EXPECT_FALSE(hit.valid());
    EXPECT_FALSE(accel.occluded(ray));
    EXPECT_EQ(accel.all_hits(ray, &hit, 1), 0u);
  }
}

// A soup with zero-area triangles mixed in (exactly collinear vertices in both windings,
// coincident vertices) and rays aimed at points of them: no structure may report one, in
// closest, any or all-hits queries, and all agree with the brute-force reference. The
// builders drop them (stats().degenerate); before that the SSE2 and AVX2 kernels reported
// hits on them as the float test did (same operations), the binary BVH through the test.
TEST_P(TriangleAccelTest, DegenerateTrianglesAreNeverHit) {
  auto tris = accel_test::triangle_soup(300, 23);
  const auto first_degenerate = static_cast<std::uint32_t>(tris.size());
  std::mt19937 rng(24);
  std::uniform_int_distribution<int> corner(-8, 8), step(-4, 4);
  std::vector<vec3> targets;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  while (tris.size() < first_degenerate + 300) {
    // Integer vertices a quarter apart: exact, and inside the soup's [-2, 2] cube.
    const vec3 c = 0.25f * vec3(corner(rng), corner(rng), corner(rng));
    const vec3 d = 0.125f * vec3(step(rng), step(rng), step(rng));
    if (d == vec3(0.0f)) continue;
    for (const Triangle& t : {Triangle{c, c + d, c + 2.0f * d, 0},
                              Triangle{c, c + 2.0f * d, c + d, 0}, Triangle{c, c, c + d, 0}}) {
      tris.push_back(t);
      for (int k = 0; k < 4; ++k) targets.push_back(c + 2.0f * unit(rng) * d);
    }
  }
  const TriangleAccel accel = build(tris);
  EXPECT_EQ(accel.stats().degenerate, tris.size() - first_degenerate);
  std::vector<Ray> rays;
  for (const vec3& target : targets) {
    const vec3 origin = target + 3.0f * accel_test::random_direction(rng);
    rays.push_back(Ray{origin, target - origin, 0.0f, kInfinity});
  }
  HitRecord all[16];
  for (std::size_t i = 0; i < rays.size(); ++i) {
    HitRecord hit;
    if (accel.closest(rays[i], hit)) {
      ASSERT_LT(hit.primitive, first_degenerate) << "ray " << i;
    }
    const std::uint32_t n = accel.all_hits(rays[i], all, 16);
    for (std::uint32_t k = 0; k < n; ++k) ASSERT_LT(all[k].primitive, first_degenerate);
  }
  // Only degenerate triangles: nothing to hit at all.
  const TriangleAccel only(
      build(std::vector<Triangle>(tris.begin() + first_degenerate, tris.end())));
  for (const Ray& ray : rays) {
    HitRecord hit;
    ASSERT_FALSE(only.closest(ray, hit));
    ASSERT_FALSE(only.occluded(ray));
  }
  expect_same_hits(tris, accel, rays);
}

TEST_P(TriangleAccelTest, EmptyAndSingleTriangle) {
  const TriangleAccel empty = build({});
  HitRecord hit;
  EXPECT_FALSE(empty.closest(Ray{vec3(0.0f), vec3(0, 0, 1)}, hit));
  EXPECT_FALSE(empty.occluded(Ray{vec3(0.0f), vec3(0, 0, 1)}));

  const std::vector<Triangle> one{Triangle{vec3(-1, -1, 2), vec3(1, -1, 2), vec3(0, 1, 2), 0}};
  const TriangleAccel single = build(one);
  ASSERT_TRUE(single.closest(Ray{vec3(0.0f), vec3(0, 0, 1)}, hit));
  EXPECT_EQ(hit.t, 2.0f);
  EXPECT_EQ(hit.primitive, 0u);
  EXPECT_FALSE(single.closest(Ray{vec3(0.0f), vec3(0, 0, -1)}, hit));
  EXPECT_FALSE(single.occluded(Ray{vec3(0.0f), vec3(0, 0, 1), 0.0f, 1.5f}));
}

TEST_P(TriangleAccelTest, BatchesMatchSingleRays) {
  const auto tris = accel_test::triangle_soup(300, 10);
  const TriangleAccel accel = build(tris);
  const auto rays = accel_test::test_rays(300, 16, 1.5f);
  std::vector<HitRecord> hits(rays.size());
  std::vector<std::uint8_t> blocked(rays.size());
  accel.closest(rays, hits);
  accel.occluded(rays, blocked);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    HitRecord single;
    const bool hit = accel.closest(rays[i], single);
    EXPECT_EQ(hits[i].valid(), hit);
    if (hit) {
      EXPECT_EQ(hits[i].t, single.t);
    }
    EXPECT_EQ(blocked[i] != 0, hit);
  }
}

TEST_P(TriangleAccelTest, HitsNameTrianglesByTheGivenReferences) {
  const auto tris = accel_test::triangle_soup(200, 17);
  std::vector<std::uint32_t> references(tris.size());
  for (std::uint32_t i = 0; i < references.size(); ++i) references[i] = 0x80000000U | (7 * i + 3);
  AccelBuildOptions options;
  options.kind = GetParam().kind;
  options.max_isa = GetParam().isa;
  options.presplit_budget = GetParam().presplit;
  options.spatial_split_budget = GetParam().sbvh;
  const TriangleAccel accel = TriangleAccel::build(tris, options, references);
  std::size_t hits = 0;
  for (const Ray& ray : accel_test::test_rays(300, 18, 1.5f)) {
    const accel_test::ReferenceHit expected = accel_test::reference_closest(tris, ray);
    HitRecord got;
    ASSERT_EQ(accel.closest(ray, got), expected.hit);
    if (!expected.hit) continue;
    ++hits;
    ASSERT_EQ(got.t, expected.record.t);
    const std::uint32_t index = ((got.primitive & 0x7fffffffU) - 3) / 7;
    ASSERT_LT(index, tris.size());
    ASSERT_EQ(got.primitive, references[index]);
    HitRecord all[4];
    ASSERT_GE(accel.all_hits(ray, all, 4), 1u);
    ASSERT_EQ(all[0].t, got.t);
    ASSERT_NE(all[0].primitive & 0x80000000U, 0u);
  }
  EXPECT_GT(hits, 30u);
}

INSTANTIATE_TEST_SUITE_P(AllStructures, TriangleAccelTest,
                         testing::Values(Variant{AccelKind::kBvh, KernelIsa::kSse2},
                                         Variant{AccelKind::kWide, KernelIsa::kSse2},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx2},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx512},
                                         Variant{AccelKind::kOctree, KernelIsa::kSse2},
                                         Variant{AccelKind::kOctree, KernelIsa::kAvx2},
                                         Variant{AccelKind::kOctree, KernelIsa::kAvx512},
                                         Variant{AccelKind::kBrute, KernelIsa::kSse2},
                                         Variant{AccelKind::kBrute, KernelIsa::kAvx2},
                                         Variant{AccelKind::kBrute, KernelIsa::kAvx512},
                                         Variant{AccelKind::kWide, KernelIsa::kSse2, 1.0f},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx2, 1.0f},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx512, 1.0f},
                                         Variant{AccelKind::kWide, KernelIsa::kSse2, 0.0f, 1.0f},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx2, 0.0f, 1.0f},
                                         Variant{AccelKind::kWide, KernelIsa::kAvx512, 0.0f, 1.0f}),
                         variant_name);

TEST(AccelChooser, BruteForceForFewTrianglesWideBvhOtherwise) {
  EXPECT_EQ(choose_accel_kind(1), AccelKind::kBrute);
  EXPECT_EQ(choose_accel_kind(kBruteForceMaxTriangles), AccelKind::kBrute);
  EXPECT_EQ(choose_accel_kind(kBruteForceMaxTriangles + 1), AccelKind::kWide);
  EXPECT_EQ(choose_accel_kind(10'000'000), AccelKind::kWide);
  const auto tris = accel_test::triangle_soup(200, 3);
  EXPECT_EQ(TriangleAccel::build(tris).stats().kind, AccelKind::kWide);
  EXPECT_EQ(TriangleAccel::build(std::span(tris).first(4)).stats().kind, AccelKind::kBrute);
}

TEST(AccelKindNames, RoundTrip) {
  for (AccelKind kind :
       {AccelKind::kAuto, AccelKind::kBvh, AccelKind::kWide, AccelKind::kOctree, AccelKind::kBrute})
    EXPECT_EQ(parse_accel_kind(accel_kind_name(kind)), kind);
  EXPECT_FALSE(parse_accel_kind("kd-tree").has_value());
}

TEST(KernelIsaNames, RoundTrip) {
  for (KernelIsa isa : {KernelIsa::kSse2, KernelIsa::kAvx2, KernelIsa::kAvx512})
    EXPECT_EQ(parse_kernel_isa(kernel_isa_name(isa)), isa);
  EXPECT_FALSE(parse_kernel_isa("neon").has_value());
}

// Intel's first AVX-512 cores lower their clock for 512-bit work: there the default build
// walks with the AVX2 kernels; everywhere else with the widest set the processor runs.
TEST(KernelIsaChoice, DefaultSkipsAvx512WhereItLowersTheClock) {
  EXPECT_TRUE(avx512_lowers_clock("GenuineIntel", 6, 85));    // Skylake-SP, Cascade Lake
  EXPECT_TRUE(avx512_lowers_clock("GenuineIntel", 6, 87));    // Xeon Phi (Knights Landing)
  EXPECT_FALSE(avx512_lowers_clock("GenuineIntel", 6, 106));  // Ice Lake-SP
  EXPECT_FALSE(avx512_lowers_clock("GenuineIntel", 6, 143));  // Sapphire Rapids
  EXPECT_FALSE(avx512_lowers_clock("AuthenticAMD", 25, 97));  // Zen 4
  EXPECT_FALSE(avx512_lowers_clock("AuthenticAMD", 6, 85));   // the model number is Intel's
  // What the default build then runs: WidestTheProcessorRunsUpToTheCap.
  EXPECT_EQ(AccelBuildOptions{}.max_isa, preferred_kernel_isa());
}

// The widest set the processor runs, never above the cap: a cap the processor lacks falls
// back to the next narrower set it has, and each wider set implies the narrower ones.
TEST(KernelIsaChoice, WidestTheProcessorRunsUpToTheCap) {
  if (!cpu_supports_kernels(KernelIsa::kSse2)) GTEST_SKIP() << "no SIMD kernels on this target";
  const auto tris = accel_test::triangle_soup(64, 5);
  const auto built_isa = [&](KernelIsa cap) {
    AccelBuildOptions options;
    options.kind = AccelKind::kWide;
    options.max_isa = cap;
    return std::string(TriangleAccel::build(tris, options).stats().isa);
  };
  EXPECT_EQ(built_isa(KernelIsa::kSse2), "sse2");
  const bool avx2 = cpu_supports_kernels(KernelIsa::kAvx2);
  const bool avx512 = cpu_supports_kernels(KernelIsa::kAvx512);
  if (avx512) {
    EXPECT_TRUE(avx2);
  }
  EXPECT_EQ(built_isa(KernelIsa::kAvx2), avx2 ? "avx2" : "sse2");
  EXPECT_EQ(built_isa(KernelIsa::kAvx512), avx512 ? "avx512" : (avx2 ? "avx2" : "sse2"));
  EXPECT_EQ(built_isa(AccelBuildOptions{}.max_isa), built_isa(preferred_kernel_isa()));
}

}  // namespace
}  // namespace tessera
