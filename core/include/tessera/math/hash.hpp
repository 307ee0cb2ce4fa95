#pragma once
#include <cstdint>

#include "tessera/math/host_device.hpp"

namespace tessera {

// Integer hashes the samplers build on (rng.hpp, sobol.hpp). They are pure functions, so
// every sample value can be a pure function of (seed, pixel, sample index, dimension).
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
  // 24 high bits -> [0, 1), never exactly 1. Taking the high bits keeps a 32-bit
  // fixed-point Sobol value's strata: floor(value * 2^k) is its top k bits for k <= 24.
  return static_cast<float>(x >> 8) * (1.0f / 16777216.0f);
}

}  // namespace tessera
