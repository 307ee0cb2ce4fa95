#pragma once
#include <cstdint>
#include <vector>

namespace tessera {

struct TileRect {
  std::uint32_t index = 0;  // position in row-major tile order
  std::uint32_t x = 0;
  std::uint32_t y = 0;
  std::uint32_t width = 0;
  std::uint32_t height = 0;

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * height; }
};

// Cuts a width x height image into tiles of tile_size (edge tiles are smaller), row-major.
std::vector<TileRect> make_tiles(std::uint32_t width, std::uint32_t height,
                                 std::uint32_t tile_size);

}  // namespace tessera
