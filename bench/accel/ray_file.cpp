#include "ray_file.hpp"

#include <bit>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace tessera::bench {

static_assert(std::endian::native == std::endian::little, "ray files are little-endian");
static_assert(sizeof(Ray) == 32 && offsetof(Ray, direction) == 12 && offsetof(Ray, t_min) == 24 &&
                  offsetof(Ray, t_max) == 28,
              "tessera::Ray must match the 32-byte ray record");

std::vector<Ray> read_ray_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(path.string() + ": cannot open ray file");
  const auto size = static_cast<std::size_t>(in.tellg());
  if (size % sizeof(Ray) != 0)
    throw std::runtime_error(path.string() + ": size " + std::to_string(size) +
                             " is not a multiple of the 32-byte ray record");
  std::vector<Ray> rays(size / sizeof(Ray));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(rays.data()), static_cast<std::streamsize>(size));
  if (!in) throw std::runtime_error(path.string() + ": short read");
  return rays;
}

void write_ray_file(const std::filesystem::path& path, std::span<const Ray> rays) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path.string() + ": cannot create ray file");
  out.write(reinterpret_cast<const char*>(rays.data()),
            static_cast<std::streamsize>(rays.size_bytes()));
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace tessera::bench
