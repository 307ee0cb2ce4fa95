#pragma once
// Reading an equirectangular environment image (HDR, EXR or any format OpenImageIO reads)
// into plain linear RGB floats, the renderer's own array: nothing reads the file at shading
// time.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tessera {

struct EnvironmentImage {
  std::uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, rows from the top (the zenith) down
};

// Reads `path`; a one- or two-channel image is grey. Throws std::runtime_error saying why
// (missing, unreadable, or more than `max_pixels` pixels, checked before reading them).
EnvironmentImage read_environment_image(const std::filesystem::path& path,
                                        std::uint64_t max_pixels);

}  // namespace tessera
