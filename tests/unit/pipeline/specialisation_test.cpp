#include <gtest/gtest.h>

#include <cmath>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

SceneDescription cornell() {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  scene.render.width = 24;
  scene.render.height = 18;
  scene.render.samples_per_pixel = 4;
  scene.render.tile_size = 8;
  return scene;
}

// Diffuse triangles under a sky, no emitters: the sky is the one light (sampled for direct
// light), no specular code.
SceneDescription triangles_under_sky() {
  SceneDescription scene;
  scene.camera.position = {0, 0.5, 3};
  scene.camera.look_at = {0, 0, 0};
  scene.background.color = {0.6, 0.7, 0.9};
  MaterialDesc grey;
  grey.name = "grey";
  scene.materials.push_back(grey);
  TriangleMeshDesc mesh;
  mesh.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 1, 0}};
  mesh.indices = {0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  scene.meshes.push_back(mesh);
  scene.render.width = 24;
  scene.render.height = 18;
  scene.render.samples_per_pixel = 4;
  scene.render.tile_size = 8;
  return scene;
}

void expect_same_image(SceneDescription scene) {
  const auto specialised = PreparedScene::build(scene);
  const auto general = PreparedScene::build(scene, PrepareOptions{.all_features = true});
  ASSERT_NE(&specialised->variant(), &general->variant())
      << "the scene should not need every feature";
  const auto a = render_image(*specialised);
  const auto b = render_image(*general);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "float " << i;
}

TEST(Specialisation, PicksTheSmallestCoveringVariant) {
  const auto box = PreparedScene::build(cornell());
  EXPECT_EQ(box->variant().features.shapes, kShapeSphere | kShapeQuad);
  EXPECT_TRUE(box->variant().features.direct_lighting);
  EXPECT_TRUE(box->variant().features.specular);
  EXPECT_FALSE(box->variant().features.aovs);

  const auto sky = PreparedScene::build(triangles_under_sky());
  EXPECT_EQ(sky->variant().features.shapes, kShapeTriangle);
  EXPECT_TRUE(sky->variant().features.direct_lighting);
  EXPECT_FALSE(sky->variant().features.specular);
  EXPECT_TRUE(sky->variant().features.covers(sky->required_features()));

  // Under a black sky nothing lights the triangles: no shadow rays are compiled in.
  SceneDescription dark = triangles_under_sky();
  dark.background.color = glm::dvec3(0.0);
  const auto unlit = PreparedScene::build(dark);
  EXPECT_FALSE(unlit->variant().features.direct_lighting);
  EXPECT_FALSE(unlit->variant().features.specular);
}

TEST(Specialisation, CornellBoxSameImageAsAllFeatures) {
  expect_same_image(cornell());
}

TEST(Specialisation, TrianglesUnderSkySameImageAsAllFeatures) {
  expect_same_image(triangles_under_sky());
}

TEST(Specialisation, MixedShapesSameImageAsAllFeatures) {
  SceneDescription scene = cornell();
  TriangleMeshDesc tri;
  tri.positions = {{-0.5, 1.5, -1}, {0.5, 1.5, -1}, {0, 2, -1}};
  tri.indices = {0, 1, 2};
  scene.meshes.push_back(tri);
  const auto prepared = PreparedScene::build(scene);
  // Spheres, rectangles and a mesh: the common class, not the one with every shape.
  EXPECT_EQ(prepared->variant().features.shapes, kCommonShapes);
  expect_same_image(scene);
  // A disk beside them needs every shape list.
  DiskDesc disk;
  disk.center = {0, 0.5, -1};
  disk.radius = 0.2;
  scene.disks.push_back(disk);
  const auto with_disk = PreparedScene::build(scene);
  EXPECT_EQ(with_disk->variant().features.shapes, kAllShapes);
  // Every feature is needed here except AOVs, so ask for none and compare with all on.
  expect_same_image(scene);
}

TEST(Specialisation, EveryIntegratorHasAVariantPerShapeClass) {
  for (IntegratorKind kind :
       {IntegratorKind::kPath, IntegratorKind::kNormals, IntegratorKind::kShadow,
        IntegratorKind::kTransparency, IntegratorKind::kAlbedo, IntegratorKind::kDepth,
        IntegratorKind::kPhong}) {
    for (unsigned shapes : kShapeClasses) {
      const RenderVariant& v =
          select_render_variant(kind, PipelineFeatures{shapes, false, false, false});
      EXPECT_EQ(v.integrator, kind);
      EXPECT_EQ(v.features.shapes, shapes) << to_string(kind);
    }
    EXPECT_EQ(all_features_variant(kind).features.shapes, kAllShapes);
  }
}

