#pragma once
#include <cstdint>

#include "tessera/math/host_device.hpp"

namespace tessera {

// Counter-based random numbers: every value is a pure function of (job seed, pixel,
// sample index, dimension), so an image does not depend on thread count, tile size or
// the order tiles are rendered in.
TESSERA_HD TESSERA_INLINE std::uint32_t mix32(std::uint32_t x) {
  // lowbias32 by Chris Wellons: good avalanche at two multiplies.
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

TESSERA_HD TESSERA_INLINE std::uint32_t hash_combine(std::uint32_t seed, std::uint32_t value) {
  return mix32(seed ^ (value + 0x9e3779b9U + (seed << 6) + (seed >> 2)));
}

TESSERA_HD TESSERA_INLINE float uint_to_unit_float(std::uint32_t x) {
  // 24 high bits -> [0, 1), never exactly 1.
  return static_cast<float>(x >> 8) * (1.0f / 16777216.0f);
}

class SampleStream {
 public:
  TESSERA_HD SampleStream(std::uint64_t seed, std::uint32_t pixel_x, std::uint32_t pixel_y,
                          std::uint32_t sample_index) {
    std::uint32_t h = mix32(static_cast<std::uint32_t>(seed) ^ 0x2545f491U);
    h = hash_combine(h, static_cast<std::uint32_t>(seed >> 32));
    h = hash_combine(h, pixel_x);
    h = hash_combine(h, pixel_y);
    h = hash_combine(h, sample_index);
    key_ = h;
  }
  // The next dimension's value in [0, 1).
  TESSERA_HD float next() { return uint_to_unit_float(hash_combine(key_, dimension_++)); }
  TESSERA_HD std::uint32_t dimension() const { return dimension_; }
  // Jumps to `dimension`, so each bounce of a path draws from its own fixed block.
  TESSERA_HD void set_dimension(std::uint32_t dimension) { dimension_ = dimension; }

 private:
  std::uint32_t key_ = 0;
  std::uint32_t dimension_ = 0;
};

}  // namespace tessera
