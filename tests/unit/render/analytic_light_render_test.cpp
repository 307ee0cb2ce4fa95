// The path tracer under lights that are not shapes, against closed forms: a point light, a
// spot light and a sun (a delta direction and one with an angular radius) over a Lambertian
// plane, the white furnace under a constant environment, and RayON's gradient sky as camera
// rays see it. Each rendering runs under every LightStrategy; tolerances are in standard
// errors from the per-pixel sample variance (path_statistics.hpp), plus a stated bound on
// the reference's own error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "path_statistics.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

using glm::dvec3;
using test::PixelStatistics;
using test::render_statistics;

constexpr double kPi = std::numbers::pi;
constexpr double kAlbedo = 0.5;
constexpr LightStrategy kStrategies[] = {LightStrategy::kMis, LightStrategy::kLight,
                                         LightStrategy::kBsdf};
const char* strategy_name(LightStrategy s) {
  return s == LightStrategy::kMis ? "mis" : s == LightStrategy::kLight ? "light" : "bsdf";
}

// A Lambertian plane y = 0 seen from the side, lit only by `lights` (no environment).
SceneDescription plane_scene(std::vector<LightDesc> lights) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.6, 2.5};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 20.0;  // every pixel sees the plane
  MaterialDesc plane;
  plane.name = "plane";
  plane.albedo = dvec3(kAlbedo);
  scene.materials = {plane};
  scene.quads.push_back(
      QuadDesc{.corner = {-10, 0, -10}, .u = {20, 0, 0}, .v = {0, 0, 20}, .material = 0});
  scene.lights = std::move(lights);
  scene.render.width = 24;
  scene.render.height = 24;
  scene.render.max_depth = 2;  // direct light only
  scene.render.seed = 11;
  return scene;
}

// Each pixel's expected radiance a / pi * E(p), averaged over a 2 x 2 grid of the pixel's
// footprint, the plane point found in double from the renderer's camera ray.
std::vector<double> expected_plane_radiance(const SceneDescription& scene,
                                            const std::function<double(const dvec3&)>& irradiance) {
  const Camera camera =
      Camera::from_description(scene.camera, scene.render.width, scene.render.height);
  std::vector<double> out;
  for (std::uint32_t y = 0; y < scene.render.height; ++y)
    for (std::uint32_t x = 0; x < scene.render.width; ++x) {
      double sum = 0.0;
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          const Ray ray = camera.generate(static_cast<float>(x) + (i + 0.5f) / 2.0f,
                                          static_cast<float>(y) + (j + 0.5f) / 2.0f);
          const dvec3 o(ray.origin), d(ray.direction);
          sum += kAlbedo / kPi * irradiance(o - (o.y / d.y) * d);
        }
      out.push_back(sum / 4.0);
    }
  return out;
}

// The image and each quadrant within 4 standard errors of the expected mean, plus
// `reference_error` of it for the reference (the 2 x 2 footprint average's second-order
// error where E varies smoothly; more where a spot's edge crosses a pixel).
void expect_matches(const PixelStatistics& image, const std::vector<double>& expected,
                    const std::string& what, double reference_error) {
  const std::uint32_t w = image.width, h = image.height;
  const std::uint32_t regions[][4] = {{0, 0, w, h},
                                      {0, 0, w / 2, h / 2},
                                      {w / 2, 0, w, h / 2},
                                      {0, h / 2, w / 2, h},
                                      {w / 2, h / 2, w, h}};
  for (const auto& r : regions) {
    double diff = 0.0, variance = 0.0, reference = 0.0, n = 0.0;
    for (std::uint32_t y = r[1]; y < r[3]; ++y)
      for (std::uint32_t x = r[0]; x < r[2]; ++x) {
        diff += image.at(x, y) - expected[y * w + x];
        variance += image.variance_of_mean[y * w + x];
        reference += expected[y * w + x];
        n += 1.0;
      }
    diff /= n;
    reference /= n;
    const double sigma = std::sqrt(variance) / n;
    if (r[2] == w && r[0] == 0 && r[3] == h && r[1] == 0)
      std::printf("[lights] %-26s mean %.5f expected %.5f: error %+.2e = %+.2f sigma\n",
                  what.c_str(), reference + diff, reference, diff / reference,
                  sigma > 0.0 ? diff / sigma : 0.0);
    EXPECT_LT(std::fabs(diff), 4.0 * sigma + reference_error * reference)
        << what << " region (" << r[0] << ", " << r[1] << "): mean " << reference + diff
        << ", expected " << reference << ", sigma " << sigma;
  }
  EXPECT_EQ(image.dropped, 0u) << what;
}

