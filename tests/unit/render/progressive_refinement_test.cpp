// Progressive refinement (PreparedScene::refine_tile): passes of 1, 4, 16 and 64 spp
// continue one sample sequence, so the last pass is the 64-spp image, AOVs included.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <vector>

#include "lit_box_scene.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/tile.hpp"
#include "tessera/render/tile_accumulation.hpp"

namespace tessera {
namespace {

// Float rounding of the rescaling between passes: a few ulps of values below ~30.
void expect_planes_near(const std::vector<float>& a, const std::vector<float>& b,
                        const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) {  // equal infinities (depth where nothing was hit) are not near
      ASSERT_NEAR(a[i], b[i], 2e-5f + 2e-5f * std::fabs(b[i])) << what << " float " << i;
    }
  }
}

TEST(ProgressiveRefinement, PassesAddUpToTheFullRender) {
  SceneDescription description = test::lit_box(0.0, 64);
  description.render.aovs =
      kAovAlbedo | kAovDepth | kAovPrimitiveId | kAovVariance | kAovSampleCount;
  const auto scene = PreparedScene::build(description);
  for (const TileRect& tile : make_tiles(24, 24, 8)) {
    TilePasses at_once;
    scene->render_tile(tile, at_once);
    TilePasses passes;
    std::uint32_t done = 0;
    for (std::uint32_t end : {1u, 4u, 16u, 64u}) {
      scene->refine_tile(tile, passes, done, end);
      done = end;
      EXPECT_EQ(passes.aovs[5][0], static_cast<float>(end));  // sample_count
    }
    expect_planes_near(passes.beauty, at_once.beauty, "beauty");
    for (std::size_t i = 0; i < kAovCount; ++i)
      expect_planes_near(passes.aovs[i], at_once.aovs[i], "aov");
  }
}

TEST(ProgressiveRefinement, RejectsPassesThatCannotContinue) {
  const auto scene = PreparedScene::build(test::lit_box(0.0, 64));
  const TileRect tile = make_tiles(24, 24, 8)[0];
  TilePasses passes;
  EXPECT_THROW(scene->refine_tile(tile, passes, 4, 4), std::invalid_argument);
  EXPECT_THROW(scene->refine_tile(tile, passes, 4, 8), std::invalid_argument);  // empty planes
  const auto adaptive = PreparedScene::build(test::lit_box(0.05, 64));
  adaptive->refine_tile(tile, passes, 0, 16);
  EXPECT_THROW(adaptive->refine_tile(tile, passes, 16, 64), std::invalid_argument);
}

// The floats themselves, not a tolerance: NaN-free planes compare by their bits.
void expect_planes_identical(const std::vector<float>& a, const std::vector<float>& b,
                             const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(float)), 0)
        << what << " float " << i << ": " << a[i] << " vs " << b[i];
}

// What a job with passes relies on: passes of accumulate_tile end with exactly the single
// render's floats, every AOV included (the variance's running statistics cross the passes).
TEST(TileAccumulation, PassesEqualTheSingleRenderBitForBit) {
  SceneDescription description = test::lit_box(0.0, 24);
  description.render.aovs = kAllAovs;
  const auto scene = PreparedScene::build(description);
  for (const std::uint32_t passes : {1u, 2u, 5u, 24u}) {
    for (const TileRect& tile : make_tiles(24, 24, 8)) {
      TilePasses at_once;
      scene->render_tile(tile, at_once);
      TileAccumulation state;
      for (std::uint32_t pass = 1; pass <= passes; ++pass) {
        scene->accumulate_tile(tile, state, pass_sample_end(24, passes, pass));
        EXPECT_EQ(state.samples_done, pass_sample_end(24, passes, pass));
      }
      ASSERT_EQ(state.samples_done, 24u);
      const TilePasses image = accumulated_image(state);
      expect_planes_identical(image.beauty, at_once.beauty, "beauty");
      for (std::size_t i = 0; i < kAovCount; ++i)
        expect_planes_identical(image.aovs[i], at_once.aovs[i], "aov");
    }
  }
}

// Between passes the image is the average of the samples so far: close to a render of that
// many samples (the same samples, summed at another weight).
TEST(TileAccumulation, IntermediateImageIsTheAverageSoFar) {
  const auto scene = PreparedScene::build(test::lit_box(0.0, 16));
  SceneDescription four = test::lit_box(0.0, 4);
  const auto four_spp = PreparedScene::build(four);
  const TileRect tile = make_tiles(24, 24, 8)[4];
  TileAccumulation state;
  scene->accumulate_tile(tile, state, 4);
  TilePasses reference;
  four_spp->render_tile(tile, reference);
  expect_planes_near(accumulated_image(state).beauty, reference.beauty, "beauty at 4 spp");
  EXPECT_NE(accumulated_image(state).beauty, state.sums.beauty);  // scaled by 16 / 4
}

TEST(TileAccumulation, RejectsRangesThatCannotContinue) {
  const auto scene = PreparedScene::build(test::lit_box(0.0, 16));
  const TileRect tile = make_tiles(24, 24, 8)[0];
  TileAccumulation state;
  EXPECT_THROW(scene->accumulate_tile(tile, state, 17), std::invalid_argument);
  scene->accumulate_tile(tile, state, 8);
  EXPECT_THROW(scene->accumulate_tile(tile, state, 8), std::invalid_argument);
  EXPECT_THROW(scene->accumulate_tile(make_tiles(24, 24, 16)[0], state, 12),
               std::invalid_argument);  // another tile's size
  const auto adaptive = PreparedScene::build(test::lit_box(0.05, 64));
  TileAccumulation fresh;
  EXPECT_THROW(adaptive->accumulate_tile(tile, fresh, 16), std::invalid_argument);
  EXPECT_EQ(pass_sample_end(10, 3, 1), 3u);
  EXPECT_EQ(pass_sample_end(10, 3, 3), 10u);
  EXPECT_THROW(pass_sample_end(2, 3, 1), std::invalid_argument);
}

}  // namespace
}  // namespace tessera
