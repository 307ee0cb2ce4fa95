#include "tessera/math/offset_ray.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>

namespace tessera {
namespace {

// Wächter and Binder's offset written out per axis, as the scalar (device) path does it:
// the host's SSE2 form must give the same bits.
float reference_axis(float p, float n, float spawn_scale) {
  const auto of_i = static_cast<std::int32_t>(kSpawnUlps * n);
  std::uint32_t bits;
  std::memcpy(&bits, &p, sizeof bits);
  bits += static_cast<std::uint32_t>(p < 0.0f ? -of_i : of_i);
  float moved;
  std::memcpy(&moved, &bits, sizeof moved);
  return std::fabs(p) < spawn_scale * kSpawnBand ? p + (spawn_scale * kSpawnStep) * n : moved;
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
    // Every fourth point with a scene scale below 1 (a scene smaller than two units).
    const float spawn_scale = i % 4 == 1 ? std::ldexp(1.0f, -(i % 23)) : 1.0f;
    const vec3 moved = offset_ray_origin(p, n, spawn_scale);
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(bits_of(moved[a]), bits_of(reference_axis(p[a], n[a], spawn_scale)))
          << "axis " << a << " p " << p[a] << " n " << n[a] << " scale " << spawn_scale;
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

// Away from zero a coordinate moves by kSpawnUlps ulps times the normal's component; within
// kSpawnBand of it by a fixed step; band and step proportional to the scene's scale.
TEST(OffsetRay, MovesByKSpawnUlpsAwayFromZeroAndByTheScaledStepNearIt) {
  const vec3 up(0.0f, 1.0f, 0.0f);
  const auto ulps = static_cast<std::uint32_t>(kSpawnUlps);
  for (const float y : {1000.0f, 1.0f, -20.0f, 0.04f}) {
    const float moved = offset_ray_origin(vec3(0.0f, y, 0.0f), up).y;
    EXPECT_EQ(bits_of(moved), bits_of(y) + (y > 0.0f ? ulps : -ulps)) << y;
  }
  for (const float y : {0.0f, 0.01f, -0.02f})
    EXPECT_EQ(offset_ray_origin(vec3(0.0f, y, 0.0f), up).y, y + kSpawnStep) << y;
  const float scale = std::ldexp(1.0f, -10);
  EXPECT_EQ(offset_ray_origin(vec3(0.0f), up, scale).y, scale * kSpawnStep);
  // 0.01 is outside the scaled band (2^-15): it moves by ulps, not by the step.
  const float moved = offset_ray_origin(vec3(0.0f, 0.01f, 0.0f), up, scale).y;
  EXPECT_EQ(bits_of(moved), bits_of(0.01f) + ulps);
}
}  // namespace
}  // namespace tessera
