// The convergence metrics tessera-bench converge reports, against hand-computed answers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tessera/image/image_error.hpp"

namespace tessera {
namespace {

RgbaImage grey(std::uint32_t width, std::uint32_t height, float value) {
  RgbaImage image{width, height, std::vector<float>(std::size_t{width} * height * 4, value)};
  for (std::size_t p = 3; p < image.pixels.size(); p += 4) image.pixels[p] = 1.0f;
  return image;
}

TEST(ImageError, RelativeMseWeighsEachPixelByItsReference) {
  const RgbaImage reference = grey(2, 1, 1.0f);
  RgbaImage image = reference;
  image.pixels[0] = 2.0f;  // one of six channels off by 1: d^2 / (1 + 0.01)
  const ImageError e = image_error(image, reference);
  EXPECT_NEAR(e.rel_mse, (1.0 / 1.01) / 6.0, 1e-12);
  EXPECT_NEAR(e.rmse, std::sqrt(1.0 / 6.0), 1e-12);
  EXPECT_NEAR(e.mean, 7.0 / 6.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.reference_mean, 1.0);
  // Alpha is not counted: changing it changes nothing.
  image.pixels[3] = 0.0f;
  EXPECT_NEAR(image_error(image, reference).rel_mse, (1.0 / 1.01) / 6.0, 1e-12);
  // A black reference pixel is weighed by 1 / 0.01, not divided by zero.
  const RgbaImage black = grey(1, 1, 0.0f);
  EXPECT_NEAR(image_error(grey(1, 1, 0.1f), black).rel_mse, 0.01 / 0.01, 1e-6);
  EXPECT_THROW(image_error(grey(1, 1, 0.0f), grey(2, 1, 0.0f)), std::invalid_argument);
}

TEST(TimeToError, InterpolatesWhenTheSeriesReachesTheTarget) {
  // relMSE = 0.1 / t: 1e-3 is reached at t = 100, between the renders at 64 and 128 s.
  std::vector<ErrorPoint> series;
  for (double t = 1; t <= 128; t *= 2) series.push_back({t, 0.1 / t});
  const auto at = time_to_error(series, 1e-3);
  ASSERT_TRUE(at.has_value());
  EXPECT_FALSE(at->extrapolated);
  EXPECT_NEAR(at->seconds, 100.0, 1e-9);
  EXPECT_NEAR(at->slope, -1.0, 1e-12);
  EXPECT_EQ(at->seconds_at_unit_slope, at->seconds);  // measured: nothing to extrapolate
  EXPECT_FALSE(at->shallow);
}

// A renderer with a fixed cost per render (20 ms) and 10 ms per sample, relMSE 1 / spp, at
// 1-256 spp: it reaches 1e-3 at 1,000 spp, 10.02 s. Extrapolated through the later half of
// the renders: 9.44 s (slope -1.04). Through every render the set-up of the shortest ones
// steepened the slope to -1.20 and gave 6.78 s, a third short.
TEST(TimeToError, ExtrapolationLeavesOutTheShortRendersFixedCost) {
  std::vector<ErrorPoint> series;
  for (double spp = 1; spp <= 256; spp *= 2) series.push_back({0.02 + 0.01 * spp, 1.0 / spp});
  const auto at = time_to_error(series, 1e-3);
  ASSERT_TRUE(at.has_value());
  EXPECT_TRUE(at->extrapolated);
  EXPECT_NEAR(at->seconds, 10.02, 0.07 * 10.02);
  EXPECT_NEAR(at->slope, -1.0, 0.05);
  EXPECT_FALSE(at->shallow);
  // From the 256-spp render (2.58 s, relMSE 1/256) at slope -1: 10.08 s, near the 10.02 s
  // it takes; the fixed cost is a smaller share of the longest render.
  EXPECT_NEAR(at->seconds_at_unit_slope, 2.58 / 256.0 / 1e-3, 1e-9);
}

// Fireflies: a heavy-tailed series whose later renders barely improve until the rare bright
// samples are averaged (relMSE stepping 0.046, 0.087, 0.042, 0.019 at 0.19-1.48 s, the
// held-out studio scene's 32-256 spp) fits a slope flatter than -0.8, which is flagged.
TEST(TimeToError, FlagsASeriesTooShortForItsFireflies) {
  const std::vector<ErrorPoint> series = {{0.008, 0.23},  {0.014, 0.12},  {0.029, 0.15},
                                          {0.054, 0.31},  {0.097, 0.12},  {0.192, 0.046},
                                          {0.387, 0.087}, {0.732, 0.042}, {1.477, 0.019}};
  const auto at = time_to_error(series, 1e-3);
  ASSERT_TRUE(at.has_value());
  EXPECT_TRUE(at->extrapolated);
  EXPECT_GT(at->slope, kShallowSlope);
  EXPECT_TRUE(at->shallow);
  EXPECT_GT(at->seconds, 100.0);  // the flat fit's hundreds of seconds
  EXPECT_NEAR(at->seconds_at_unit_slope, 1.477 * 0.019 / 1e-3, 1e-9);
}

TEST(TimeToError, ExtrapolatesAPowerLawAndRefusesAFlatOne) {
  std::vector<ErrorPoint> series;
  for (double t = 1; t <= 8; t *= 2) series.push_back({t, 0.5 / std::sqrt(t)});  // slope -1/2
  const auto at = time_to_error(series, 1e-3);
  ASSERT_TRUE(at.has_value());
  EXPECT_TRUE(at->extrapolated);
  EXPECT_NEAR(at->slope, -0.5, 1e-12);
  EXPECT_NEAR(at->seconds, 250000.0, 1e-6);  // 0.5 / sqrt(t) = 1e-3 at t = 500^2
  // Much flatter than an unbiased renderer's -1: flagged, with the last render's relMSE
  // carried on at slope -1 beside it: 8 s x 0.5 / sqrt(8) / 1e-3.
  EXPECT_TRUE(at->shallow);
  EXPECT_NEAR(at->seconds_at_unit_slope, 8.0 * 0.5 / std::sqrt(8.0) / 1e-3, 1e-6);

  const std::vector<ErrorPoint> flat = {{1, 0.2}, {2, 0.2}, {4, 0.2}};  // bias, no progress
  EXPECT_FALSE(time_to_error(flat, 1e-3).has_value());
  EXPECT_FALSE(time_to_error(std::vector<ErrorPoint>{{1, 0.5}}, 1e-3).has_value());
}

}  // namespace
}  // namespace tessera
