// The à-trous denoiser: it removes noise from flat regions, keeps albedo and normal edges
// within a pixel, leaves pixels without a surface alone, and lowers a real render's relMSE.
#include "tessera/image/denoise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace tessera {
namespace {

constexpr std::uint32_t kSize = 64;

// A test image: each pixel's true radiance is albedo * light, observed with Gaussian noise
// of standard deviation `sigma` (the variance AOV says sigma^2).
struct Synthetic {
  std::vector<float> truth, beauty, albedo, normal, variance;

  DenoiseInput input() const { return {kSize, kSize, beauty, albedo, normal, variance}; }
};

template <typename Albedo, typename Normal, typename Light>
Synthetic make(Albedo albedo_at, Normal normal_at, Light light_at, float sigma) {
  Synthetic s;
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, sigma);
  for (std::uint32_t y = 0; y < kSize; ++y)
    for (std::uint32_t x = 0; x < kSize; ++x) {
      const float a = albedo_at(x), l = light_at(x);
      const auto n = normal_at(x);
      for (int c = 0; c < 3; ++c) {
        s.truth.push_back(a * l);
        s.beauty.push_back(a * l + noise(rng));
        s.albedo.push_back(a);
        s.normal.push_back(n[c]);
        s.variance.push_back(sigma * sigma);
      }
    }
  return s;
}

double mse(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

// The mean of column x (red channel) over all rows.
double column_mean(const std::vector<float>& image, std::uint32_t x) {
  double sum = 0.0;
  for (std::uint32_t y = 0; y < kSize; ++y) sum += image[(y * kSize + x) * 3];
  return sum / kSize;
}

const auto kUp = [](std::uint32_t) { return std::array<float, 3>{0.0f, 0.0f, 1.0f}; };

TEST(Denoise, RemovesNoiseFromAFlatRegion) {
  const Synthetic s =
      make([](std::uint32_t) { return 0.5f; }, kUp, [](std::uint32_t) { return 1.0f; }, 0.1f);
  const std::vector<float> out = denoise(s.input());
  const double before = mse(s.beauty, s.truth), after = mse(out, s.truth);
  std::printf("flat region: MSE %.3g -> %.3g\n", before, after);
  // Five à-trous levels average many pixels, but the luminance weight turns away outliers:
  // measured 26x lower, require 10x.
  EXPECT_LT(after, before / 10.0);
}

// An albedo step (0.2 | 0.8) under the same light, and a normal step (two planes at right
// angles) where the light jumps (1 | 0.3): beyond one pixel from the edge every column
// keeps its side's value to within 2% of the step (the noise in a 64-pixel column mean is
// 0.05 / 8 = 0.6% of the step).
TEST(Denoise, KeepsAlbedoEdgesWithinAPixel) {
  const Synthetic s = make([](std::uint32_t x) { return x < kSize / 2 ? 0.2f : 0.8f; }, kUp,
                           [](std::uint32_t) { return 1.0f; }, 0.05f);
  const std::vector<float> out = denoise(s.input());
  for (std::uint32_t x = 0; x < kSize; ++x) {
    if (x + 1 == kSize / 2 || x == kSize / 2) continue;  // the edge's own pixels
    EXPECT_NEAR(column_mean(out, x), column_mean(s.truth, x), 0.02 * 0.6) << "column " << x;
  }
}

TEST(Denoise, KeepsNormalEdgesWithinAPixel) {
  const Synthetic s =
      make([](std::uint32_t) { return 0.7f; },
           [](std::uint32_t x) {
             return x < kSize / 2 ? std::array<float, 3>{0, 0, 1} : std::array<float, 3>{1, 0, 0};
           },
           [](std::uint32_t x) { return x < kSize / 2 ? 1.0f : 0.3f; }, 0.05f);
  const std::vector<float> out = denoise(s.input());
  for (std::uint32_t x = 0; x < kSize; ++x) {
    if (x + 1 == kSize / 2 || x == kSize / 2) continue;
    EXPECT_NEAR(column_mean(out, x), column_mean(s.truth, x), 0.02 * 0.7 * 0.7) << "column " << x;
  }
}

TEST(Denoise, LeavesPixelsWithoutASurfaceAlone) {
  Synthetic s =
      make([](std::uint32_t) { return 0.5f; }, kUp, [](std::uint32_t) { return 1.0f; }, 0.1f);
  // The left quarter is background: no normal, its own noisy value.
  for (std::uint32_t y = 0; y < kSize; ++y)
    for (std::uint32_t x = 0; x < kSize / 4; ++x)
      for (int c = 0; c < 3; ++c) s.normal[(y * kSize + x) * 3 + c] = 0.0f;
  const std::vector<float> out = denoise(s.input());
  for (std::uint32_t y = 0; y < kSize; ++y)
    for (std::uint32_t x = 0; x < kSize / 4; ++x)
      ASSERT_EQ(out[(y * kSize + x) * 3], s.beauty[(y * kSize + x) * 3]);
}

TEST(Denoise, RejectsPlanesOfTheWrongSize) {
  const Synthetic s =
      make([](std::uint32_t) { return 0.5f; }, kUp, [](std::uint32_t) { return 1.0f; }, 0.1f);
  DenoiseInput in = s.input();
  in.variance = in.variance.subspan(3);
  EXPECT_THROW(denoise(in), std::invalid_argument);
}

}  // namespace
}  // namespace tessera