TEST(Specialisation, AovsAreComputedOnlyWhenAsked) {
  SceneDescription scene = cornell();
  TilePasses passes;
  const TileRect tile{0, 0, 0, 8, 8};
  PreparedScene::build(scene)->render_tile(tile, passes);
  for (const auto& plane : passes.aovs) EXPECT_TRUE(plane.empty());

  scene.render.aovs = kAovAlbedo | kAovDepth | kAovPrimitiveId | kAovNormal;
  const auto with_aovs = PreparedScene::build(scene);
  EXPECT_TRUE(with_aovs->variant().features.aovs);
  with_aovs->render_tile(tile, passes);
  for (std::size_t i = 0; i < passes.aovs.size(); ++i)
    ASSERT_EQ(passes.aovs[i].size(), (scene.render.aovs >> i & 1u) != 0 ? 8u * 8u * 4u : 0u);
  // The beauty pass does not change when AOVs are recorded beside it.
  std::vector<float> beauty_only(8 * 8 * 4);
  scene.render.aovs = 0;
  PreparedScene::build(scene)->render_tile(tile, beauty_only);
  EXPECT_EQ(beauty_only, passes.beauty);
  // The depth and albedo planes equal what the depth and albedo integrators render: the
  // same camera rays (same sample streams), recorded at the first hit. With one sample per
  // pixel, because the depth plane keeps the nearest sample (+inf for a miss) where the
  // preview averages (0 for a miss); R, G and B only: the planes' fourth component is
  // unused, the preview's is its coverage. The image shows the box and, beside it, nothing.
  const TileRect edge{0, 0, 0, 24, 18};  // the whole image
  scene.render.samples_per_pixel = 1;
  scene.render.aovs = kAovAlbedo | kAovDepth;
  PreparedScene::build(scene)->render_tile(edge, passes);
  for (auto [integrator, aov] :
       {std::pair{IntegratorKind::kDepth, 2}, std::pair{IntegratorKind::kAlbedo, 0}}) {
    scene.render.integrator = integrator;
    scene.render.aovs = 0;
    std::vector<float> reference(edge.pixel_count() * 4);
    PreparedScene::build(scene)->render_tile(edge, reference);
    int misses = 0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      if (i % 4 == 3) continue;
      const bool missed = reference[i - i % 4 + 3] == 0.0f;
      misses += missed ? 1 : 0;
      if (aov == 2 && missed)
        EXPECT_TRUE(std::isinf(passes.aovs[aov][i])) << i;
      else
        EXPECT_EQ(reference[i], passes.aovs[aov][i]) << to_string(integrator) << " " << i;
    }
    EXPECT_GT(misses, 0);
    EXPECT_LT(misses, static_cast<int>(edge.pixel_count() * 3));
  }
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

TEST(SceneFeatures, DescribesWhatTheCornellBoxContains) {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  SceneFeatures f = SceneFeatures::of(scene);
  EXPECT_EQ(f.shapes, kShapeSphere | kShapeQuad);
  EXPECT_EQ(f.light_shapes, kShapeQuad);
  EXPECT_TRUE(f.emissive);
  EXPECT_TRUE(f.transmissive);  // the glass sphere
  EXPECT_TRUE(f.specular());
  EXPECT_FALSE(f.depth_of_field);
  EXPECT_EQ(f.aovs, 0u);
  EXPECT_EQ(f.primitive_count, 8u);

  // Without the glass and the mirror, and with the lamp made a plain wall, nothing
  // specular or emissive remains.
  for (auto& m : scene.materials) {
    m.type = MaterialType::kLambertian;
    m.emission = glm::dvec3(0.0);
  }
  f = SceneFeatures::of(scene);
  EXPECT_FALSE(f.emissive);
  EXPECT_FALSE(f.transmissive);
  EXPECT_FALSE(f.specular());
  EXPECT_EQ(f.light_shapes, 0u);
}

}  // namespace
}  // namespace tessera
