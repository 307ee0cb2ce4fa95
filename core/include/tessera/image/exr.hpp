#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tessera/render/tile.hpp"

namespace tessera {

// A float RGBA image in memory, rows top to bottom.
struct RgbaImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<float> pixels;  // width * height * 4
};

// Encodes a float RGBA buffer as a complete EXR file in memory (32-bit float channels,
// so a decoded tile is bit-identical to what was rendered). `x`, `y` place it within the
// full image as the EXR data window origin.
std::vector<std::uint8_t> encode_exr(std::span<const float> rgba, std::uint32_t width,
                                     std::uint32_t height, std::uint32_t x = 0,
                                     std::uint32_t y = 0);

// Decodes an EXR file held in memory. Throws std::runtime_error on malformed data.
RgbaImage decode_exr(std::span<const std::uint8_t> bytes);

// Writes a tiled EXR as tiles arrive, in any order, through OpenImageIO's write_tile.
class TiledExrWriter {
 public:
  TiledExrWriter(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                 std::uint32_t tile_size);
  ~TiledExrWriter();
  TiledExrWriter(const TiledExrWriter&) = delete;
  TiledExrWriter& operator=(const TiledExrWriter&) = delete;

  void write_tile(const TileRect& tile, std::span<const float> rgba);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes a whole image to EXR, or to 8-bit PNG (sRGB-encoded, clamped) for previews, by extension.
void write_image(const std::filesystem::path& path, const RgbaImage& image);
RgbaImage read_image(const std::filesystem::path& path);

}  // namespace tessera
