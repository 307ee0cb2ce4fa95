#include <gtest/gtest.h>

#include <cmath>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

SceneDescription small_cornell(std::uint32_t tile_size) {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  scene.render.width = 40;
  scene.render.height = 30;
  scene.render.samples_per_pixel = 4;
  scene.render.tile_size = tile_size;
  return scene;
}

TEST(RenderDeterminism, TileSizeDoesNotChangeTheImage) {
  const auto a = render_image(*PreparedScene::build(small_cornell(8)));
  const auto b = render_image(*PreparedScene::build(small_cornell(13)));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "at float " << i;
}

TEST(RenderDeterminism, TileOrderDoesNotChangeTheImage) {
  const auto scene = PreparedScene::build(small_cornell(16));
  const auto tiles = make_tiles(40, 30, 16);
  std::vector<std::vector<float>> forward(tiles.size()), backward(tiles.size());
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    forward[i].resize(tiles[i].pixel_count() * 4);
    scene->render_tile(tiles[i], forward[i]);
  }
  for (std::size_t i = tiles.size(); i-- > 0;) {
    backward[i].resize(tiles[i].pixel_count() * 4);
    scene->render_tile(tiles[i], backward[i]);
  }
  EXPECT_EQ(forward, backward);
}

TEST(RenderDeterminism, SeedChangesTheNoise) {
  SceneDescription a = small_cornell(16), b = small_cornell(16);
  b.render.seed = a.render.seed + 1;
  EXPECT_NE(render_image(*PreparedScene::build(a)), render_image(*PreparedScene::build(b)));
}

TEST(RenderImage, CornellIsFiniteLitAndColoured) {
  SceneDescription scene = small_cornell(16);
  scene.render.samples_per_pixel = 16;
  const auto image = render_image(*PreparedScene::build(scene));
  double red_wall = 0, green_wall = 0;
  for (std::size_t i = 0; i < image.size(); ++i) ASSERT_TRUE(std::isfinite(image[i]));
  // Left third of the middle row is the red wall, right third the green one.
  const std::uint32_t row = 15;
  for (std::uint32_t x = 0; x < 5; ++x) {
    const float* left = &image[(row * 40 + x + 2) * 4];
    const float* right = &image[(row * 40 + 37 - x) * 4];
    red_wall += left[0] - left[1];
    green_wall += right[1] - right[0];
  }
  EXPECT_GT(red_wall, 0.1);
  EXPECT_GT(green_wall, 0.1);
}

TEST(RenderImage, LambertianPlaneUnderUniformSkyMatchesAnalyticRadiance) {
  // Camera looks straight down on an infinite-ish diffuse plane under a uniform sky of
  // radiance 1: the reflected radiance is exactly the albedo (the plane sees the whole
  // upper hemisphere and nothing else), so each pixel converges to albedo.
  SceneDescription scene;
  scene.camera.position = {0, 1, 0};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, -1};
  scene.camera.fov_degrees = 20;
  scene.background.color = glm::dvec3(1.0);
  MaterialDesc grey;
  grey.name = "grey";
  grey.albedo = glm::dvec3(0.5);
  scene.materials.push_back(grey);
  scene.quads.push_back(
      QuadDesc{.corner = {-1e3, 0, -1e3}, .u = {2e3, 0, 0}, .v = {0, 0, 2e3}, .material = 0});
  scene.render.width = 8;
  scene.render.height = 8;
  scene.render.samples_per_pixel = 4096;
  scene.render.max_depth = 2;
  scene.render.tile_size = 8;
  const auto image = render_image(*PreparedScene::build(scene));
  double mean = 0;
  for (std::size_t i = 0; i < image.size(); i += 4) mean += image[i];
  mean /= 64.0;
  EXPECT_NEAR(mean, 0.5, 0.01);
}

}  // namespace
}  // namespace tessera
