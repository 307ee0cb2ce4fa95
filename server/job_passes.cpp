#include "server/job_passes.hpp"

#include "tessera/render/tile.hpp"
#include "tessera/render/tile_accumulation.hpp"

namespace tessera::server {

PassLayout::PassLayout(const RenderSettings& settings)
    : tiles_(static_cast<std::uint32_t>(
          make_tiles(settings.width, settings.height, settings.tile_size).size())),
      passes_(settings.pass_count()),
      samples_(settings.samples_per_pixel) {}

std::uint32_t PassLayout::samples_after(std::uint32_t pass) const {
  return pass_sample_end(samples_, passes_, pass);
}

}  // namespace tessera::server
