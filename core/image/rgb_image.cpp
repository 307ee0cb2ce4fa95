#include "tessera/image/rgb_image.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "tessera/image/image_codecs.hpp"

namespace tessera {

RgbImage read_rgb_image(const std::filesystem::path& path, std::uint64_t max_pixels) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error("no such file");
  return image_codecs::table().read_rgb(path, max_pixels);
}

void decode_srgb(std::vector<float>& values) {
  for (float& v : values) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace tessera
