#include "tessera/render/tile_accumulation.hpp"

#include <stdexcept>
#include <string>

namespace tessera {

std::uint32_t pass_sample_end(std::uint32_t samples, std::uint32_t passes, std::uint32_t pass) {
  if (passes == 0 || pass == 0 || pass > passes || passes > samples)
    throw std::invalid_argument("pass_sample_end: pass " + std::to_string(pass) + " of " +
                                std::to_string(passes) + " over " + std::to_string(samples) +
                                " samples");
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(samples) * pass / passes);
}

TilePasses accumulated_image(const TileAccumulation& state) {
  TilePasses image = state.sums;
  if (state.samples_done == 0 || state.samples_done == state.samples_total) return image;
  const float scale =
      static_cast<float>(state.samples_total) / static_cast<float>(state.samples_done);
  const auto rescale = [&](std::vector<float>& plane) {
    for (float& value : plane) value *= scale;
  };
  rescale(image.beauty);
  rescale(image.aovs[0]);  // albedo
  rescale(image.aovs[1]);  // normal
  return image;
}

}  // namespace tessera
