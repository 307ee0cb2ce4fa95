#include "tessera/render/tile.hpp"

#include <algorithm>

namespace tessera {

std::vector<TileRect> make_tiles(std::uint32_t width, std::uint32_t height,
                                 std::uint32_t tile_size) {
  std::vector<TileRect> tiles;
  if (width == 0 || height == 0 || tile_size == 0) return tiles;
  for (std::uint32_t y = 0; y < height; y += tile_size)
    for (std::uint32_t x = 0; x < width; x += tile_size)
      tiles.push_back(TileRect{static_cast<std::uint32_t>(tiles.size()), x, y,
                               std::min(tile_size, width - x), std::min(tile_size, height - y)});
  return tiles;
}

}  // namespace tessera