void check_plane(const std::string& name, const SceneDescription& scene,
                 const std::function<double(const dvec3&)>& irradiance, double reference_error,
                 std::uint32_t spp) {
  const auto prepared = PreparedScene::build(scene);
  const std::vector<double> expected = expected_plane_radiance(scene, irradiance);
  for (LightStrategy strategy : kStrategies) {
    const PixelStatistics image = render_statistics(*prepared, strategy, spp);
    expect_matches(image, expected, name + " " + strategy_name(strategy), reference_error);
  }
}

const dvec3 kLightPosition(0.1, 1.0, -0.2);

// E = I cos(theta) / r^2 = I h / r^3 from a point light of intensity I; radiance a / pi E.
// The 2 x 2 footprint average is good to < 1e-4 here (E changes < 2% across a pixel).
TEST(AnalyticLightRender, PointLightOnAPlaneMatchesTheClosedForm) {
  constexpr double kIntensity = 3.0;
  const SceneDescription scene = plane_scene(
      {LightDesc{.type = "point", .position = kLightPosition, .intensity = kIntensity}});
  check_plane(
      "point", scene,
      [&](const dvec3& p) {
        const dvec3 d = kLightPosition - p;
        const double r = glm::length(d);
        return kIntensity * d.y / (r * r * r);
      },
      2e-4, 8);
}

