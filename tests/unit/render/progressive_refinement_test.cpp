// Progressive refinement (PreparedScene::refine_tile): passes of 1, 4, 16 and 64 spp
// continue one sample sequence, so the last pass is the 64-spp image, AOVs included.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "lit_box_scene.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/tile.hpp"

namespace tessera {
namespace {

// Float rounding of the rescaling between passes: a few ulps of values below ~30.
void expect_planes_near(const std::vector<float>& a, const std::vector<float>& b,
                        const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i])  // equal infinities (depth where nothing was hit) are not near
      ASSERT_NEAR(a[i], b[i], 2e-5f + 2e-5f * std::fabs(b[i])) << what << " float " << i;
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

}  // namespace
}  // namespace tessera
