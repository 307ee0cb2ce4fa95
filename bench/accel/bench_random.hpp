#pragma once
#include <cstdint>

namespace tessera::bench {

// Counter-based random numbers: the value depends only on (stream, index), never on thread
// or call order, so generated meshes and ray files are identical on every machine.
inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

inline float random_unit(std::uint64_t stream, std::uint64_t index) {
  const std::uint64_t bits = mix64(mix64(stream) ^ (index * 0x9e3779b97f4a7c15ULL));
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);  // 24 bits: exactly in [0, 1)
}

}  // namespace tessera::bench
