#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "client/tile_assembler.hpp"

namespace tessera {
namespace {

// A pixel value that tells where it belongs, so misplaced copies show up.
float pattern(std::uint32_t x, std::uint32_t y, int channel) {
  return static_cast<float>(x) + 1000.0f * static_cast<float>(y) +
         0.25f * static_cast<float>(channel);
}

std::vector<float> tile_pixels(const TileRect& t) {
  std::vector<float> rgba(t.pixel_count() * 4);
  for (std::uint32_t row = 0; row < t.height; ++row)
    for (std::uint32_t col = 0; col < t.width; ++col)
      for (int c = 0; c < 4; ++c)
        rgba[(row * t.width + col) * 4 + c] = pattern(t.x + col, t.y + row, c);
  return rgba;
}

TEST(TileAssembler, TilesInAnyOrderMakeTheImageAndTheTiledExr) {
  const std::uint32_t width = 37, height = 21, tile_size = 8;  // edge tiles are partial
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("tessera_tile_assembler_" + std::to_string(::getpid()) + ".exr");
  std::vector<TileRect> tiles = make_tiles(width, height, tile_size);
  std::shuffle(tiles.begin(), tiles.end(), std::mt19937(42));
  {
    TileAssembler assembler(width, height, tile_size, path);
    EXPECT_EQ(assembler.tiles_total(), 15u);
    for (const TileRect& t : tiles) {
      EXPECT_FALSE(assembler.complete());
      assembler.add_tile(t, tile_pixels(t));
    }
    EXPECT_TRUE(assembler.complete());
    assembler.finish();
    for (std::uint32_t y = 0; y < height; ++y)
      for (std::uint32_t x = 0; x < width; ++x)
        for (int c = 0; c < 4; ++c)
          ASSERT_EQ(assembler.image().pixels[(y * width + x) * 4 + c], pattern(x, y, c))
              << x << "," << y;
  }
  const RgbaImage file = read_image(path);
  std::filesystem::remove(path);
  ASSERT_EQ(file.width, width);
  ASSERT_EQ(file.height, height);
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(file.pixels[(y * width + x) * 4 + c], pattern(x, y, c)) << x << "," << y;
}

TEST(TileAssembler, RejectsTilesThatDoNotFitTheGrid) {
  TileAssembler assembler(20, 10, 8, std::nullopt);
  const TileRect first{0, 0, 0, 8, 8};
  assembler.add_tile(first, tile_pixels(first));
  EXPECT_THROW(assembler.add_tile(first, tile_pixels(first)), std::runtime_error);  // twice
  const TileRect out_of_grid{6, 0, 8, 8, 2};
  EXPECT_THROW(assembler.add_tile(out_of_grid, tile_pixels(out_of_grid)), std::runtime_error);
  const TileRect misplaced{1, 16, 0, 8, 8};
  EXPECT_THROW(assembler.add_tile(misplaced, tile_pixels(misplaced)), std::runtime_error);
  const TileRect edge{2, 16, 0, 4, 8};
  EXPECT_THROW(assembler.add_tile(edge, std::vector<float>(4)),
               std::runtime_error);  // short buffer
  assembler.add_tile(edge, tile_pixels(edge));
  EXPECT_EQ(assembler.tiles_received(), 2u);
}

TEST(TileAssembler, FinishNamesTheFirstMissingTile) {
  TileAssembler assembler(16, 16, 8, std::nullopt);
  for (const TileRect& t : make_tiles(16, 16, 8))
    if (t.index != 2) assembler.add_tile(t, tile_pixels(t));
  try {
    assembler.finish();
    FAIL() << "finish() accepted an incomplete image";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tile 2 "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("3 of 4 tiles"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

std::vector<float> filled(const TileRect& t, float value) {
  return std::vector<float>(t.pixel_count() * 4, value);
}

// Progressive passes: each tile's passes arrive in order; the EXR on disk is rewritten
// whole as each pass of the image completes, so it always shows a finished pass.
TEST(TileAssembler, PassesReplaceTilesAndRewriteTheExrAsEachPassCompletes) {
  const std::uint32_t width = 20, height = 12, tile_size = 8;  // 3 x 2 tiles
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("tessera_tile_assembler_passes_" + std::to_string(::getpid()) + ".exr");
  std::filesystem::remove(path);
  const std::vector<TileRect> tiles = make_tiles(width, height, tile_size);
  TileAssembler assembler(width, height, tile_size, path, rgba_channels(), 3);
  EXPECT_EQ(assembler.passes(), 3u);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    EXPECT_FALSE(std::filesystem::exists(path));  // no pass complete yet
    EXPECT_EQ(assembler.add_tile(tiles[i], filled(tiles[i], 1.0f), 1), i + 1 == tiles.size());
  }
  EXPECT_EQ(assembler.passes_done(), 1u);
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_EQ(read_image(path).pixels[0], 1.0f);
  // A pass out of order, or a tile's pass again, is an error.
  EXPECT_THROW(assembler.add_tile(tiles[0], filled(tiles[0], 3.0f), 3), std::runtime_error);
  EXPECT_THROW(assembler.add_tile(tiles[0], filled(tiles[0], 1.0f), 1), std::runtime_error);
  assembler.add_tile(tiles[0], filled(tiles[0], 2.0f), 2);
  EXPECT_EQ(assembler.image().pixels[0], 2.0f);  // the latest pass shows at once
  EXPECT_EQ(read_image(path).pixels[0], 1.0f);   // the file keeps the last whole pass
  for (std::size_t i = 1; i < tiles.size(); ++i)
    assembler.add_tile(tiles[i], filled(tiles[i], 2.0f), 2);
  EXPECT_EQ(read_image(path).pixels[0], 2.0f);
  for (const TileRect& t : tiles) {
    EXPECT_FALSE(assembler.complete());
    assembler.add_tile(t, filled(t, 3.0f), 3);
  }
  EXPECT_TRUE(assembler.complete());
  EXPECT_EQ(assembler.passes_done(), 3u);
  assembler.finish();
  const RgbaImage file = read_image(path);
  EXPECT_TRUE(
      std::all_of(file.pixels.begin(), file.pixels.end(), [](float v) { return v == 3.0f; }));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tessera
