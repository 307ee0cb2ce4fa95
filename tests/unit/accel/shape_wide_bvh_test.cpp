// The CPU's eight-wide walk of the shape BVH (accel/shape_wide_bvh.hpp) against brute
// force and against the binary walk it replaces: the same closest hit (distance and
// primitive) and the same any-hit answer on random scenes of overlapping spheres and
// quads, on axis-aligned rays along the flat boxes of axis-aligned quads, with a bound
// already set by an earlier hit, and on the degenerate trees (empty, one primitive).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "accel_test_scenes.hpp"
#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/accel/shape_wide_bvh.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"

namespace tessera {
namespace {

// Spheres and quads behind one reference space: references below the sphere count name
// spheres, the others quads.
struct ShapeScene {
  std::vector<Sphere> spheres;
  std::vector<Quad> quads;
  Bvh bvh;
  WideBvh wide;

  std::uint32_t size() const { return static_cast<std::uint32_t>(spheres.size() + quads.size()); }

  bool intersect(std::uint32_t ref, const Ray& ray, float t_max, HitRecord& hit) const {
    const auto sphere_count = static_cast<std::uint32_t>(spheres.size());
    if (ref < sphere_count) return tessera::intersect(spheres[ref], ray, t_max, hit, ref);
    return tessera::intersect(quads[ref - sphere_count], ray, t_max, hit, ref);
  }

  void build(std::uint32_t max_leaf_size) {
    std::vector<Aabb> boxes;
    std::vector<std::uint32_t> refs;
    for (const Sphere& s : spheres) boxes.push_back(bounds(s));
    for (const Quad& q : quads) boxes.push_back(bounds(q));
    for (std::uint32_t i = 0; i < size(); ++i) refs.push_back(i);
    BvhBuildOptions options;
    options.max_leaf_size = max_leaf_size;
    bvh = build_bvh(boxes, refs, options);
    wide = collapse_shape_bvh(bvh);
  }

