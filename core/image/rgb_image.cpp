#include "tessera/image/rgb_image.hpp"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {

RgbImage read_rgb_image(const std::filesystem::path& path, std::uint64_t max_pixels) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error("no such file");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error("cannot read it: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw std::runtime_error("it has no pixels");
  const std::uint64_t pixels = static_cast<std::uint64_t>(spec.width) * spec.height;
  if (pixels > max_pixels)
    throw std::runtime_error(std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                             " pixels is more than the " + std::to_string(max_pixels) + " allowed");
  RgbImage image;
  image.integer_format = !spec.format.is_floating_point();
  image.width = static_cast<std::uint32_t>(spec.width);
  image.height = static_cast<std::uint32_t>(spec.height);
  image.rgb.assign(pixels * 3, 0.0f);
  const int channels = spec.nchannels >= 3 ? 3 : 1;
  std::vector<float> grey;
  float* target = image.rgb.data();
  if (channels == 1) {
    grey.resize(pixels);
    target = grey.data();
  }
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, target,
                      static_cast<OIIO::stride_t>(channels * sizeof(float))))
    throw std::runtime_error("cannot read its pixels: " + in->geterror());
  if (channels == 1)
    for (std::uint64_t i = 0; i < pixels; ++i)
      image.rgb[3 * i] = image.rgb[3 * i + 1] = image.rgb[3 * i + 2] = grey[i];
  return image;
}

void decode_srgb(std::vector<float>& values) {
  for (float& v : values) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace tessera
