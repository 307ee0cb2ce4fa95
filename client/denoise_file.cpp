#include "client/denoise_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
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

bool same_name(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// The header attributes Tessera writes, read back so the rewritten file keeps them.
ImageMetadata metadata_of(const std::filesystem::path& path) {
  const ImageHeader header = read_image_header(path);
  const auto find = [&](std::string_view name) -> const ImageHeader::Attribute* {
    for (const ImageHeader::Attribute& a : header.attributes)
      if (same_name(a.name, name)) return &a;
    return nullptr;
  };
  ImageMetadata m;
  if (const auto* a = find("Software")) m.software = a->value;
  if (const auto* a = find("tessera/scene")) m.scene_name = a->value;
  if (const auto* a = find("tessera/jobId")) m.job_id = a->value;
  if (const auto* a = find("tessera/samplesPerPixel"); a && !a->numbers.empty())
    m.samples_per_pixel = static_cast<std::uint32_t>(a->numbers[0]);
  if (const auto* a = find("tessera/renderSeconds"); a && !a->numbers.empty())
    m.render_seconds = a->numbers[0];
  const auto matrix = [&](std::string_view name, std::optional<std::array<float, 16>>& out) {
    const auto* a = find(name);
    if (!a || a->numbers.size() != 16) return;
    std::array<float, 16> values{};
    for (std::size_t i = 0; i < 16; ++i) values[i] = static_cast<float>(a->numbers[i]);
    out = values;
  };
  matrix("worldToCamera", m.world_to_camera);
  matrix("worldToScreen", m.world_to_screen);
  matrix("worldToNDC", m.world_to_ndc);
  return m;
}

}  // namespace

void denoise_exr_file(const std::filesystem::path& input, const std::filesystem::path& output,
                      const std::filesystem::path& preview_png, const PreviewOptions& preview) {
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
  const ImageMetadata metadata = metadata_of(input);
  // Written beside the output, then renamed over it, so a failure leaves the input whole;
  // OpenImageIO picks the writer by extension.
  const std::filesystem::path temporary = output.string() + ".part.exr";
  write_exr(temporary, ChannelImage{image.width, image.height, channels, std::move(out)}, 64,
            metadata);
  std::filesystem::rename(temporary, output);
  if (!preview_png.empty()) {
    RgbaImage image_of_denoised{image.width, image.height, std::vector<float>(pixels * 4, 1.0f)};
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) image_of_denoised.pixels[p * 4 + c] = clean[p * 3 + c];
    write_image(preview_png, image_of_denoised, preview);
  }
}

}  // namespace tessera
