// Where a prepared scene's triangles are traced: a few triangles beside other bounded
// shapes join the shape BVH (and its CPU wide form), triangles alone or in large numbers
// keep the SIMD triangle structure; and through the shape BVH a triangle gives the same
// hit, bit for bit, as the SIMD structure does.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tessera/accel/triangle_accel.hpp"
#include "tessera/pipeline/bvh_tracer.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

TriangleMeshDesc octahedron() {
  TriangleMeshDesc mesh;
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return mesh;
}

// `triangles` small triangles in a row along x (a strip of separate triangles).
TriangleMeshDesc strip(std::uint32_t triangles) {
  TriangleMeshDesc mesh;
  for (std::uint32_t i = 0; i < triangles; ++i) {
    const double x = 0.01 * i;
    mesh.positions.push_back({x, -3.0, 0.0});
    mesh.positions.push_back({x + 0.008, -3.0, 0.0});
    mesh.positions.push_back({x, -2.99, 0.0});
    for (std::uint32_t k = 0; k < 3; ++k) mesh.indices.push_back(3 * i + k);
  }
  return mesh;
}

SceneDescription scene_of(std::vector<TriangleMeshDesc> meshes, bool with_sphere) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 5.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  MaterialDesc white;
  white.name = "white";
  scene.materials.push_back(white);
  scene.meshes = std::move(meshes);
  if (with_sphere) scene.spheres.push_back(SphereDesc{.center = {0.0, 3.0, 0.0}, .radius = 0.5});
  scene.render.width = 8;
  scene.render.height = 8;
  return scene;
}

std::uint32_t triangles_in_bvh(const SceneView& view) {
  std::uint32_t count = 0;
  for (std::uint32_t i = 0; i < view.bvh.node_count; ++i) {
    const BvhNode& node = view.bvh.nodes[i];
    if (!node.is_leaf()) continue;
    for (std::uint32_t k = node.offset; k < node.offset + node.count; ++k)
      count += primitive_type(view.bvh.primitives[k]) == PrimitiveType::kTriangle ? 1 : 0;
  }
  return count;
}

TEST(ShapeBvhTriangles, FewTrianglesBesideShapesJoinTheShapeBvh) {
  const auto prepared = PreparedScene::build(scene_of({octahedron()}, true));
  const SceneView view = prepared->view();
  EXPECT_EQ(view.bvh.triangles, nullptr);
  EXPECT_EQ(triangles_in_bvh(view), 8u);
  EXPECT_NE(view.bvh.wide_nodes, nullptr);
}

TEST(ShapeBvhTriangles, TrianglesAloneKeepTheSimdStructure) {
  const auto prepared = PreparedScene::build(scene_of({octahedron()}, false));
  const SceneView view = prepared->view();
  ASSERT_NE(view.bvh.triangles, nullptr);
  EXPECT_EQ(view.bvh.triangles->stats().triangles, 8u);
  EXPECT_EQ(triangles_in_bvh(view), 0u);
}

TEST(ShapeBvhTriangles, ManyTrianglesKeepTheSimdStructure) {
  const auto count = static_cast<std::uint32_t>(kShapeBvhMaxTriangles + 1);
  const auto prepared = PreparedScene::build(scene_of({strip(count)}, true));
  const SceneView view = prepared->view();
  ASSERT_NE(view.bvh.triangles, nullptr);
  EXPECT_EQ(view.bvh.triangles->stats().triangles, count);
  EXPECT_EQ(triangles_in_bvh(view), 0u);
}

TEST(ShapeBvhTriangles, ShapeBvhHitsEqualTheSimdStructureBitForBit) {
  const auto prepared = PreparedScene::build(scene_of({octahedron()}, true));
  const SceneView view = prepared->view();
  ASSERT_EQ(view.bvh.triangles, nullptr);
  // The SIMD structure over the same triangles, named by the same references.
  std::vector<Triangle> triangles(view.triangles, view.triangles + 8);
  std::vector<std::uint32_t> references;
  for (std::uint32_t i = 0; i < 8; ++i)
    references.push_back(make_primitive_ref(PrimitiveType::kTriangle, i));
  const TriangleAccel simd = TriangleAccel::build(triangles, AccelBuildOptions{}, references);
  const BvhTracer tracer(view.bvh, SceneIntersection<kAllShapes>{view});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const vec3 origin(3.0f * u(rng), 3.0f * u(rng), 3.0f);
    const vec3 target(u(rng), u(rng), u(rng));
    const Ray ray{origin, glm::normalize(target - origin)};
    HitRecord from_bvh, from_simd;
    from_simd.t = ray.t_max;
    const bool found = tracer.trace_closest(ray, from_bvh);
    const bool expected = simd.closest(ray, from_simd);
    if (found && primitive_type(from_bvh.primitive) == PrimitiveType::kSphere) continue;
    ASSERT_EQ(found, expected);
    if (!found) continue;
    ++hits;
    EXPECT_EQ(from_bvh.t, from_simd.t);
    EXPECT_EQ(from_bvh.u, from_simd.u);
    EXPECT_EQ(from_bvh.v, from_simd.v);
    EXPECT_EQ(from_bvh.primitive, from_simd.primitive);
    EXPECT_EQ(tracer.occluded(ray), true);
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace tessera