  BvhView binary_view() const { return bvh.view(); }
  BvhView wide_view() const {
    BvhView view = bvh.view();
    view.wide_nodes = wide.nodes.empty() ? nullptr : wide.nodes.data();
    return view;
  }
};

// Overlapping spheres of mixed sizes and quads of random orientation in [-2, 2]^3, and the
// walls of a box around them (axis-aligned quads spanning the scene, whose boxes are flat).
ShapeScene random_scene(std::uint32_t spheres, std::uint32_t quads, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> radius(0.05f, 0.8f);
  std::uniform_real_distribution<float> side(0.1f, 1.5f);
  ShapeScene scene;
  for (std::uint32_t i = 0; i < spheres; ++i)
    scene.spheres.push_back(Sphere{accel_test::random_point(rng, -2.0f, 2.0f), radius(rng), 0});
  for (std::uint32_t i = 0; i < quads; ++i)
    scene.quads.push_back(Quad::make(accel_test::random_point(rng, -2.0f, 2.0f),
                                     side(rng) * accel_test::random_direction(rng),
                                     side(rng) * accel_test::random_direction(rng), 0));
  const vec3 c(-3.0f);
  scene.quads.push_back(Quad::make(c, vec3(6, 0, 0), vec3(0, 0, 6), 0));  // floor
  scene.quads.push_back(Quad::make(c, vec3(6, 0, 0), vec3(0, 6, 0), 0));  // back
  scene.quads.push_back(Quad::make(c, vec3(0, 0, 6), vec3(0, 6, 0), 0));  // left
  scene.quads.push_back(Quad::make(vec3(3, -3, -3), vec3(0, 0, 6), vec3(0, 6, 0), 0));
  return scene;
}

HitRecord brute_closest(const ShapeScene& scene, const Ray& ray, float t_max) {
  HitRecord best;
  best.t = t_max;
  for (std::uint32_t ref = 0; ref < scene.size(); ++ref) scene.intersect(ref, ray, best.t, best);
  return best;
}

bool brute_any(const ShapeScene& scene, const Ray& ray) {
  for (std::uint32_t ref = 0; ref < scene.size(); ++ref) {
    HitRecord hit;
    if (scene.intersect(ref, ray, ray.t_max, hit)) return true;
  }
  return false;
}

template <bool kAnyHit>
bool walk(const ShapeScene& scene, const BvhView& view, const Ray& ray, HitRecord& hit) {
  const auto intersect = [&](std::uint32_t ref, const Ray& r, float t_max, HitRecord& h) {
    return scene.intersect(ref, r, t_max, h);
  };
  if (view.wide_nodes != nullptr) return traverse_shape_wide<kAnyHit>(view, ray, hit, intersect);
  return traverse_bvh<kAnyHit>(view, ray, hit, intersect);
}

// Closest hit of the wide walk equals brute force and the binary walk (t and primitive);
// its any-hit answer equals brute force's.
void expect_agreement(const ShapeScene& scene, const Ray& ray, float bound = kInfinity) {
  ASSERT_FALSE(scene.wide.nodes.empty());
  const HitRecord expected = brute_closest(scene, ray, bound);
  HitRecord wide;
  wide.t = bound;
  const bool wide_found = walk<false>(scene, scene.wide_view(), ray, wide);
  HitRecord binary;
  binary.t = bound;
  const bool binary_found = walk<false>(scene, scene.binary_view(), ray, binary);
  ASSERT_EQ(wide_found, expected.valid());
  ASSERT_EQ(binary_found, expected.valid());
  if (expected.valid()) {
    EXPECT_EQ(wide.t, expected.t);
    EXPECT_EQ(wide.primitive, expected.primitive);
    EXPECT_EQ(binary.t, expected.t);
  }
  HitRecord any;
  any.t = ray.t_max;
  EXPECT_EQ(walk<true>(scene, scene.wide_view(), ray, any), brute_any(scene, ray));
}

TEST(ShapeWideBvh, ClosestAndAnyHitMatchBruteForceOnRandomScenes) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    for (std::uint32_t leaf : {1u, 4u}) {
      ShapeScene scene = random_scene(60, 40, seed);
      scene.build(leaf);
      std::mt19937 rng(seed + 100);
      std::uniform_real_distribution<float> length(0.2f, 6.0f);
      int hits = 0;
      for (int i = 0; i < 3000; ++i) {
        Ray ray{accel_test::random_point(rng, -2.5f, 2.5f), accel_test::random_direction(rng)};
        if (i % 2 == 1) ray.t_max = length(rng);  // shadow-ray-like segments
        expect_agreement(scene, ray);
        hits += brute_closest(scene, ray, ray.t_max).valid() ? 1 : 0;
      }
      EXPECT_GT(hits, 1000);  // the rays do meet the shapes
    }
  }
}

TEST(ShapeWideBvh, ManyShapesMakeADeepTreeThatStillAgrees) {
  ShapeScene scene = random_scene(3000, 2000, 7);
  for (Sphere& s : scene.spheres) s.radius *= 0.1f;
  scene.build(1);
  ASSERT_GT(scene.wide.nodes.size(), 100u);
  std::mt19937 rng(8);
  for (int i = 0; i < 2000; ++i)
    expect_agreement(
        scene, Ray{accel_test::random_point(rng, -2.5f, 2.5f), accel_test::random_direction(rng)});
}

