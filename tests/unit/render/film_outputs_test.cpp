// What the film writes beside the colour: alpha from coverage, misses as Z = +inf, normal 0
// and ID 0, primitive IDs that never collide and survive the EXR exactly, the transparent
// background, and the firefly clamp's bound.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "tessera/image/exr.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/film.hpp"
#include "tessera/render/output_channels.hpp"
#include "tessera/render/path_tracer.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

SceneDescription load(const std::string& yaml) {
  return load_scene_yaml(yaml, "film_outputs_test", ".").scene;
}

TilePasses render_whole(const SceneDescription& scene) {
  const auto prepared = PreparedScene::build(scene);
  TilePasses passes;
  prepared->render_tile(TileRect{0, 0, 0, scene.render.width, scene.render.height}, passes);
  return passes;
}

// An orthographic camera 8 units tall over 16 pixels (2 px per unit) looking at a unit-albedo
// square whose right edge, x = 0.25, runs through the middle of column 8 (x in [0, 0.5)).
const char* kHalfCoveredScene = R"(
camera: { position: [0, 0, 5], look_at: [0, 0, 0], projection: orthographic, ortho_height: 8 }
environment: { type: constant, color: [0.2, 0.4, 0.6] }
materials:
  - { name: white, type: lambertian, albedo: 0.5 }
  - { name: lamp, type: light, emission: 1 }
geometry:
  - { type: rectangle, material: white, corner: [-3.75, -3, 0], u: [4, 0, 0], v: [0, 6, 0] }
  - { type: sphere, material: lamp, center: [0, 0, 10], radius: 1, visible: false }
render: { width: 16, height: 16, spp: 64, tile_size: 16, aovs: [albedo, normal, depth, primitive_id] }
)";

TEST(FilmOutputs, MissesAreTransparentInfinitelyFarWithoutNormalOrId) {
  const SceneDescription scene = load(kHalfCoveredScene);
  const TilePasses passes = render_whole(scene);
  const auto at = [&](std::uint32_t x, std::uint32_t y) { return 4 * (y * 16 + x); };
  const std::size_t miss = at(15, 0), hit = at(4, 8), half = at(8, 8);
  // A miss: alpha 0, Z = +inf, normal 0, albedo 0, ID 0; the background still drawn.
  EXPECT_EQ(passes.beauty[miss + 3], 0.0f);
  EXPECT_NEAR(passes.beauty[miss + 0], 0.2f, 1e-6f);
  EXPECT_TRUE(std::isinf(passes.aovs[2][miss]) && passes.aovs[2][miss] > 0.0f);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(passes.aovs[1][miss + c], 0.0f);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(passes.aovs[0][miss + c], 0.0f);
  EXPECT_EQ(float_as_id(passes.aovs[3][miss]), 0u);
  // A covered pixel: alpha 1, the plane's distance, its normal, an ID.
  EXPECT_FLOAT_EQ(passes.beauty[hit + 3], 1.0f);
  EXPECT_NEAR(passes.aovs[2][hit], 5.0f, 1e-4f);
  EXPECT_NEAR(passes.aovs[1][hit + 2], 1.0f, 1e-5f);
  EXPECT_NE(float_as_id(passes.aovs[3][hit]), 0u);
  // The pixel the edge halves: alpha is the covered share (64 stratified samples), Z the
  // nearest surface (never an average with +inf).
  EXPECT_NEAR(passes.beauty[half + 3], 0.5f, 0.02f);
  EXPECT_NEAR(passes.aovs[2][half], 5.0f, 1e-4f);
}

TEST(FilmOutputs, TransparentBackgroundLeavesMissesEmptyButStillLightsTheScene) {
  SceneDescription scene = load(kHalfCoveredScene);
  const TilePasses drawn = render_whole(scene);
  scene.render.transparent_background = true;
  const TilePasses transparent = render_whole(scene);
  const std::size_t miss = 4 * 15, hit = 4 * (8 * 16 + 4), half = 4 * (8 * 16 + 8);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(transparent.beauty[miss + c], 0.0f);
  // Covered pixels are unchanged: the background lights them the same.
  for (int c = 0; c < 4; ++c) EXPECT_EQ(transparent.beauty[hit + c], drawn.beauty[hit + c]);
  EXPECT_GT(transparent.beauty[hit], 0.0f);
  // The half-covered pixel loses exactly the background its missing samples added.
  EXPECT_NEAR(transparent.beauty[half + 0],
              drawn.beauty[half + 0] - 0.2f * (1.0f - drawn.beauty[half + 3]), 1e-5f);
}

