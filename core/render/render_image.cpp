#include "tessera/render/render_image.hpp"

#include <algorithm>
#include <cstddef>

namespace tessera {

std::vector<float> render_image(const PreparedScene& scene) {
  const auto& s = scene.settings();
  std::vector<float> image(static_cast<std::size_t>(s.width) * s.height * 4, 0.0f);
  std::vector<float> tile_buffer;
  for (const TileRect& tile : make_tiles(s.width, s.height, s.tile_size)) {
    tile_buffer.resize(tile.pixel_count() * 4);
    scene.render_tile(tile, tile_buffer);
    for (std::uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(
          tile_buffer.begin() + static_cast<std::ptrdiff_t>(row) * tile.width * 4, tile.width * 4,
          image.begin() + (static_cast<std::ptrdiff_t>(tile.y + row) * s.width + tile.x) * 4);
  }
  return image;
}

}  // namespace tessera
