#include "tessera/image/exr.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tessera/image/image_codecs.hpp"

// The pure parts of image I/O; every call into OpenImageIO is in the image codecs module
// (core/image_codecs/), reached through image_codecs::table().
namespace tessera {

namespace {
float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
}  // namespace

float tone_map(float c, const PreviewOptions& options) {
  c *= std::exp2(options.exposure);
  if (!(c > 0.0f)) return 0.0f;  // negatives and NaN
  switch (options.curve) {
    case ToneCurve::kClamp:
      break;
    case ToneCurve::kAces:
      // Narkowicz 2015, "ACES Filmic Tone Mapping Curve": a rational fit of the ACES
      // reference rendering transform's tone scale, per channel.
      c = (c * (2.51f * c + 0.03f)) / (c * (2.43f * c + 0.59f) + 0.14f);
      break;
  }
  return std::clamp(c, 0.0f, 1.0f);
}

std::vector<std::uint8_t> encode_exr(std::span<const float> pixels, std::uint32_t width,
                                     std::uint32_t height, const std::vector<std::string>& channels,
                                     std::uint32_t x, std::uint32_t y) {
  if (pixels.size() != static_cast<std::size_t>(width) * height * channels.size())
    throw std::invalid_argument("encode_exr: buffer size does not match width * height * channels");
  return image_codecs::table().encode_exr(pixels, width, height, channels, x, y);
}

std::vector<std::uint8_t> encode_exr(std::span<const float> rgba, std::uint32_t width,
                                     std::uint32_t height, std::uint32_t x, std::uint32_t y) {
  return encode_exr(rgba, width, height, rgba_channels(), x, y);
}

ChannelImage decode_exr_channels(std::span<const std::uint8_t> bytes) {
  return image_codecs::table().decode_exr_channels(bytes);
}

RgbaImage decode_exr(std::span<const std::uint8_t> bytes) {
  return image_codecs::table().decode_exr(bytes);
}

ChannelImage select_channels(const ChannelImage& image, const std::vector<std::string>& wanted) {
  const std::size_t stride = image.channels.size();
  std::vector<std::size_t> source;
  for (const std::string& name : wanted) {
    const auto it = std::find(image.channels.begin(), image.channels.end(), name);
    if (it == image.channels.end())
      throw std::runtime_error("the image has no channel '" + name + "'");
    source.push_back(static_cast<std::size_t>(it - image.channels.begin()));
  }
  ChannelImage out;
  out.width = image.width;
  out.height = image.height;
  out.channels = wanted;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  out.pixels.resize(pixels * wanted.size());
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t c = 0; c < source.size(); ++c)
      out.pixels[p * source.size() + c] = image.pixels[p * stride + source[c]];
  return out;
}

struct TiledExrWriter::Impl {
  const image_codecs::Table* codecs = nullptr;
  void* file = nullptr;  // the module's handle
  std::uint32_t tile_size = 0;
  std::size_t channel_count = 0;
  std::vector<float> padded;
  bool open = false;

  ~Impl() {
    if (file != nullptr) codecs->free_tiled_exr(file);
  }
};

TiledExrWriter::TiledExrWriter(const std::filesystem::path& path, std::uint32_t width,
                               std::uint32_t height, std::uint32_t tile_size,
                               const std::vector<std::string>& channels,
                               const ImageMetadata& metadata)
    : impl_(std::make_unique<Impl>()) {
  impl_->codecs = &image_codecs::table();
  impl_->channel_count = channels.size();
  impl_->tile_size = tile_size;
  impl_->file = impl_->codecs->open_tiled_exr(path, width, height, tile_size, channels, metadata);
  impl_->open = true;
}

TiledExrWriter::~TiledExrWriter() {
  try {
    close();
  } catch (...) {
  }
}

void TiledExrWriter::write_tile(const TileRect& tile, std::span<const float> pixels) {
  const std::uint32_t ts = impl_->tile_size;
  const std::size_t nc = impl_->channel_count;
  if (tile.x % ts != 0 || tile.y % ts != 0 || tile.width > ts || tile.height > ts)
    throw std::invalid_argument("write_tile: tile does not match the file's tile grid");
  if (pixels.size() != tile.pixel_count() * nc)
    throw std::invalid_argument("write_tile: buffer size does not match the tile and channels");
  // Edge tiles are smaller than the grid; OpenImageIO expects a full tile buffer.
  impl_->padded.assign(static_cast<std::size_t>(ts) * ts * nc, 0.0f);
  const std::size_t row_floats = tile.width * nc;
  for (std::uint32_t row = 0; row < tile.height; ++row)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(row * row_floats), row_floats,
                impl_->padded.begin() + static_cast<std::ptrdiff_t>(row * ts * nc));
  impl_->codecs->write_tile(impl_->file, tile, impl_->padded);
}

void TiledExrWriter::close() {
  if (!impl_ || !impl_->open) return;
  impl_->open = false;
  impl_->codecs->close_tiled_exr(impl_->file);
}

void write_exr(const std::filesystem::path& path, const ChannelImage& image,
               std::uint32_t tile_size, const ImageMetadata& metadata) {
  image_codecs::table().write_exr(path, image, tile_size, metadata);
}

void write_image(const std::filesystem::path& path, const RgbaImage& image,
                 const PreviewOptions& preview) {
  const image_codecs::Table& codecs = image_codecs::table();
  if (path.extension() == ".exr") return codecs.write_rgba_exr(path, image);
  std::vector<std::uint8_t> ldr(static_cast<std::size_t>(image.width) * image.height * 3);
  for (std::size_t i = 0, n = static_cast<std::size_t>(image.width) * image.height; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      ldr[i * 3 + c] = static_cast<std::uint8_t>(
          std::lround(255.0f * linear_to_srgb(tone_map(image.pixels[i * 4 + c], preview))));
  codecs.write_rgb8(path, image.width, image.height, ldr);
}

const ImageHeader::Attribute* ImageHeader::find(std::string_view name) const {
  for (const Attribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

ImageHeader read_image_header(const std::filesystem::path& path) {
  return image_codecs::table().read_header(path);
}

RgbaImage read_image(const std::filesystem::path& path) {
  return image_codecs::table().read_rgba(path);
}

}  // namespace tessera