// The six rectangles of the Cornell box (and its two spheres) have six distinct IDs through
// an EXR round trip: each rectangle's centre, projected by the camera matrices, reads a
// different ID. As floats they all rounded to 134217728 (2^27).
TEST(FilmOutputs, CornellRectanglesHaveDistinctIdsThroughTheExr) {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  scene.render.width = 96;
  scene.render.height = 72;
  scene.render.samples_per_pixel = 1;
  scene.render.aovs = kAovPrimitiveId;
  const TilePasses passes = render_whole(scene);
  const std::vector<float> interleaved = interleave_passes(passes, kAovPrimitiveId);
  const std::vector<std::string> channels = output_channels(kAovPrimitiveId);
  const ChannelImage decoded = select_channels(
      decode_exr_channels(encode_exr(interleaved, 96, 72, channels, 0, 0)), channels);
  const CameraMatrices m = camera_matrices(scene.camera, 96, 72);
  std::set<std::uint32_t> ids;
  for (const QuadDesc& quad : scene.quads) {
    // A point a little inside the rectangle from its centre, towards the camera, so the
    // light (just below the ceiling) does not hide the ceiling's centre.
    glm::dvec3 centre = quad.corner + 0.5 * quad.u + 0.5 * quad.v;
    if (centre.y > 2.0 && quad.u.x > 1.0) centre.z += 1.0;  // the ceiling
    const glm::dvec4 ndc = m.world_to_ndc * glm::dvec4(centre, 1.0);
    const int px = static_cast<int>(ndc.x / ndc.w * 96);
    const int py = static_cast<int>(ndc.y / ndc.w * 72);
    ASSERT_TRUE(px >= 0 && px < 96 && py >= 0 && py < 72);
    const std::uint32_t id =
        float_as_id(decoded.pixels[(static_cast<std::size_t>(py) * 96 + px) * 5 + 4]);
    EXPECT_NE(id, 0u);
    EXPECT_EQ(id, float_as_id(interleaved[static_cast<std::size_t>(py) * 96 * 5 + px * 5 + 4]));
    ids.insert(id);
  }
  EXPECT_EQ(ids.size(), scene.quads.size());
}

TEST(FilmOutputs, ClampScalesOnlyContributionsAboveTheLimitKeepingHue) {
  EXPECT_EQ(clamp_indirect(vec3(4.0f, 2.0f, 1.0f), 0.0f, true), vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(clamp_indirect(vec3(4.0f, 2.0f, 1.0f), 1.0f, false), vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(clamp_indirect(vec3(0.5f, 0.2f, 0.1f), 1.0f, true), vec3(0.5f, 0.2f, 0.1f));
  const vec3 clamped = clamp_indirect(vec3(4.0f, 2.0f, 1.0f), 1.0f, true);
  EXPECT_FLOAT_EQ(clamped.x, 1.0f);
  EXPECT_FLOAT_EQ(clamped.y, 0.5f);
  EXPECT_FLOAT_EQ(clamped.z, 0.25f);
}

// With one sample per pixel each pixel is one sample. Next-event estimation only and
// max_depth 3 give a sample exactly two light contributions: the first surface's direct
// light (never clamped) and the second surface's, which is indirect. The direct part is
// the whole sample at max_depth 2 (the same random numbers), so the clamped render minus
// that one is each sample's indirect light: never above the clamp, while unclamped it is.
TEST(FilmOutputs, ClampBoundsEachSamplesIndirectLight) {
  SceneDescription scene =
      load_scene_file(std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml").scene;
  scene.render.width = 48;
  scene.render.height = 36;
  scene.render.samples_per_pixel = 1;
  scene.render.light_strategy = LightStrategy::kLight;
  scene.render.max_depth = 2;
  const TilePasses direct = render_whole(scene);
  scene.render.max_depth = 3;
  const TilePasses unclamped = render_whole(scene);
  constexpr float kClamp = 0.25f;
  scene.render.clamp = kClamp;
  const TilePasses clamped = render_whole(scene);
  // A clamp nothing reaches changes no bit: off by default is the same image.
  scene.render.clamp = 1e30;
  EXPECT_EQ(render_whole(scene).beauty, unclamped.beauty);

  float largest_unclamped = 0.0f, largest_clamped = 0.0f;
  for (std::size_t i = 0; i < direct.beauty.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      largest_unclamped =
          std::max(largest_unclamped, unclamped.beauty[i + c] - direct.beauty[i + c]);
      largest_clamped = std::max(largest_clamped, clamped.beauty[i + c] - direct.beauty[i + c]);
    }
  EXPECT_GT(largest_unclamped, 2.0f * kClamp) << "the scene must have indirect fireflies";
  // Up to the rounding of (direct + indirect) - direct, with direct up to the lamp's 16.
  EXPECT_LE(largest_clamped, kClamp + 1e-4f);
  EXPECT_EQ(RenderSettings{}.clamp, 0.0);
}

}  // namespace
}  // namespace tessera
