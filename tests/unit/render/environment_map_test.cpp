// The equirectangular image environment: its importance sampling against its pdf
// (chi-square, chi2.hpp), the rotation about +y, and a Lambertian plane under an image
// whose lower half is bright (which the plane never sees) against the irradiance the image
// gives in closed form, under every light strategy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "chi2.hpp"
#include "path_statistics.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/light_sampling.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

using glm::dvec3;
constexpr double kPi = std::numbers::pi;

// A width x height image of smooth variation, a bright blob, and rows below the horizon
// `below` times brighter.
EnvironmentDesc image_environment(std::uint32_t width, std::uint32_t height, double rotation,
                                  float below) {
  EnvironmentDesc env;
  env.type = "image";
  env.color = dvec3(1.0, 0.9, 0.8);
  env.intensity = 1.5;
  env.rotation_degrees = rotation;
  env.image_width = width;
  env.image_height = height;
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) {
      float value = 0.2f + 0.1f * static_cast<float>((x * 7 + y * 3) % 5);
      if (x == width / 3 && y == height / 4) value = 40.0f;  // a sun-like pixel
      if (y >= height / 2) value *= below;
      env.image_pixels.insert(env.image_pixels.end(), {value, 0.5f * value, 0.25f * value});
    }
  return env;
}

SceneView prepared_view(const std::shared_ptr<const PreparedScene>& prepared) {
  return prepared->view();
}

TEST(EnvironmentMap, ImportanceSamplingFollowsItsPdf) {
  SceneDescription scene;
  scene.environment = image_environment(32, 16, 40.0, 1.0f);
  const auto prepared = PreparedScene::build(scene);
  const Environment& env = prepared_view(prepared).environment;
  ASSERT_EQ(env.kind, EnvironmentKind::kImage);

  constexpr int kSamples = 300000;
  const test::CapHistogram bins(test::DirectionCap{dvec3(0.0, 1.0, 0.0), -1.0}, 24, 48);
  std::vector<double> observed(bins.cells(), 0.0);
  test::UniformFloats u(4242);
  int mismatch = 0, zero = 0, radiance_mismatch = 0;
  for (int i = 0; i < kSamples; ++i) {
    float pdf;
    vec3 seen;
    const vec3 w = env.sample(u(), u(), pdf, seen);
    if (!(pdf > 0.0f)) {
      ++zero;
      continue;
    }
    observed[bins.cell_of(dvec3(w))] += 1.0;
    // A direction on a pixel edge may round into the neighbour: a few in 1e4.
    if (!(std::fabs(env.pdf(w) - pdf) <= 1e-3f * pdf)) ++mismatch;
    // The sample's radiance is the image's there (but on pixel edges).
    if (seen != env.radiance(w)) ++radiance_mismatch;
  }
  EXPECT_EQ(zero, 0);
  EXPECT_LT(mismatch, kSamples / 1000) << "samples whose pdf differs from pdf(direction)";
  EXPECT_LT(radiance_mismatch, kSamples / 1000);
  std::vector<double> expected =
      bins.integrate([&](const dvec3& w) { return static_cast<double>(env.pdf(vec3(w))); });
  double integral = 0.0;
  for (double& e : expected) {
    integral += e;
    e *= kSamples;
  }
  // The midpoint rule over bins that pixel edges cut (the density jumps 100x at the bright
  // pixel) is good to a few 1e-3; the chi-square below uses the same expected counts.
  EXPECT_NEAR(integral, 1.0, 5e-3);
  const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
  std::printf("[chi2] environment image p = %.4g (%s)\n", chi2.p_value, chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, 0.01) << chi2.summary;
}

