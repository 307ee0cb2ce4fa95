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

// Float image with named channels (R, G, B, A, then AOVs such as albedo.R or depth.Z),
// interleaved per pixel, rows top to bottom.
struct ChannelImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;  // width * height * channels.size()
};

inline const std::vector<std::string>& rgba_channels() {
  static const std::vector<std::string> names = {"R", "G", "B", "A"};
  return names;
}

// Encodes a float buffer with the named channels as a complete EXR file in memory.
std::vector<std::uint8_t> encode_exr(std::span<const float> pixels, std::uint32_t width,
                                     std::uint32_t height, const std::vector<std::string>& channels,
                                     std::uint32_t x, std::uint32_t y);

// Decodes every channel of an EXR held in memory. Throws std::runtime_error on malformed data.
// EXR files keep their own channel order (OpenEXR sorts by name), so callers that need a
// layout ask for it with select_channels().
ChannelImage decode_exr_channels(std::span<const std::uint8_t> bytes);

// The channels named in `wanted`, in that order. Throws std::runtime_error naming the
// first missing channel.
ChannelImage select_channels(const ChannelImage& image, const std::vector<std::string>& wanted);

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
                 std::uint32_t tile_size,
                 const std::vector<std::string>& channels = rgba_channels());
  ~TiledExrWriter();
  TiledExrWriter(const TiledExrWriter&) = delete;
  TiledExrWriter& operator=(const TiledExrWriter&) = delete;

  // `pixels` holds the file's channels interleaved, tile.width * tile.height of them.
  void write_tile(const TileRect& tile, std::span<const float> pixels);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes a whole image to EXR, or to 8-bit PNG (sRGB-encoded, clamped) for previews, by extension.
void write_image(const std::filesystem::path& path, const RgbaImage& image);
RgbaImage read_image(const std::filesystem::path& path);

}  // namespace tessera
