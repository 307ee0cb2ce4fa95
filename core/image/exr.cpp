#include "tessera/image/exr.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tessera {

bool is_id_channel(std::string_view name) {
  const std::size_t dot = name.rfind('.');
  const std::string_view layer = dot == std::string_view::npos ? name : name.substr(0, dot);
  return layer.size() >= 2 && layer.substr(layer.size() - 2) == "ID";
}

namespace {
// FLOAT channels, and UINT for ID channels. Both are four bytes, so a buffer of floats
// whose ID slots hold integer bits is the file's native layout (written and read with
// TypeUnknown: no conversion).
OIIO::ImageSpec channel_spec(std::uint32_t width, std::uint32_t height,
                             const std::vector<std::string>& channels) {
  if (channels.empty()) throw std::invalid_argument("an EXR needs at least one channel");
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height),
                       static_cast<int>(channels.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channels;
  if (std::any_of(channels.begin(), channels.end(), is_id_channel))
    for (const std::string& name : channels)
      spec.channelformats.push_back(is_id_channel(name) ? OIIO::TypeDesc::UINT32
                                                        : OIIO::TypeDesc::FLOAT);
  const auto alpha = std::find(channels.begin(), channels.end(), "A");
  spec.alpha_channel = alpha == channels.end() ? -1 : static_cast<int>(alpha - channels.begin());
  spec.attribute("compression", "zip");
  return spec;
}

// The format to hand OpenImageIO for a buffer laid out as channel_spec describes.
OIIO::TypeDesc buffer_format(const OIIO::ImageSpec& spec) {
  return spec.channelformats.empty() ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UNKNOWN;
}

// Whether every channel of a file is four bytes (FLOAT or UINT), so it reads natively.
bool four_byte_channels(const OIIO::ImageSpec& spec) {
  for (int c = 0; c < spec.nchannels; ++c) {
    const OIIO::TypeDesc format = spec.channelformat(c);
    if (format != OIIO::TypeDesc::FLOAT && format != OIIO::TypeDesc::UINT32) return false;
  }
  return true;
}

void add_metadata(OIIO::ImageSpec& spec, const ImageMetadata& metadata) {
  // Rec. 709 primaries and D65 white: what the renderer's linear RGB means.
  static constexpr float kRec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), kRec709);
  if (!metadata.software.empty()) spec.attribute("Software", metadata.software);
  if (!metadata.scene_name.empty()) spec.attribute("tessera/scene", metadata.scene_name);
  if (!metadata.job_id.empty()) spec.attribute("tessera/jobId", metadata.job_id);
  if (metadata.samples_per_pixel > 0)
    spec.attribute("tessera/samplesPerPixel", static_cast<int>(metadata.samples_per_pixel));
  if (metadata.render_seconds)
    spec.attribute("tessera/renderSeconds", static_cast<float>(*metadata.render_seconds));
  if (metadata.world_to_camera)
    spec.attribute("worldtocamera", OIIO::TypeMatrix44, metadata.world_to_camera->data());
  if (metadata.world_to_screen)
    spec.attribute("worldtoscreen", OIIO::TypeMatrix44, metadata.world_to_screen->data());
  if (metadata.world_to_ndc)
    spec.attribute("worldtoNDC", OIIO::TypeMatrix44, metadata.world_to_ndc->data());
}

OIIO::ImageSpec rgba_spec(std::uint32_t width, std::uint32_t height) {
  return channel_spec(width, height, rgba_channels());
}

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
  std::vector<std::uint8_t> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("tile.exr", &proxy);
  if (!out)
    throw std::runtime_error("encode_exr: OpenImageIO has no EXR writer: " + OIIO::geterror());
  OIIO::ImageSpec spec = channel_spec(width, height, channels);
  spec.x = static_cast<int>(x);
  spec.y = static_cast<int>(y);
  spec.full_x = 0;
  spec.full_y = 0;
  if (!out->open("tile.exr", spec) || !out->write_image(buffer_format(spec), pixels.data()) ||
      !out->close())
    throw std::runtime_error("encode_exr: " + out->geterror());
  return bytes;
}

std::vector<std::uint8_t> encode_exr(std::span<const float> rgba, std::uint32_t width,
                                     std::uint32_t height, std::uint32_t x, std::uint32_t y) {
  return encode_exr(rgba, width, height, rgba_channels(), x, y);
}

