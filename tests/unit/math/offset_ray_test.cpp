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

// The error-bound offset per axis, as the device path does it.
float reference_error_axis(float p, float n, float distance) {
  const float x = p + distance * n;
  if (n == 0.0f) return x;
  if (x == 0.0f) return n > 0.0f ? 0x1p-149f : -0x1p-149f;
  std::int32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits += (x < 0.0f) != (n < 0.0f) ? -1 : 1;
  float moved;
  std::memcpy(&moved, &bits, sizeof moved);
  return moved;
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

// With an error bound, the point moves along the normal by at least the distance the error
// can reach along it (error times the sum of |n|), on every axis the normal has a component,
// whatever the point's own magnitude; a negative bound takes Waechter and Binder's ulps.
TEST(OffsetRay, AnErrorBoundMovesThePointPastTheError) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> exponent(-8.0f, 6.0f);
  for (int i = 0; i < 20000; ++i) {
    vec3 p, n;
    for (int a = 0; a < 3; ++a) {
      p[a] = i % 7 == 0 && a == 1 ? 0.0f : unit(rng) * std::pow(10.0f, exponent(rng));
      n[a] = i % 5 == 0 && a == 2 ? 0.0f : unit(rng);
    }
    n = glm::normalize(n);
    const float error = position_error_bound(std::pow(10.0f, exponent(rng)));
    const vec3 moved = offset_ray_origin(p, n, 1.0f, error);
    const double reach = double{error} * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
    const float distance = error * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(bits_of(moved[a]), bits_of(reference_error_axis(p[a], n[a], distance)))
          << "axis " << a << " p " << p[a] << " n " << n[a];
      const double step = double{moved[a]} - double{p[a]};
      if (n[a] == 0.0f) {
        ASSERT_EQ(moved[a], p[a]);
      } else {
        // At least the reach's share of this axis, and strictly past the point.
        ASSERT_GE(step * (n[a] > 0.0f ? 1.0 : -1.0), reach * std::fabs(double{n[a]}) * 0.999999)
            << "axis " << a << " p " << p[a] << " n " << n[a] << " error " << error;
        ASSERT_GT(step * (n[a] > 0.0f ? 1.0 : -1.0), 0.0);
      }
    }
  }
  // A zero coordinate steps to the smallest subnormal on the normal's side.
  EXPECT_EQ(offset_ray_origin(vec3(0.0f), vec3(0.0f, -1.0f, 0.0f), 1.0f, 0.0f),
            vec3(0.0f, -0x1p-149f, 0.0f));
  const vec3 p(1000.0f, 2.0f, -3.0f), n(0.0f, 1.0f, 0.0f);
  EXPECT_EQ(offset_ray_origin(p, n, 1.0f, -1.0f), offset_ray_origin(p, n, 1.0f));
  // 1,000 units out, a quad's error bound is far below Waechter and Binder's 256 ulps
  // (1.5 cm), which stepped over a 1 cm gap.
  const float quad_error = position_error_bound(1003.0f);
  EXPECT_LT(offset_ray_origin(vec3(1000.0f), n, 1.0f, quad_error).y - 1000.0f, 1e-3f);
  EXPECT_GT(offset_ray_origin(vec3(1000.0f), n, 1.0f).y - 1000.0f, 1e-2f);
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
