#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <set>

#include "client/local_render.hpp"
#include "client/tile_assembler.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

SceneDescription small_cornell() {
  SceneDescription scene =
      load_scene_file(std::filesystem::path(TESSERA_SOURCE_DIR) / "examples/scenes/cornell.yaml")
          .scene;
  scene.render.width = 45;
  scene.render.height = 30;
  scene.render.samples_per_pixel = 2;
  scene.render.tile_size = 8;
  return scene;
}

// Pixels depend on the pixel, not on which thread rendered which tile in which order.
TEST(LocalRender, ParallelTilesEqualTheSerialRenderBitForBit) {
  const auto prepared = PreparedScene::build(small_cornell());
  const std::vector<float> reference = render_image(*prepared);
  for (unsigned threads : {1u, 3u, 8u}) {
    SCOPED_TRACE(threads);
    TileAssembler assembler(45, 30, 8, std::nullopt);
    std::set<std::uint32_t> seen;
    std::uint64_t rays = 0;
    const LocalRenderResult result = render_local(
        *prepared, threads,
        [&](const TileRect& tile, std::span<const float> rgba, std::uint64_t r) {
          EXPECT_TRUE(seen.insert(tile.index).second) << "tile " << tile.index << " twice";
          rays += r;
          assembler.add_tile(tile, rgba);
        });
    EXPECT_FALSE(result.stopped);
    EXPECT_EQ(seen.size(), 24u);
    EXPECT_EQ(result.rays, rays);
    // At least one camera ray per sample.
    EXPECT_GE(result.rays, 45u * 30u * 2u);
    assembler.finish();
    ASSERT_EQ(assembler.image().pixels.size(), reference.size());
    EXPECT_EQ(std::memcmp(assembler.image().pixels.data(), reference.data(),
                          reference.size() * sizeof(float)),
              0);
  }
}

TEST(LocalRender, StopFlagEndsEarlyAndCallbackErrorsPropagate) {
  const auto prepared = PreparedScene::build(small_cornell());
  std::atomic<bool> stop{false};
  std::uint32_t calls = 0;
  const LocalRenderResult stopped = render_local(
      *prepared, 1,
      [&](const TileRect&, std::span<const float>, std::uint64_t) {
        if (++calls == 3) stop = true;
      },
      &stop);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(calls, 3u);

  EXPECT_THROW(render_local(*prepared, 2,
                            [](const TileRect& tile, std::span<const float>, std::uint64_t) {
                              if (tile.index == 5) throw std::runtime_error("disk full");
                            }),
               std::runtime_error);
}

}  // namespace
}  // namespace tessera
