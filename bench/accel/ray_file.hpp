#pragma once
#include <filesystem>
#include <span>
#include <vector>

#include "tessera/geometry/ray.hpp"

namespace tessera::bench {

// Ray files: little-endian float32 records `ox oy oz dx dy dz tnear tfar`, 32 bytes each,
// no header. tessera::Ray has exactly that layout, so records load straight into it.
std::vector<Ray> read_ray_file(const std::filesystem::path& path);
void write_ray_file(const std::filesystem::path& path, std::span<const Ray> rays);

}  // namespace tessera::bench
