#include "tessera/image/exr.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tessera {

namespace {
OIIO::ImageSpec rgba_spec(std::uint32_t width, std::uint32_t height) {
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 4, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "A"};
  spec.alpha_channel = 3;
  spec.attribute("compression", "zip");
  return spec;
}

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
}  // namespace

std::vector<std::uint8_t> encode_exr(std::span<const float> rgba, std::uint32_t width,
                                     std::uint32_t height, std::uint32_t x, std::uint32_t y) {
  if (rgba.size() != static_cast<std::size_t>(width) * height * 4)
    throw std::invalid_argument("encode_exr: buffer size does not match width * height * 4");
  std::vector<std::uint8_t> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("tile.exr", &proxy);
  if (!out)
    throw std::runtime_error("encode_exr: OpenImageIO has no EXR writer: " + OIIO::geterror());
  OIIO::ImageSpec spec = rgba_spec(width, height);
  spec.x = static_cast<int>(x);
  spec.y = static_cast<int>(y);
  spec.full_x = 0;
  spec.full_y = 0;
  if (!out->open("tile.exr", spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgba.data()) ||
      !out->close())
    throw std::runtime_error("encode_exr: " + out->geterror());
  return bytes;
}

RgbaImage decode_exr(std::span<const std::uint8_t> bytes) {
  OIIO::Filesystem::IOMemReader proxy(const_cast<std::uint8_t*>(bytes.data()), bytes.size());
  // OIIO 2.4 takes the proxy as open()'s own argument; the "oiio:ioproxy" config hint
  // alone makes it read "tile.exr" from disk.
  auto in = OIIO::ImageInput::open("tile.exr", nullptr, &proxy);
  if (!in) throw std::runtime_error("decode_exr: not a readable EXR: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 3)
    throw std::runtime_error("decode_exr: unexpected image layout");
  RgbaImage image;
  image.width = static_cast<std::uint32_t>(spec.width);
  image.height = static_cast<std::uint32_t>(spec.height);
  image.pixels.assign(static_cast<std::size_t>(image.width) * image.height * 4, 1.0f);
  const int channels = std::min(spec.nchannels, 4);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, image.pixels.data(),
                      4 * sizeof(float)))
    throw std::runtime_error("decode_exr: " + in->geterror());
  return image;
}

struct TiledExrWriter::Impl {
  std::unique_ptr<OIIO::ImageOutput> out;
  std::uint32_t width, height, tile_size;
  std::vector<float> padded;
  bool open = false;
};

TiledExrWriter::TiledExrWriter(const std::filesystem::path& path, std::uint32_t width,
                               std::uint32_t height, std::uint32_t tile_size)
    : impl_(std::make_unique<Impl>()) {
  impl_->width = width;
  impl_->height = height;
  impl_->tile_size = tile_size;
  impl_->out = OIIO::ImageOutput::create(path.string());
  if (!impl_->out)
    throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec = rgba_spec(width, height);
  spec.tile_width = static_cast<int>(tile_size);
  spec.tile_height = static_cast<int>(tile_size);
  if (!impl_->out->supports("tiles"))
    throw std::runtime_error("cannot write " + path.string() + ": format does not support tiles");
  if (!impl_->out->open(path.string(), spec))
    throw std::runtime_error("cannot write " + path.string() + ": " + impl_->out->geterror());
  impl_->open = true;
}

TiledExrWriter::~TiledExrWriter() {
  try {
    close();
  } catch (...) {
  }
}

void TiledExrWriter::write_tile(const TileRect& tile, std::span<const float> rgba) {
  const std::uint32_t ts = impl_->tile_size;
  if (tile.x % ts != 0 || tile.y % ts != 0 || tile.width > ts || tile.height > ts)
    throw std::invalid_argument("write_tile: tile does not match the file's tile grid");
  // Edge tiles are smaller than the grid; OpenImageIO expects a full tile buffer.
  impl_->padded.assign(static_cast<std::size_t>(ts) * ts * 4, 0.0f);
  for (std::uint32_t row = 0; row < tile.height; ++row)
    std::copy_n(rgba.begin() + static_cast<std::ptrdiff_t>(row) * tile.width * 4, tile.width * 4,
                impl_->padded.begin() + static_cast<std::ptrdiff_t>(row) * ts * 4);
  if (!impl_->out->write_tile(static_cast<int>(tile.x), static_cast<int>(tile.y), 0,
                              OIIO::TypeDesc::FLOAT, impl_->padded.data()))
    throw std::runtime_error("write_tile: " + impl_->out->geterror());
}

void TiledExrWriter::close() {
  if (!impl_ || !impl_->open) return;
  impl_->open = false;
  if (!impl_->out->close()) throw std::runtime_error("closing EXR: " + impl_->out->geterror());
}

void write_image(const std::filesystem::path& path, const RgbaImage& image) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  const std::string ext = path.extension().string();
  if (ext == ".exr") {
    if (!out->open(path.string(), rgba_spec(image.width, image.height)) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !out->close())
      throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
    return;
  }
  std::vector<std::uint8_t> ldr(static_cast<std::size_t>(image.width) * image.height * 3);
  for (std::size_t i = 0, n = static_cast<std::size_t>(image.width) * image.height; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      ldr[i * 3 + c] =
          static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(image.pixels[i * 4 + c])));
  OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3,
                       OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, ldr.data()) ||
      !out->close())
    throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
}

RgbaImage read_image(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error("cannot read " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  RgbaImage image;
  image.width = static_cast<std::uint32_t>(spec.width);
  image.height = static_cast<std::uint32_t>(spec.height);
  image.pixels.assign(static_cast<std::size_t>(image.width) * image.height * 4, 1.0f);
  if (!in->read_image(0, 0, 0, std::min(spec.nchannels, 4), OIIO::TypeDesc::FLOAT,
                      image.pixels.data(), 4 * sizeof(float)))
    throw std::runtime_error("cannot read " + path.string() + ": " + in->geterror());
  return image;
}

}  // namespace tessera
