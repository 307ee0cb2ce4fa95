#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tessera/render/tile.hpp"

namespace tessera {

// A float RGBA image in memory, rows top to bottom.
struct RgbaImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<float> pixels;  // width * height * 4
};

// Float image with named channels (R, G, B, A, then AOVs such as Albedo.R or Z),
// interleaved per pixel, rows top to bottom. ID channels (is_id_channel) hold 32-bit
// unsigned integers whose bits sit in the float slots (id_as_float in render/film.hpp).
struct ChannelImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;  // width * height * channels.size()
};

inline const std::vector<std::string>& rgba_channels() {
  static const std::vector<std::string> names = {"R", "G", "B", "A"};
  return names;
}

// Channels whose layer name ends in "ID" (PrimitiveID.X) are written as EXR UINT channels:
// an ID must read back exactly, and a float keeps integers exact only up to 2^24. In memory
// they travel as the integer's bits in a float slot, which every copy here preserves.
inline bool is_id_channel(std::string_view name) {
  const std::size_t dot = name.rfind('.');
  const std::string_view layer = dot == std::string_view::npos ? name : name.substr(0, dot);
  return layer.size() >= 2 && layer.substr(layer.size() - 2) == "ID";
}

// Header attributes of a rendered image. OpenEXR's standard attributes where one exists
// (worldToCamera, worldToNDC, chromaticities), "software", and Tessera's own under
// "tessera/". Matrices are Imath's M44f as stored: row vectors (p' = p * M), which is
// glm's column-major memory of the same transform.
struct ImageMetadata {
  std::string software;                  // "software": name and version
  std::string scene_name;                // "tessera/scene"
  std::string job_id;                    // "tessera/jobId"; empty for a local render
  std::uint32_t samples_per_pixel = 0;   // "tessera/samplesPerPixel"
  std::optional<double> render_seconds;  // "tessera/renderSeconds", wall time
  // See CameraMatrices (render/camera.hpp) for the spaces.
  std::optional<std::array<float, 16>> world_to_camera;  // "worldToCamera"
  std::optional<std::array<float, 16>> world_to_screen;  // "worldToScreen": [-1, 1], +Y up
  std::optional<std::array<float, 16>> world_to_ndc;     // "worldToNDC": [0, 1], +Y down
};
// Encodes a float buffer with the named channels as a complete EXR file in memory.
std::vector<std::uint8_t> encode_exr(std::span<const float> pixels, std::uint32_t width,
                                     std::uint32_t height, const std::vector<std::string>& channels,
                                     std::uint32_t x, std::uint32_t y);

// Decodes every channel of an EXR held in memory. Throws std::runtime_error on malformed data.
// EXR files keep their own channel order (OpenEXR sorts by name), so callers that need a
// layout ask for it with select_channels().
ChannelImage decode_exr_channels(std::span<const std::uint8_t> bytes);

// The channels named in `wanted`, in that order. Throws std::runtime_error naming the
// first missing channel.
ChannelImage select_channels(const ChannelImage& image, const std::vector<std::string>& wanted);

// Encodes a float RGBA buffer as a complete EXR file in memory (32-bit float channels,
// so a decoded tile is bit-identical to what was rendered). `x`, `y` place it within the
// full image as the EXR data window origin.
std::vector<std::uint8_t> encode_exr(std::span<const float> rgba, std::uint32_t width,
                                     std::uint32_t height, std::uint32_t x = 0,
                                     std::uint32_t y = 0);

// Decodes an EXR file held in memory. Throws std::runtime_error on malformed data.
RgbaImage decode_exr(std::span<const std::uint8_t> bytes);

// Writes a tiled EXR as tiles arrive, in any order, through OpenImageIO's write_tile.
class TiledExrWriter {
 public:
  TiledExrWriter(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
                 std::uint32_t tile_size,
                 const std::vector<std::string>& channels = rgba_channels(),
                 const ImageMetadata& metadata = {});
  ~TiledExrWriter();
  TiledExrWriter(const TiledExrWriter&) = delete;
  TiledExrWriter& operator=(const TiledExrWriter&) = delete;

  // `pixels` holds the file's channels interleaved, tile.width * tile.height of them.
  void write_tile(const TileRect& tile, std::span<const float> pixels);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// An image file's header as OpenImageIO reads it, for inspection and tests: attributes by
// the names OpenImageIO gives them (the camera matrices keep OpenEXR's, worldToNDC;
// software reads as "Software"), their values as text and, for numeric ones, every
// number; and each channel's pixel type.
struct ImageHeader {
  struct Attribute {
    std::string name;
    std::string value;
    std::vector<double> numbers;
  };
  std::vector<Attribute> attributes;
  std::vector<std::string> channel_names;
  std::vector<std::string> channel_types;  // "float", "uint", "half", ...
  const Attribute* find(std::string_view name) const;
};
ImageHeader read_image_header(const std::filesystem::path& path);

// Writes a whole channel image as a tiled EXR with the given header attributes.
void write_exr(const std::filesystem::path& path, const ChannelImage& image,
               std::uint32_t tile_size, const ImageMetadata& metadata);

// How a preview maps linear radiance to display values before the sRGB encoding.
enum class ToneCurve {
  kClamp,  // clip at 1
  kAces,   // Narkowicz's fit of the ACES filmic curve (2015): rolls highlights off smoothly
};
struct PreviewOptions {
  float exposure = 0.0f;  // stops: radiance is multiplied by 2^exposure first
  ToneCurve curve = ToneCurve::kClamp;
};
// The display value in [0, 1] of linear radiance `c` (before the sRGB encoding).
float tone_map(float c, const PreviewOptions& options);

// Writes a whole image to EXR, or to 8-bit PNG (exposure, tone curve, sRGB-encoded) for
// previews, by extension.
void write_image(const std::filesystem::path& path, const RgbaImage& image,
                 const PreviewOptions& preview = {});
RgbaImage read_image(const std::filesystem::path& path);

}  // namespace tessera
