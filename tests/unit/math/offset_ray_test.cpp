#include "tessera/math/offset_ray.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>

namespace tessera {
namespace {

// Wächter and Binder's offset written out per axis, as the scalar (device) path does it:
// the host's SSE2 form must give the same bits.
float reference_axis(float p, float n) {
  const auto of_i = static_cast<std::int32_t>(256.0f * n);
  std::uint32_t bits;
  std::memcpy(&bits, &p, sizeof bits);
  bits += static_cast<std::uint32_t>(p < 0.0f ? -of_i : of_i);
  float moved;
  std::memcpy(&moved, &bits, sizeof moved);
  return std::fabs(p) < 1.0f / 32.0f ? p + (1.0f / 65536.0f) * n : moved;
}

std::uint32_t bits_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

TEST(OffsetRay, MatchesThePerAxisFormBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> exponent(-12.0f, 6.0f);
  const float specials[] = {0.0f, -0.0f, 1.0f / 32.0f, -1.0f / 32.0f, 0.03124f, -0.03126f, 1e6f};
  for (int i = 0; i < 20000; ++i) {
    vec3 p, n;
    for (int a = 0; a < 3; ++a) {
      p[a] = i % 5 == 0 ? specials[(i / 5 + a) % 7] : unit(rng) * std::pow(10.0f, exponent(rng));
      n[a] = unit(rng);
    }
    n = glm::normalize(n);
    const vec3 moved = offset_ray_origin(p, n);
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(bits_of(moved[a]), bits_of(reference_axis(p[a], n[a])))
          << "axis " << a << " p " << p[a] << " n " << n[a];
  }
}

TEST(OffsetRay, MovesThePointToTheNormalsSide) {
  const vec3 n(0.0f, 1.0f, 0.0f);
  for (const float y : {-1000.0f, -1.0f, -0.01f, 0.0f, 0.01f, 1.0f, 1000.0f}) {
    const vec3 p(3.0f, y, -2.0f);
    EXPECT_GT(offset_ray_origin(p, n).y, y);
    EXPECT_LT(offset_ray_origin(p, -n).y, y);
    EXPECT_EQ(offset_ray_origin(p, n).x, 3.0f);
  }
}

}  // namespace
}  // namespace tessera
