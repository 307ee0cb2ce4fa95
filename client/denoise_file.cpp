#include "client/denoise_file.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "tessera/image/denoise.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/output_channels.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

namespace {

// The channels an AOV adds to the output (output_channels() without R, G, B, A).
std::vector<std::string> aov_channels(std::uint32_t aov) {
  std::vector<std::string> names = output_channels(aov);
  names.erase(names.begin(), names.begin() + 4);
  return names;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// One plane of three channels as width * height * 3 floats.
std::vector<float> plane(const ChannelImage& image, const std::vector<std::string>& names) {
  const ChannelImage three = select_channels(image, names);
  return three.pixels;
}

}  // namespace

void denoise_exr_file(const std::filesystem::path& input, const std::filesystem::path& output,
                      const std::filesystem::path& preview_png) {
  ChannelImage image;
  try {
    image = decode_exr_channels(read_bytes(input));
  } catch (const std::exception& e) {
    throw std::runtime_error(input.string() + ": " + e.what());
  }
  const std::vector<std::string> rgb = {"R", "G", "B"};
  const std::vector<std::string> albedo = aov_channels(kAovAlbedo),
                                 normal = aov_channels(kAovNormal),
                                 variance = aov_channels(kAovVariance);
  std::string missing;
  for (const auto* names : {&rgb, &albedo, &normal, &variance})
    for (const std::string& name : *names)
      if (std::find(image.channels.begin(), image.channels.end(), name) == image.channels.end())
        missing += (missing.empty() ? "" : ", ") + name;
  if (!missing.empty())
    throw std::runtime_error(input.string() + " lacks the channels " + missing +
                             "; the denoiser needs the albedo, normal and variance AOVs (render "
                             "with `tessera render --denoise`, or aovs: [albedo, normal, "
                             "variance])");
  const std::vector<float> beauty = plane(image, rgb);
  const std::vector<float> albedo_plane = plane(image, albedo);
  const std::vector<float> normal_plane = plane(image, normal);
  const std::vector<float> variance_plane = plane(image, variance);
  const std::vector<float> clean =
      denoise({image.width, image.height, beauty, albedo_plane, normal_plane, variance_plane});

  // Every input channel (a previous denoised pass replaced), then denoised.R/G/B.
  const std::vector<std::string> denoised = {"denoised.R", "denoised.G", "denoised.B"};
  std::vector<std::string> kept;
  for (const std::string& name : image.channels)
    if (std::find(denoised.begin(), denoised.end(), name) == denoised.end()) kept.push_back(name);
  const ChannelImage base = select_channels(image, kept);
  std::vector<std::string> channels = kept;
  channels.insert(channels.end(), denoised.begin(), denoised.end());
  const std::size_t pixels = std::size_t{image.width} * image.height;
  std::vector<float> out;
  out.reserve(pixels * channels.size());
  for (std::size_t p = 0; p < pixels; ++p) {
    out.insert(out.end(), base.pixels.begin() + p * kept.size(),
               base.pixels.begin() + (p + 1) * kept.size());
    out.insert(out.end(), clean.begin() + p * 3, clean.begin() + p * 3 + 3);
  }
  const std::vector<std::uint8_t> bytes =
      encode_exr(out, image.width, image.height, channels, 0, 0);
  {
    const std::filesystem::path temporary = output.string() + ".part";
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    if (!file.flush()) throw std::runtime_error("cannot write " + temporary.string());
    file.close();
    std::filesystem::rename(temporary, output);
  }
  if (!preview_png.empty()) {
    RgbaImage preview{image.width, image.height, std::vector<float>(pixels * 4, 1.0f)};
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) preview.pixels[p * 4 + c] = clean[p * 3 + c];
    write_image(preview_png, preview);
  }
}

}  // namespace tessera
