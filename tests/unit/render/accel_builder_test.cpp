// render.accel_builder (its YAML: scene/camera_fields_test.cpp): the scene's choice of triangle
// structure reaches every structure the renderer builds (the world one and each shared geometry's),
// and changes speed and memory but not the image.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>

#include "scene_materials.hpp"
#include "tessera/render/accel_builder.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

TEST(AccelBuilder, EachChoiceGivesItsBuildOptions) {
  for (const char* automatic : {"", "auto"}) {
    const AccelBuildOptions options = accel_build_options(automatic);
    EXPECT_FALSE(options.presplit_budget.has_value()) << automatic;
    EXPECT_FALSE(options.spatial_split_budget.has_value()) << automatic;
  }
  const AccelBuildOptions spatial = accel_build_options("spatial");
  EXPECT_EQ(spatial.presplit_budget, 0.0f);
  EXPECT_EQ(spatial.spatial_split_budget, kAutoSpatialSplitBudget);
  const AccelBuildOptions binned = accel_build_options("binned");
  EXPECT_EQ(binned.presplit_budget, 0.0f);
  EXPECT_EQ(binned.spatial_split_budget, 0.0f);
  try {
    accel_build_options("fast");
    ADD_FAILURE() << "no error for an unknown builder";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("render.accel_builder"), std::string::npos) << e.what();
  }
}

// 6,000 long thin slanted triangles (strands 1-2 mm wide and up to 1.7 long) in a unit
// box, above a floor and under a lamp: their boxes fit them so poorly that the automatic
// choice pre-splits them.
TriangleMeshDesc strands(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TriangleMeshDesc mesh;
  for (std::uint32_t i = 0; i < 6000; ++i) {
    const glm::dvec3 a(unit(rng), unit(rng), unit(rng));
    const glm::dvec3 b(unit(rng), unit(rng), unit(rng));
    const glm::dvec3 side = 0.001 * glm::dvec3(1.0 + unit(rng), unit(rng), unit(rng));
    mesh.positions.push_back(a - 0.5);
    mesh.positions.push_back(b - 0.5);
    mesh.positions.push_back(0.5 * (a + b) + side - 0.5);
    mesh.indices.push_back(3 * i);
    mesh.indices.push_back(3 * i + 1);
    mesh.indices.push_back(3 * i + 2);
  }
  return mesh;
}

SceneDescription strand_scene(const std::string& builder, bool two_placements) {
  SceneDescription scene;
  scene.camera.position = {0.3, 0.6, 2.6};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 45.0;
  scene.materials.push_back(test::lambertian_material("white"));
  scene.materials.push_back(test::light_material("light", glm::dvec3(4.0)));
  TriangleMeshDesc mesh = strands(17);
  if (two_placements) {
    for (std::uint32_t i = 0; i < 2; ++i) {
      TriangleMeshDesc placed = mesh;
      TransformDesc t;
      t.translate = {i == 0 ? -0.35 : 0.35, 0.0, 0.0};
      t.scale = {0.6, 0.6, 0.6};
      placed.transform = t;
      placed.source_index = i;
      scene.meshes.push_back(placed);
    }
  } else {
    scene.meshes.push_back(mesh);
  }
  QuadDesc floor;
  floor.corner = {-3.0, -0.6, 3.0};
  floor.u = {6.0, 0.0, 0.0};
  floor.v = {0.0, 0.0, -6.0};
  scene.quads.push_back(floor);
  QuadDesc lamp;
  lamp.corner = {-0.5, 2.0, -0.5};
  lamp.u = {1.0, 0.0, 0.0};
  lamp.v = {0.0, 0.0, 1.0};
  lamp.material = 1;
  scene.quads.push_back(lamp);
  scene.render.width = 40;
  scene.render.height = 30;
  scene.render.samples_per_pixel = 4;
  scene.render.tile_size = 16;
  scene.render.seed = 3;
  scene.render.accel_builder = builder;
  return scene;
}

void expect_builder(const AccelStats& stats, const std::string& builder) {
  ASSERT_EQ(stats.kind, AccelKind::kWide) << builder;
  if (builder == "auto") {
    EXPECT_GT(stats.fill_ratio, kAutoPresplitMinFillRatio);
    EXPECT_GT(stats.presplit_budget, 0.0f);
    EXPECT_TRUE(stats.presplit_chosen);
  } else if (builder == "spatial") {
    EXPECT_EQ(stats.presplit_budget, 0.0f);
    EXPECT_EQ(stats.spatial_split_budget, kAutoSpatialSplitBudget);
    EXPECT_FALSE(stats.spatial_split_chosen);
    EXPECT_GT(stats.leaf_references, stats.triangles);
  } else {
    EXPECT_EQ(stats.presplit_budget, 0.0f);
    EXPECT_EQ(stats.spatial_split_budget, 0.0f);
    EXPECT_EQ(stats.leaf_references, stats.triangles);
  }
}

// Every builder finds the same closest hits, so the images are equal bit for bit: no ray of
// this scene meets two triangles at one distance (the strands are random, none shares an
// edge), where the structure's order could pick either.
TEST(AccelBuilder, TheSceneGetsTheStructureItAsksForAndTheSameImage) {
  for (const bool shared : {false, true}) {
    const auto automatic = PreparedScene::build(strand_scene("auto", shared));
    const std::vector<float> expected = render_image(*automatic);
    SceneDescription empty = strand_scene("auto", shared);
    empty.meshes.clear();
    ASSERT_NE(render_image(*PreparedScene::build(empty)), expected) << "no strand in view";
    for (const std::string builder : {"auto", "spatial", "binned"}) {
      SCOPED_TRACE(builder + (shared ? ", two placements" : ", baked"));
      const auto scene = PreparedScene::build(strand_scene(builder, shared));
      if (shared) {
        ASSERT_EQ(scene->shared_mesh_geometries(), 1u);
        expect_builder(scene->shared_mesh_accel_stats(0), builder);
      } else {
        ASSERT_EQ(scene->shared_mesh_geometries(), 0u);
        expect_builder(scene->triangle_accel_stats(), builder);
      }
      EXPECT_EQ(render_image(*scene), expected);
    }
  }
}

}  // namespace
}  // namespace tessera
