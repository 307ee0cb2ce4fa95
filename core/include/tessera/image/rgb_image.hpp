#pragma once
// Reading an image (HDR, EXR, PNG, JPEG or any format OpenImageIO reads) into plain RGB
// floats, the renderer's own array: environments and textures are read once where the scene
// is loaded, and nothing reads a file at shading time.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tessera {

struct RgbImage {
  std::uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, rows from the top down, the file's values
  // The file stores integers (8- or 16-bit): conventionally sRGB-encoded, where float
  // files are linear.
  bool integer_format = false;
};

// Reads `path`; a one- or two-channel image is grey. Throws std::runtime_error saying why
// (missing, unreadable, or more than `max_pixels` pixels, checked before reading them).
RgbImage read_rgb_image(const std::filesystem::path& path, std::uint64_t max_pixels);

// The sRGB transfer function's inverse (IEC 61966-2-1), applied to every value in place.
void decode_srgb(std::vector<float>& values);

}  // namespace tessera