// A spot pointing straight down with a 25 degree cone and a 10 degree falloff: E = I
// falloff(cos) h / r^3, falloff the smoothstep in cos between the cone's edge and 15
// degrees. The edge crosses pixels where E bends sharply: the footprint average is then
// good to ~2e-3 of the image mean.
TEST(AnalyticLightRender, SpotFalloffMatchesItsFormula) {
  constexpr double kIntensity = 4.0;
  constexpr double kCone = 25.0, kFalloff = 10.0;
  const SceneDescription scene = plane_scene({LightDesc{.type = "spot",
                                                        .position = kLightPosition,
                                                        .direction = {0, -1, 0},
                                                        .intensity = kIntensity,
                                                        .cone_angle_degrees = kCone,
                                                        .cone_falloff_degrees = kFalloff}});
  const double cos_outer = std::cos(kCone * kPi / 180.0);
  const double cos_inner = std::cos((kCone - kFalloff) * kPi / 180.0);
  check_plane(
      "spot", scene,
      [&](const dvec3& p) {
        const dvec3 d = kLightPosition - p;
        const double r = glm::length(d);
        const double c =
            d.y / r;  // the angle to the axis (straight down) is the angle to the normal
        const double t = std::clamp((c - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
        return kIntensity * t * t * (3.0 - 2.0 * t) * d.y / (r * r * r);
      },
      5e-3, 8);
}

// A sun of irradiance E at 30 degrees from the zenith lights the plane with E cos(30
// degrees) everywhere: as a delta direction, and with a 6 degree angular radius (a cone
// wholly above the horizon gives the same E cos(theta), by symmetry about its axis), whose
// escaping BSDF samples the miss program weighs against light sampling.
TEST(AnalyticLightRender, SunIrradianceOnAPlaneIsItsValueTimesCos) {
  constexpr double kIrradiance = 2.0;
  const double theta = 30.0 * kPi / 180.0;
  const dvec3 travel(std::sin(theta), -std::cos(theta), 0.0);
  for (double radius : {0.0, 6.0}) {
    const SceneDescription scene = plane_scene({LightDesc{.type = "sun",
                                                          .direction = travel,
                                                          .irradiance = kIrradiance,
                                                          .angular_radius_degrees = radius}});
    check_plane(
        "sun radius " + std::to_string(static_cast<int>(radius)), scene,
        [&](const dvec3&) { return kIrradiance * std::cos(theta); }, 1e-5, radius > 0.0 ? 64 : 4);
  }
}

// White furnace: a white (albedo 1) Lambertian sphere under a constant environment of
// radiance 1 reflects exactly 1 everywhere, as every escaping camera ray sees: each pixel
// within 5 of its standard errors, the image mean within 4 (plus 1e-4 of float rounding).
TEST(AnalyticLightRender, WhiteFurnaceUnderAConstantEnvironmentIsOne) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  MaterialDesc white;
  white.name = "white";
  white.albedo = dvec3(1.0);
  scene.materials = {white};
  scene.spheres.push_back(SphereDesc{.center = {0.2, -0.1, 0.0}, .radius = 1.0, .material = 0});
  scene.environment = EnvironmentDesc{.type = "constant", .color = dvec3(1.0), .intensity = 1.0};
  scene.render.width = 20;
  scene.render.height = 20;
  scene.render.max_depth = 8;
  const auto prepared = PreparedScene::build(scene);
  EXPECT_EQ(prepared->view().light_count, 1u);  // the environment, sampled
  for (LightStrategy strategy : kStrategies) {
    const PixelStatistics image = render_statistics(*prepared, strategy, 64);
    double sum = 0.0, variance = 0.0;
    int noisy = 0;
    for (std::size_t i = 0; i < image.mean.size(); ++i) {
      const double sigma = std::sqrt(image.variance_of_mean[i]);
      EXPECT_LT(std::fabs(image.mean[i] - 1.0), 5.0 * sigma + 1e-4)
          << strategy_name(strategy) << " pixel " << i << " sigma " << sigma;
      sum += image.mean[i];
      variance += image.variance_of_mean[i];
      if (sigma > 0.0) ++noisy;
    }
    const double n = static_cast<double>(image.mean.size());
    std::printf("[furnace env] %-6s image mean %.6f (sigma %.1e)\n", strategy_name(strategy),
                sum / n, std::sqrt(variance) / n);
    EXPECT_LT(std::fabs(sum / n - 1.0), 4.0 * std::sqrt(variance) / n + 1e-4);
    // Light sampling is noisy on the object, so the object is in view; BSDF sampling of a
    // white Lambertian under radiance 1 is exactly 1 per sample.
    if (strategy != LightStrategy::kBsdf) {
      EXPECT_GT(noisy, 30);
    }
  }
}

// RayON's sky: t = (y + 1) / 2 of the unit direction blends white into (0.5, 0.7, 1.0),
// times the intensity. A camera ray straight up sees (0.5, 0.7, 1.0) x intensity, a
// horizontal one the midpoint (0.75, 0.85, 1.0) x intensity.
TEST(AnalyticLightRender, GradientEnvironmentIsRayonsSky) {
  constexpr double kIntensity = 0.18;
  const auto render_looking = [&](const dvec3& direction, const dvec3& up) {
    SceneDescription scene;
    scene.camera.position = {0.0, 0.0, 0.0};
    scene.camera.look_at = direction;
    scene.camera.up = up;
    scene.camera.fov_degrees = 0.01;  // every ray within 1e-4 of the axis
    scene.environment = EnvironmentDesc{.type = "gradient", .intensity = kIntensity};
    scene.render.width = 4;
    scene.render.height = 4;
    scene.render.samples_per_pixel = 4;
    return render_image(*PreparedScene::build(scene));
  };
  const auto expect_pixel = [&](const auto& image, const dvec3& colour) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(image[4 * (2 * 4 + 2) + c], colour[c] * kIntensity, 1e-5) << c;
  };
  expect_pixel(render_looking({0, 1, 0}, {0, 0, 1}), dvec3(0.5, 0.7, 1.0));
  expect_pixel(render_looking({1, 0, 0}, {0, 1, 0}), dvec3(0.75, 0.85, 1.0));
  expect_pixel(render_looking({0, -1, 0}, {0, 0, 1}), dvec3(1.0, 1.0, 1.0));
}

}  // namespace
}  // namespace tessera
