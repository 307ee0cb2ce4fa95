// libtessera_image_codecs.so: every call into OpenImageIO, built as a module the library
// loads on first use (tessera/image/image_codecs.hpp says why). Only the entry point at
// the end is exported; the library's own checks (buffer sizes, tile grids) happen before
// it calls in, in core/image/exr.cpp.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "tessera/image/image_codecs.hpp"

namespace tessera::image_codecs {
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

std::vector<std::uint8_t> encode_exr(std::span<const float> pixels, std::uint32_t width,
                                     std::uint32_t height, const std::vector<std::string>& channels,
                                     std::uint32_t x, std::uint32_t y) {
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

// Opens an in-memory EXR and hands it to `read`. The proxy must outlive the input, so both
// live in this frame.
template <typename Read>
auto read_exr_in_memory(std::span<const std::uint8_t> bytes, int min_channels, Read&& read) {
  OIIO::Filesystem::IOMemReader proxy(const_cast<std::uint8_t*>(bytes.data()), bytes.size());
  // OIIO 2.4 takes the proxy as open()'s own argument; the "oiio:ioproxy" config hint
  // alone makes it read "tile.exr" from disk.
  auto in = OIIO::ImageInput::open("tile.exr", nullptr, &proxy);
  if (!in) throw std::runtime_error("decode_exr: not a readable EXR: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < min_channels)
    throw std::runtime_error("decode_exr: unexpected image layout");
  return read(*in, spec);
}

// The first four channels as RGBA; a file without alpha reads as opaque. Returns false
// (the input's error set) when the pixels do not read.
bool read_rgba_pixels(OIIO::ImageInput& in, RgbaImage& image) {
  const OIIO::ImageSpec& spec = in.spec();
  image.width = static_cast<std::uint32_t>(spec.width);
  image.height = static_cast<std::uint32_t>(spec.height);
  image.pixels.assign(static_cast<std::size_t>(image.width) * image.height * 4, 1.0f);
  return in.read_image(0, 0, 0, std::min(spec.nchannels, 4), OIIO::TypeDesc::FLOAT,
                       image.pixels.data(), 4 * sizeof(float));
}

ChannelImage decode_exr_channels(std::span<const std::uint8_t> bytes) {
  return read_exr_in_memory(bytes, 1, [](OIIO::ImageInput& in, const OIIO::ImageSpec& spec) {
    ChannelImage image;
    image.width = static_cast<std::uint32_t>(spec.width);
    image.height = static_cast<std::uint32_t>(spec.height);
    image.channels = spec.channelnames;
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * spec.nchannels);
    // Native reads keep UINT channels' bits; other layouts (half channels) convert to float.
    const OIIO::TypeDesc format =
        four_byte_channels(spec) ? OIIO::TypeDesc::UNKNOWN : OIIO::TypeDesc::FLOAT;
    if (!in.read_image(0, 0, 0, spec.nchannels, format, image.pixels.data()))
      throw std::runtime_error("decode_exr: " + in.geterror());
    return image;
  });
}

RgbaImage decode_exr(std::span<const std::uint8_t> bytes) {
  return read_exr_in_memory(bytes, 3, [](OIIO::ImageInput& in, const OIIO::ImageSpec&) {
    RgbaImage image;
    if (!read_rgba_pixels(in, image)) throw std::runtime_error("decode_exr: " + in.geterror());
    return image;
  });
}

struct TiledFile {
  std::unique_ptr<OIIO::ImageOutput> out;
  OIIO::TypeDesc format = OIIO::TypeDesc::FLOAT;
};

void* open_tiled_exr(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                     std::uint32_t tile_size, const std::vector<std::string>& channels,
                     const ImageMetadata& metadata) {
  auto file = std::make_unique<TiledFile>();
  file->out = OIIO::ImageOutput::create(path.string());
  if (!file->out)
    throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec = channel_spec(width, height, channels);
  spec.tile_width = static_cast<int>(tile_size);
  spec.tile_height = static_cast<int>(tile_size);
  add_metadata(spec, metadata);
  file->format = buffer_format(spec);
  if (!file->out->supports("tiles"))
    throw std::runtime_error("cannot write " + path.string() + ": format does not support tiles");
  if (!file->out->open(path.string(), spec))
    throw std::runtime_error("cannot write " + path.string() + ": " + file->out->geterror());
  return file.release();
}

// `pixels` is a whole tile of the file's grid (the library pads edge tiles).
void write_tile(void* handle, const TileRect& tile, std::span<const float> pixels) {
  auto* file = static_cast<TiledFile*>(handle);
  if (!file->out->write_tile(static_cast<int>(tile.x), static_cast<int>(tile.y), 0, file->format,
                             pixels.data()))
    throw std::runtime_error("write_tile: " + file->out->geterror());
}

void close_tiled_exr(void* handle) {
  auto* file = static_cast<TiledFile*>(handle);
  if (!file->out->close()) throw std::runtime_error("closing EXR: " + file->out->geterror());
}

void free_tiled_exr(void* handle) {
  delete static_cast<TiledFile*>(handle);
}

// Writes one whole image to a file of the format its extension names.
void write_image_file(const std::filesystem::path& path, const OIIO::ImageSpec& spec,
                      OIIO::TypeDesc format, const void* pixels) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  if (!out->open(path.string(), spec) || !out->write_image(format, pixels) || !out->close())
    throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
}

void write_exr(const std::filesystem::path& path, const ChannelImage& image,
               std::uint32_t tile_size, const ImageMetadata& metadata) {
  OIIO::ImageSpec spec = channel_spec(image.width, image.height, image.channels);
  spec.tile_width = static_cast<int>(tile_size);
  spec.tile_height = static_cast<int>(tile_size);
  add_metadata(spec, metadata);
  write_image_file(path, spec, buffer_format(spec), image.pixels.data());
}

void write_rgba_exr(const std::filesystem::path& path, const RgbaImage& image) {
  write_image_file(path, channel_spec(image.width, image.height, rgba_channels()),
                   OIIO::TypeDesc::FLOAT, image.pixels.data());
}

void write_rgb8(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                std::span<const std::uint8_t> rgb) {
  const OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 3,
                             OIIO::TypeDesc::UINT8);
  write_image_file(path, spec, OIIO::TypeDesc::UINT8, rgb.data());
}

ImageHeader read_header(const std::filesystem::path& path) {
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

RgbaImage read_rgba(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error("cannot read " + path.string() + ": " + OIIO::geterror());
  RgbaImage image;
  if (!read_rgba_pixels(*in, image))
    throw std::runtime_error("cannot read " + path.string() + ": " + in->geterror());
  return image;
}

RgbImage read_rgb(const std::filesystem::path& path, std::uint64_t max_pixels) {
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

constexpr Table kTable = {
    .abi = kAbi,
    .encode_exr = encode_exr,
    .decode_exr_channels = decode_exr_channels,
    .decode_exr = decode_exr,
    .open_tiled_exr = open_tiled_exr,
    .write_tile = write_tile,
    .close_tiled_exr = close_tiled_exr,
    .free_tiled_exr = free_tiled_exr,
    .write_exr = write_exr,
    .write_rgba_exr = write_rgba_exr,
    .write_rgb8 = write_rgb8,
    .read_header = read_header,
    .read_rgba = read_rgba,
    .read_rgb = read_rgb,
};

}  // namespace
}  // namespace tessera::image_codecs

extern "C" __attribute__((visibility("default"))) const tessera::image_codecs::Table*
tessera_image_codecs_table() {
  return &tessera::image_codecs::kTable;
}
