// Meshes placed more than once share one object-space structure (two-level instancing).
// Each image is compared with the same scene rendered with every placement baked into
// world triangles (PrepareOptions::instancing = false), an independent path through the
// renderer: world triangles in one TriangleAccel, surfaces without transforms.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_materials.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kWidth = 48;
constexpr std::uint32_t kHeight = 36;

// An octahedron with smooth per-vertex normals and uvs (so shading attributes are used).
TriangleMeshDesc octahedron() {
  TriangleMeshDesc mesh;
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  for (const auto& p : mesh.positions) {
    mesh.normals.push_back(glm::normalize(p + glm::dvec3(0.1, 0.2, 0.0)));
    mesh.uvs.push_back(glm::dvec2(0.5 + 0.5 * p.x, 0.5 + 0.5 * p.y));
  }
  return mesh;
}

// One mesh placed three times: translated, rotated with non-uniform scale, rotated with
// uniform scale; a floor and a quad light for the path and shadow views.
SceneDescription three_placements(IntegratorKind integrator, double transmission = 0.0) {
  SceneDescription scene;
  scene.camera.position = {0.5, 2.5, 7.0};
  scene.camera.look_at = {0.0, 0.3, 0.0};
  scene.camera.fov_degrees = 50.0;
  MaterialDesc white;
  white.name = "white";
  white.transmission = transmission;
  scene.materials.push_back(white);
  scene.materials.push_back(test::light_material("light", dvec3(4.0)));
  MaterialDesc red;
  red.name = "red";
  red.albedo = {0.8, 0.2, 0.1};
  red.transmission = transmission;
  scene.materials.push_back(red);

  TriangleMeshDesc base = octahedron();
  TransformDesc a;
  a.translate = {-2.0, 0.5, 0.0};
  TransformDesc b;
  b.translate = {0.3, 0.8, -0.5};
  b.rotate_axis = {0.3, 1.0, 0.2};
  b.rotate_degrees = 35.0;
  b.scale = {1.4, 0.6, 0.9};
  TransformDesc c;
  c.translate = {2.1, 0.6, 0.8};
  c.rotate_axis = {1.0, 0.0, 0.0};
  c.rotate_degrees = -50.0;
  c.scale = {0.7, 0.7, 0.7};
  std::uint32_t index = 0;
  for (const TransformDesc& t : {a, b, c}) {
    TriangleMeshDesc placed = base;
    placed.transform = t;
    placed.material = index == 1 ? 2 : 0;  // placements keep their own material
    placed.source_index = index++;
    scene.meshes.push_back(placed);
  }
  QuadDesc floor;
  floor.corner = {-5.0, -0.5, 4.0};
  floor.u = {10.0, 0.0, 0.0};
  floor.v = {0.0, 0.0, -10.0};
  scene.quads.push_back(floor);
  QuadDesc lamp;
  lamp.corner = {-1.0, 4.0, -1.0};
  lamp.u = {2.0, 0.0, 0.0};
  lamp.v = {0.0, 0.0, 2.0};
  lamp.material = 1;
  scene.quads.push_back(lamp);

  scene.render.width = kWidth;
  scene.render.height = kHeight;
  scene.render.samples_per_pixel = integrator == IntegratorKind::kPath ? 4 : 1;
  scene.render.tile_size = 16;
  scene.render.integrator = integrator;
  scene.render.seed = 7;
  return scene;
}

struct Renders {
  std::vector<float> instanced, baked;
};

Renders render_both(const SceneDescription& scene) {
  PrepareOptions sharing;
  sharing.instancing = true;
  PrepareOptions baking;
  baking.instancing = false;
  const auto instanced = PreparedScene::build(scene, sharing);
  const auto baked = PreparedScene::build(scene, baking);
  EXPECT_EQ(instanced->shared_mesh_placements(), 3u);
  EXPECT_EQ(instanced->shared_mesh_geometries(), 1u);
  EXPECT_EQ(baked->shared_mesh_placements(), 0u);
  return Renders{render_image(*instanced), render_image(*baked)};
}