// Pixel (column c, row r) of an unrotated image is the direction theta = pi (r + 1/2) / h,
// phi = 2 pi (c + 1/2) / w - pi, (sin cos phi, cos, -sin sin phi); turning the environment
// by 90 degrees about +y takes it to (z, y, -x).
TEST(EnvironmentMap, RotationTurnsTheImageAboutUp) {
  SceneDescription scene;
  EnvironmentDesc env = image_environment(32, 16, 90.0, 1.0f);
  env.color = dvec3(1.0);
  env.intensity = 1.0;
  scene.environment = env;
  const auto prepared = PreparedScene::build(scene);
  const Environment& e = prepared->view().environment;
  const double theta = kPi * (16 / 4 + 0.5) / 16, phi = 2.0 * kPi * (32 / 3 + 0.5) / 32 - kPi;
  const dvec3 local(std::sin(theta) * std::cos(phi), std::cos(theta),
                    -std::sin(theta) * std::sin(phi));
  EXPECT_EQ(e.radiance(vec3(local.z, local.y, -local.x)).x, 40.0f);
  EXPECT_LT(e.radiance(vec3(local)).x, 1.0f);  // unrotated, the blob is elsewhere
}

// A Lambertian plane (normal +y) under the image: E = sum over the upper rows' pixels of
// L times the pixel's integral of cos(theta) d omega, (sin^2 theta1 - sin^2 theta0) / 2
// times its 2 pi / w of azimuth, exact for a piecewise-constant image whatever its turn.
// The lower half is 50x brighter: importance sampling sends most samples below the plane,
// which the estimator must reject without bias.
TEST(EnvironmentMap, PlaneUnderAnImageMatchesItsIrradiance) {
  constexpr std::uint32_t kW = 16, kH = 8;
  constexpr double kAlbedo = 0.5;
  SceneDescription scene;
  scene.camera.position = {0.0, 0.6, 2.5};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 20.0;
  MaterialDesc plane;
  plane.name = "plane";
  plane.albedo = dvec3(kAlbedo);
  scene.materials = {plane};
  scene.quads.push_back(
      QuadDesc{.corner = {-10, 0, -10}, .u = {20, 0, 0}, .v = {0, 0, 20}, .material = 0});
  scene.environment = image_environment(kW, kH, 30.0, 50.0f);
  scene.render.width = 16;
  scene.render.height = 16;
  scene.render.max_depth = 2;
  const EnvironmentDesc& env = *scene.environment;
  double irradiance = 0.0;  // red channel
  for (std::uint32_t y = 0; y < kH / 2; ++y) {
    const double s0 = std::sin(kPi * y / kH), s1 = std::sin(kPi * (y + 1) / kH);
    for (std::uint32_t x = 0; x < kW; ++x)
      irradiance += env.image_pixels[3 * (y * kW + x)] * env.color.x * env.intensity * 0.5 *
                    (s1 * s1 - s0 * s0) * (2.0 * kPi / kW);
  }
  const double expected = kAlbedo / kPi * irradiance;
  const auto prepared = PreparedScene::build(scene);
  for (LightStrategy strategy :
       {LightStrategy::kMis, LightStrategy::kLight, LightStrategy::kBsdf}) {
    const test::PixelStatistics image = test::render_statistics(*prepared, strategy, 128);
    double sum = 0.0, variance = 0.0;
    for (std::size_t i = 0; i < image.mean.size(); ++i) {
      sum += image.mean[i];
      variance += image.variance_of_mean[i];
    }
    const double n = static_cast<double>(image.mean.size());
    const double mean = sum / n, sigma = std::sqrt(variance) / n;
    std::printf("[environment image] strategy %d mean %.5f expected %.5f (%+.2f sigma)\n",
                static_cast<int>(strategy), mean, expected, (mean - expected) / sigma);
    // 4 standard errors, plus 1e-5 of float rounding in the tables.
    EXPECT_LT(std::fabs(mean - expected), 4.0 * sigma + 1e-5 * expected)
        << "strategy " << static_cast<int>(strategy);
    EXPECT_EQ(image.dropped, 0u);
  }
}

}  // namespace
}  // namespace tessera
