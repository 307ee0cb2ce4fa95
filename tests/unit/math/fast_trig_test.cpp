// The light samplers' inline atan2 and sincos (math/fast_trig.hpp) against double-precision
// libm over dense sweeps: the bounds are a few float ulps of the result (absolute near zero),
// the precision the spherical maps' float angle sums have anyway.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "tessera/math/fast_trig.hpp"

namespace tessera {
namespace {

// Error allowed: 4 ulps of the exact value, or 2e-7 absolute near zero (where a float
// argument's own rounding dominates).
double allowed(double exact) {
  if (!(exact != 0.0)) return 2e-7;  // ilogb(0) is INT_MIN: no exponent to subtract from
  return std::max(4.0 * std::ldexp(1.0, std::ilogb(exact) - 23), 2e-7);
}

TEST(FastTrig, Atan2MatchesLibmInEveryQuadrant) {
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double angle = -M_PI + 2.0 * M_PI * (i + 0.5) / 20000.0;
    for (const double radius : {1e-30, 1e-3, 1.0, 7.5, 1e20}) {
      const float x = static_cast<float>(radius * std::cos(angle));
      const float y = static_cast<float>(radius * std::sin(angle));
      const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x));
      const double error = std::fabs(fast_atan2(y, x) - exact);
      worst = std::max(worst, error / allowed(std::fabs(exact)));
      ASSERT_LE(error, allowed(std::fabs(exact))) << "y " << y << " x " << x;
    }
  }
  RecordProperty("worst_error_in_allowed_units", std::to_string(worst));
}

TEST(FastTrig, Atan2KeepsLibmsAxesAndSignedZeros) {
  EXPECT_EQ(fast_atan2(0.0f, 1.0f), 0.0f);
  EXPECT_TRUE(std::signbit(fast_atan2(-0.0f, 1.0f)));
  EXPECT_FLOAT_EQ(fast_atan2(1.0f, 0.0f), static_cast<float>(M_PI / 2));
  EXPECT_FLOAT_EQ(fast_atan2(-1.0f, 0.0f), static_cast<float>(-M_PI / 2));
  EXPECT_FLOAT_EQ(fast_atan2(0.0f, -1.0f), static_cast<float>(M_PI));
  EXPECT_FLOAT_EQ(fast_atan2(-0.0f, -1.0f), static_cast<float>(-M_PI));
  EXPECT_EQ(fast_atan2(0.0f, 0.0f), std::atan2(0.0f, 0.0f));
  EXPECT_EQ(fast_atan2(0.0f, -0.0f), std::atan2(0.0f, -0.0f));
  EXPECT_TRUE(std::isnan(fast_atan2(std::numeric_limits<float>::quiet_NaN(), 1.0f)));
  EXPECT_TRUE(std::isnan(fast_atan2(1.0f, std::numeric_limits<float>::quiet_NaN())));
}

TEST(FastTrig, SincosMatchesLibmOverTheSamplersRange) {
  // The samplers pass angles in [0, 4 pi]; the sweep covers negatives and a margin too.
  for (int i = -200000; i <= 200000; ++i) {
    const float x = static_cast<float>(i) * 1.0e-4f;
    float s = 0.0f, c = 0.0f;
    fast_sincos(x, s, c);
    const double exact_sin = std::sin(static_cast<double>(x));
    const double exact_cos = std::cos(static_cast<double>(x));
    ASSERT_LE(std::fabs(s - exact_sin), allowed(std::fabs(exact_sin))) << "sin " << x;
    ASSERT_LE(std::fabs(c - exact_cos), allowed(std::fabs(exact_cos))) << "cos " << x;
  }
}

// Azimuths 2 pi u: within 5e-7 of the exact sine and cosine of 2 pi u (the error of
// rounding 2 pi u to a float before libm's sinf sees it is up to 4.8e-7), on a unit circle to
// 1e-6, over 2^22 + 1 evenly spaced u in [0, 1].
TEST(FastTrig, SincosOfTurnsMatchesTheExactAzimuth) {
  constexpr int kSteps = 1 << 22;
  double worst_sin = 0.0, worst_cos = 0.0, worst_norm = 0.0;
  for (int i = 0; i <= kSteps; ++i) {
    const float u = static_cast<float>(i) / static_cast<float>(kSteps);
    float s = 0.0f, c = 0.0f;
    fast_sincos_turns(u, s, c);
    const double phi = 2.0 * 3.14159265358979323846 * static_cast<double>(u);
    worst_sin = std::max(worst_sin, std::fabs(s - std::sin(phi)));
    worst_cos = std::max(worst_cos, std::fabs(c - std::cos(phi)));
    worst_norm = std::max(worst_norm, std::fabs(double{s} * s + double{c} * c - 1.0));
  }
  EXPECT_LE(worst_sin, 5e-7);
  EXPECT_LE(worst_cos, 5e-7);
  EXPECT_LE(worst_norm, 1e-6);
  float s = 1.0f, c = 0.0f;
  fast_sincos_turns(0.0f, s, c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
}

// The double-precision sincos within 4 double ulps (or 1e-16 absolute near zero) of libm's
// over [-20, 20], and libm's own values beyond 1e3.
TEST(FastTrig, DoubleSincosMatchesLibm) {
  double worst_ulps = 0.0;
  for (int i = -2000000; i <= 2000000; ++i) {
    const double x = static_cast<double>(i) * 1.0e-5 + 1.0e-7;
    double s = 0.0, c = 0.0;
    fast_sincos(x, s, c);
    for (const auto& [got, exact] : {std::pair{s, std::sin(x)}, std::pair{c, std::cos(x)}}) {
      const double ulp = std::max(std::ldexp(1.0, std::ilogb(exact) - 52), 1e-16 / 4.0);
      worst_ulps = std::max(worst_ulps, std::fabs(got - exact) / ulp);
    }
  }
  EXPECT_LE(worst_ulps, 4.0);
  double s = 0.0, c = 0.0;
  fast_sincos(1.0e4, s, c);
  EXPECT_EQ(s, std::sin(1.0e4));
  EXPECT_EQ(c, std::cos(1.0e4));
}

TEST(FastTrig, SincosOutsideTheReducedRangeIsLibms) {
  float s = 0.0f, c = 0.0f;
  fast_sincos(1.0e6f, s, c);
  EXPECT_EQ(s, std::sin(1.0e6f));
  EXPECT_EQ(c, std::cos(1.0e6f));
  fast_sincos(std::numeric_limits<float>::quiet_NaN(), s, c);
  EXPECT_TRUE(std::isnan(s));
  EXPECT_TRUE(std::isnan(c));
  fast_sincos(std::numeric_limits<float>::infinity(), s, c);
  EXPECT_TRUE(std::isnan(s));
}

TEST(FastTrig, SincosIsExactWhereLibmIs) {
  float s = 1.0f, c = 0.0f;
  fast_sincos(0.0f, s, c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
  fast_sincos(static_cast<float>(M_PI), s, c);
  EXPECT_NEAR(s, 0.0f, 1e-7f);
  EXPECT_EQ(c, -1.0f);
}

}  // namespace
}  // namespace tessera