ChannelImage decode_exr_channels(std::span<const std::uint8_t> bytes) {
  OIIO::Filesystem::IOMemReader proxy(const_cast<std::uint8_t*>(bytes.data()), bytes.size());
  auto in = OIIO::ImageInput::open("tile.exr", nullptr, &proxy);
  if (!in) throw std::runtime_error("decode_exr: not a readable EXR: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1)
    throw std::runtime_error("decode_exr: unexpected image layout");
  ChannelImage image;
  image.width = static_cast<std::uint32_t>(spec.width);
  image.height = static_cast<std::uint32_t>(spec.height);
  image.channels = spec.channelnames;
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * spec.nchannels);
  // Native reads keep UINT channels' bits; other layouts (half channels) convert to float.
  const OIIO::TypeDesc format =
      four_byte_channels(spec) ? OIIO::TypeDesc::UNKNOWN : OIIO::TypeDesc::FLOAT;
  if (!in->read_image(0, 0, 0, spec.nchannels, format, image.pixels.data()))
    throw std::runtime_error("decode_exr: " + in->geterror());
  return image;
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
  std::unique_ptr<OIIO::ImageOutput> out;
  std::uint32_t width, height, tile_size;
  std::size_t channel_count;
  std::vector<float> padded;
  OIIO::TypeDesc format = OIIO::TypeDesc::FLOAT;
  bool open = false;
};

TiledExrWriter::TiledExrWriter(const std::filesystem::path& path, std::uint32_t width,
                               std::uint32_t height, std::uint32_t tile_size,
                               const std::vector<std::string>& channels,
                               const ImageMetadata& metadata)
    : impl_(std::make_unique<Impl>()) {
  impl_->channel_count = channels.size();
  impl_->width = width;
  impl_->height = height;
  impl_->tile_size = tile_size;
  impl_->out = OIIO::ImageOutput::create(path.string());
  if (!impl_->out)
    throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec = channel_spec(width, height, channels);
  spec.tile_width = static_cast<int>(tile_size);
  spec.tile_height = static_cast<int>(tile_size);
  add_metadata(spec, metadata);
  impl_->format = buffer_format(spec);
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
  if (!impl_->out->write_tile(static_cast<int>(tile.x), static_cast<int>(tile.y), 0, impl_->format,
                              impl_->padded.data()))
    throw std::runtime_error("write_tile: " + impl_->out->geterror());
}

void TiledExrWriter::close() {
  if (!impl_ || !impl_->open) return;
  impl_->open = false;
  if (!impl_->out->close()) throw std::runtime_error("closing EXR: " + impl_->out->geterror());
}

void write_exr(const std::filesystem::path& path, const ChannelImage& image,
               std::uint32_t tile_size, const ImageMetadata& metadata) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec = channel_spec(image.width, image.height, image.channels);
  spec.tile_width = static_cast<int>(tile_size);
  spec.tile_height = static_cast<int>(tile_size);
  add_metadata(spec, metadata);
  if (!out->open(path.string(), spec) ||
      !out->write_image(buffer_format(spec), image.pixels.data()) || !out->close())
    throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
}

void write_image(const std::filesystem::path& path, const RgbaImage& image,
                 const PreviewOptions& preview) {
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
      ldr[i * 3 + c] = static_cast<std::uint8_t>(
          std::lround(255.0f * linear_to_srgb(tone_map(image.pixels[i * 4 + c], preview))));
  OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3,
                       OIIO::TypeDesc::UINT8);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, ldr.data()) ||
      !out->close())
    throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
}

const ImageHeader::Attribute* ImageHeader::find(std::string_view name) const {
  for (const Attribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

ImageHeader read_image_header(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error("cannot read " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  ImageHeader header;
  header.channel_names = spec.channelnames;
  for (int c = 0; c < spec.nchannels; ++c)
    header.channel_types.push_back(spec.channelformat(c).c_str());
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    ImageHeader::Attribute a;
    a.name = p.name().string();
    a.value = p.get_string();
    const OIIO::TypeDesc type = p.type();
    const std::size_t count = type.numelements() * type.aggregate * p.nvalues();
    const auto copy = [&](const auto* values) { a.numbers.assign(values, values + count); };
    if (type.basetype == OIIO::TypeDesc::FLOAT) copy(static_cast<const float*>(p.data()));
    if (type.basetype == OIIO::TypeDesc::DOUBLE) copy(static_cast<const double*>(p.data()));
    if (type.basetype == OIIO::TypeDesc::INT) copy(static_cast<const int*>(p.data()));
    if (type.basetype == OIIO::TypeDesc::UINT) copy(static_cast<const unsigned*>(p.data()));
    header.attributes.push_back(std::move(a));
  }
  return header;
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