TEST(ShapeWideBvh, AxisAlignedRaysAlongFlatBoxes) {
  // Rays parallel to the walls (zero direction components: infinite reciprocals), some
  // starting exactly in a wall's plane (0 * inf = NaN slab distances), and rays that hit
  // the walls head-on through their flat boxes.
  ShapeScene scene = random_scene(10, 10, 4);
  scene.build(1);
  const vec3 axes[6] = {vec3(1, 0, 0),  vec3(-1, 0, 0), vec3(0, 1, 0),
                        vec3(0, -1, 0), vec3(0, 0, 1),  vec3(0, 0, -1)};
  std::mt19937 rng(5);
  for (int i = 0; i < 400; ++i) {
    vec3 origin = accel_test::random_point(rng, -2.9f, 2.9f);
    if (i % 4 == 0) origin.y = -3.0f;  // in the floor's plane
    if (i % 4 == 1) origin.z = -3.0f;  // in the back wall's plane
    for (const vec3& d : axes) expect_agreement(scene, Ray{origin, d});
    expect_agreement(scene, Ray{origin, vec3(-0.0f, 1.0f, 0.0f)});
  }
}

TEST(ShapeWideBvh, AnEarlierHitBoundsTheWalk) {
  // As when the triangle structure found a hit first: only nearer shapes may replace it.
  ShapeScene scene = random_scene(40, 30, 9);
  scene.build(1);
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> bound(0.1f, 4.0f);
  for (int i = 0; i < 2000; ++i)
    expect_agreement(
        scene, Ray{accel_test::random_point(rng, -2.5f, 2.5f), accel_test::random_direction(rng)},
        bound(rng));
}

TEST(ShapeWideBvh, OneLeafTreeAndSmallAndEmptyTrees) {
  // A binary tree that is one leaf (four shapes in it) still gets a wide root.
  ShapeScene one_leaf;
  for (int i = 0; i < 4; ++i)
    one_leaf.spheres.push_back(Sphere{vec3(0.1f * static_cast<float>(i), 0, 5), 1.0f, 0});
  one_leaf.build(4);
  ASSERT_EQ(one_leaf.bvh.nodes.size(), 1u);
  ASSERT_EQ(one_leaf.wide.nodes.size(), 1u);
  expect_agreement(one_leaf, Ray{vec3(0.0f), vec3(0, 0, 1)});
  expect_agreement(one_leaf, Ray{vec3(0.0f), vec3(0, 0, -1)});
  expect_agreement(one_leaf, Ray{vec3(0.0f), vec3(0, 0, 1), 0.0f, 3.0f});  // ends before it

  // Fewer shapes than kShapeWideMinPrimitives keep the binary walk.
  ShapeScene two;
  two.spheres.push_back(Sphere{vec3(0, 0, 5), 1.0f, 0});
  two.spheres.push_back(Sphere{vec3(0, 0, 9), 1.0f, 0});
  two.build(1);
  EXPECT_FALSE(two.bvh.nodes.empty());
  EXPECT_TRUE(two.wide.nodes.empty());

  ShapeScene none;
  none.build(1);
  EXPECT_TRUE(none.bvh.nodes.empty());
  EXPECT_TRUE(none.wide.nodes.empty());
}

TEST(ShapeWideBvh, ClosestHitVisitsNearChildrenFirst) {
  // A row of spheres along the ray: ordered traversal tests the first one and drops the
  // boxes behind it, so far fewer tests than primitives are made.
  ShapeScene row;
  for (int i = 0; i < 64; ++i)
    row.spheres.push_back(Sphere{vec3(0, 0, 5.0f * static_cast<float>(i + 1)), 1.0f, 0});
  row.build(1);
  int tests = 0;
  HitRecord hit;
  const bool found =
      traverse_shape_wide<false>(row.wide_view(), Ray{vec3(0.0f), vec3(0, 0, 1)}, hit,
                                 [&](std::uint32_t ref, const Ray& r, float t_max, HitRecord& h) {
                                   ++tests;
                                   return row.intersect(ref, r, t_max, h);
                                 });
  ASSERT_TRUE(found);
  EXPECT_EQ(hit.primitive, 0u);
  EXPECT_FLOAT_EQ(hit.t, 4.0f);
  EXPECT_LE(tests, 4);
}

}  // namespace
}  // namespace tessera