// Pixels (RGB) equal within `tolerance`; a few silhouette pixels may differ, because a
// ray grazing an edge rounds differently in object and world space.
void expect_images_match(const Renders& r, float tolerance, int allowed_pixels) {
  ASSERT_EQ(r.instanced.size(), r.baked.size());
  int differing = 0, nonzero = 0;
  for (std::size_t p = 0; p < r.baked.size(); p += 4) {
    bool same = true;
    for (int c = 0; c < 3; ++c) {
      const float a = r.instanced[p + c], b = r.baked[p + c];
      if (b != 0.0f) ++nonzero;
      if (!(std::fabs(a - b) <= tolerance * (1.0f + std::fabs(b)))) same = false;
    }
    if (!same && ++differing > allowed_pixels)
      ADD_FAILURE() << "pixel " << p / 4 << ": instanced (" << r.instanced[p] << ", "
                    << r.instanced[p + 1] << ", " << r.instanced[p + 2] << "), baked ("
                    << r.baked[p] << ", " << r.baked[p + 1] << ", " << r.baked[p + 2] << ")";
  }
  EXPECT_GT(nonzero, static_cast<int>(kWidth * kHeight) / 4);
}

TEST(InstancingRender, DepthMatchesBaked) {
  expect_images_match(render_both(three_placements(IntegratorKind::kDepth)), 1e-4f, 3);
}

TEST(InstancingRender, NormalsMatchBaked) {
  expect_images_match(render_both(three_placements(IntegratorKind::kNormals)), 1e-4f, 3);
}

TEST(InstancingRender, PathWithFixedSeedMatchesBaked) {
  expect_images_match(render_both(three_placements(IntegratorKind::kPath)), 2e-3f, 8);
}

TEST(InstancingRender, ShadowRaysAreOccludedByInstances) {
  expect_images_match(render_both(three_placements(IntegratorKind::kShadow)), 1e-3f, 6);
}

TEST(InstancingRender, TransparencyCompositesEveryInstancedCrossing) {
  expect_images_match(render_both(three_placements(IntegratorKind::kTransparency, 0.6)), 1e-3f, 6);
}

TEST(InstancingRender, SharedGeometryStoresLessThanBaked) {
  SceneDescription scene = three_placements(IntegratorKind::kDepth);
  // 40 placements of the 8-triangle mesh: baked, 320 world triangles with attributes and
  // their structure; shared, 8 triangles and one structure plus 40 placements.
  const TriangleMeshDesc first = scene.meshes.front();
  for (int i = 0; i < 37; ++i) {
    TriangleMeshDesc extra = first;
    extra.transform->translate.z -= 2.5 * (i + 1);
    scene.meshes.push_back(extra);
  }
  PrepareOptions baking;
  baking.instancing = false;
  const auto instanced = PreparedScene::build(scene);
  const auto baked = PreparedScene::build(scene, baking);
  EXPECT_EQ(instanced->shared_mesh_placements(), 40u);
  EXPECT_LT(instanced->triangle_bytes(), baked->triangle_bytes());
}

// Emitting and hidden meshes stay baked (lights are sampled per world triangle); a mesh
// placed once is baked as before.
TEST(InstancingRender, EmittersHiddenAndSinglePlacementsAreBaked) {
  SceneDescription scene = three_placements(IntegratorKind::kDepth);
  scene.meshes[0].material = 1;  // emitting
  scene.meshes[1].visible = false;
  const auto prepared = PreparedScene::build(scene);
  EXPECT_EQ(prepared->shared_mesh_placements(), 0u);
  scene = three_placements(IntegratorKind::kDepth);
  scene.meshes[2].positions[0].x += 0.01;  // a different geometry now
  const auto two = PreparedScene::build(scene);
  EXPECT_EQ(two->shared_mesh_placements(), 2u);
  EXPECT_EQ(two->shared_mesh_geometries(), 1u);
}

}  // namespace
}  // namespace tessera
