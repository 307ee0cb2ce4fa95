// The camera's projections, thin lens and pixel filters against closed forms: filter
// importance sampling follows the filter's distribution, orthographic rays are parallel,
// and a thin lens keeps its focus plane sharp while an edge off it blurs as wide as the
// circle of confusion predicts.
#include "tessera/render/camera.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "chi2.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

// ---------------------------------------------------------------- pixel filters

TEST(PixelFilter, DefaultBoxLeavesTheSamplePositionAsItWas) {
  const PixelFilter box = PixelFilter::make(PixelFilterKind::kBox);
  for (float u : {0.0f, 0.1f, 0.5f, 0.73f, 0.99999994f}) EXPECT_EQ(box.position(u), u);
}

// Offsets of n stratified uniforms (the sampler's values are uniform), from the pixel centre.
std::vector<double> filter_offsets(const PixelFilter& filter, int n) {
  std::vector<double> offsets(n);
  for (int i = 0; i < n; ++i)
    offsets[i] = filter.position((static_cast<float>(i) + 0.5f) / static_cast<float>(n)) - 0.5;
  return offsets;
}

// The variance of the Gaussian filter's offsets is the truncated normal's: sigma^2 (1 -
// 2 a phi(a) / (2 Phi(a) - 1)) with a = 3 (truncation at 3 sigma), 0.973 sigma^2.
TEST(PixelFilter, GaussianOffsetsHaveTheTruncatedNormalsVariance) {
  for (double width : {1.5, 3.0, 6.0}) {
    const PixelFilter filter = PixelFilter::make(PixelFilterKind::kGaussian, width);
    const std::vector<double> offsets = filter_offsets(filter, 1 << 16);
    double mean = 0.0, square = 0.0;
    for (double x : offsets) {
      mean += x;
      square += x * x;
    }
    mean /= offsets.size();
    const double variance = square / offsets.size() - mean * mean;
    const double sigma = width / 6.0;
    const double a = 3.0;
    const double phi = std::exp(-0.5 * a * a) / std::sqrt(2.0 * std::numbers::pi);
    const double expected = sigma * sigma * (1.0 - 2.0 * a * phi / std::erf(a / std::sqrt(2.0)));
    EXPECT_NEAR(mean, 0.0, 1e-4 * width);
    // The table's density is the filter averaged over cells of width / 128, which adds
    // about cell^2 / 12, 2e-4 of sigma^2.
    EXPECT_NEAR(variance / expected, 1.0, 0.002) << "width " << width;
    EXPECT_LE(*std::max_element(offsets.begin(), offsets.end()), 0.5 * width + 1e-6);
  }
}

// Pearson's chi-square of offsets drawn from a filter against the filter's own shape,
// integrated numerically per bin: p must not be tiny.
double filter_chi2_p_value(PixelFilterKind kind, double width) {
  const PixelFilter filter = PixelFilter::make(kind, width);
  constexpr int kBins = 40;
  constexpr int kSamples = 200000;
  test::UniformFloats uniform(7);
  std::vector<double> counts(kBins, 0.0);
  const double radius = 0.5 * width;
  for (int i = 0; i < kSamples; ++i) {
    const double x = filter.position(uniform()) - 0.5;
    const int bin = std::clamp(static_cast<int>((x + radius) / width * kBins), 0, kBins - 1);
    counts[bin] += 1.0;
  }
  std::vector<double> expected(kBins, 0.0);
  double total = 0.0;
  for (int b = 0; b < kBins; ++b) {
    constexpr int kSteps = 200;
    for (int s = 0; s < kSteps; ++s) {
      const double x = -radius + (b + (s + 0.5) / kSteps) * width / kBins;
      expected[b] += PixelFilter::evaluate(kind, width, x);
    }
    total += expected[b];
  }
  double chi2 = 0.0;
  int dof = -1;
  for (int b = 0; b < kBins; ++b) {
    const double e = expected[b] / total * kSamples;
    if (e < 5.0) continue;
    chi2 += (counts[b] - e) * (counts[b] - e) / e;
    ++dof;
  }
  return test::gamma_q(0.5 * dof, 0.5 * chi2);
}

TEST(PixelFilter, SampledOffsetsFollowTheFilter) {
  EXPECT_GT(filter_chi2_p_value(PixelFilterKind::kBlackmanHarris, 3.0), 1e-3);
  EXPECT_GT(filter_chi2_p_value(PixelFilterKind::kGaussian, 3.0), 1e-3);
  EXPECT_GT(filter_chi2_p_value(PixelFilterKind::kBox, 2.0), 1e-3);
}

// ---------------------------------------------------------------- renders

// A scene seen along -Z from the origin: one white lambertian quad, nothing else (the albedo
// preview needs no light), black background.
SceneDescription quad_scene(const glm::dvec3& corner, const glm::dvec3& u, const glm::dvec3& v) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 0.0};
  scene.camera.look_at = {0.0, 0.0, -1.0};
  scene.camera.up = {0.0, 1.0, 0.0};
  MaterialDesc white;
  white.name = "white";
  white.type = MaterialType::kLambertian;
  white.albedo = glm::dvec3(1.0);
  scene.materials.push_back(white);
  QuadDesc quad;
  quad.material = 0;
  quad.corner = corner;
  quad.u = u;
  quad.v = v;
  scene.quads.push_back(quad);
  return scene;
}

// The beauty of a whole image rendered as one tile.
std::vector<float> render_image(const SceneDescription& scene) {
  const auto prepared = PreparedScene::build(scene);
  TilePasses passes;
  prepared->render_tile(TileRect{0, 0, 0, scene.render.width, scene.render.height}, passes);
  return passes.beauty;
}

// Orthographic rays are parallel: a square's image has the same size wherever it stands,
// and that size is its side over the ortho height, in image heights.
TEST(Camera, AFarCameraAimsItsRaysAsTheSameCameraAtTheOrigin) {
  // RayON's colour-bleed box scaled by 1,000 puts the eye at (0, 1100, 5200). The image
  // plane corner was a world position there, and subtracting the eye from it left its ulp
  // (5e-4) in a direction of length ~1: every ray 5e-4 rad off, 6% of a pixel, which moved
  // the light's edges by a pixel row in one sample of 17. Directions must not depend on
  // where the camera is: the same camera at the origin and moved out agree to float
  // precision (a few ulps of a unit vector, 1e-6 allowed).
  for (double distance : {5200.0, 1e5}) {
    const glm::dvec3 out{0.0, distance * 0.2, distance};
    CameraDesc near_origin;
    near_origin.position = {0.0, 0.1, 0.2};
    near_origin.look_at = {0.0, 0.0, -5.0};
    CameraDesc far = near_origin;
    far.position += out;
    far.look_at += out;
    const Camera a = Camera::from_description(near_origin, 96, 96);
    const Camera b = Camera::from_description(far, 96, 96);
    double worst = 0.0;
    for (float px : {0.0f, 13.25f, 48.0f, 95.5f})
      for (float py : {0.0f, 15.125f, 60.0f, 96.0f})
        worst = std::max<double>(
            worst, glm::length(a.generate(px, py).direction - b.generate(px, py).direction));
    EXPECT_LT(worst, 1e-6) << "camera " << distance << " units out";
    // A thin lens focused 5 units away: the lens point and the focus point, taken as world
    // positions, cancelled the same way (1e5 units out their ulp is 8e-3).
    near_origin.aperture_radius = 0.05;
    far.aperture_radius = 0.05;
    const Camera lens_a = Camera::from_description(near_origin, 96, 96);
    const Camera lens_b = Camera::from_description(far, 96, 96);
    double lens_worst = 0.0;
    for (float u : {0.1f, 0.5f, 0.93f})
      for (float v : {0.2f, 0.77f})
        lens_worst = std::max<double>(lens_worst,
                                      glm::length(lens_a.generate(13.25f, 60.0f, u, v).direction -
                                                  lens_b.generate(13.25f, 60.0f, u, v).direction));
    EXPECT_LT(lens_worst, 1e-6) << "thin lens " << distance << " units out";
  }
}

TEST(Camera, OrthographicImageSizeDoesNotDependOnDistance) {
  const CameraDesc desc{.position = {1.0, 2.0, 3.0},
                        .look_at = {1.0, 2.0, -7.0},
                        .up = {0.0, 1.0, 0.0},
                        .projection = "orthographic",
                        .ortho_height = 4.0};
  const Camera camera = Camera::from_description(desc, 64, 48);
  for (float px : {0.0f, 17.5f, 64.0f})
    for (float py : {0.0f, 30.25f, 48.0f}) {
      const Ray ray = camera.generate(px, py);
      EXPECT_NEAR(glm::length(ray.direction - vec3(0.0f, 0.0f, -1.0f)), 0.0f, 1e-6f);
      EXPECT_NEAR(ray.origin.z, 3.0f, 1e-5f);
    }
  EXPECT_NEAR(camera.generate(0.0f, 0.0f).origin.y - camera.generate(0.0f, 48.0f).origin.y, 4.0f,
              1e-5f);

  std::vector<double> areas;
  for (double depth : {2.0, 20.0}) {
    SceneDescription scene = quad_scene({-0.5, -0.5, -depth}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
    scene.camera.projection = "orthographic";
    scene.camera.ortho_height = 4.0;
    scene.render.width = 48;
    scene.render.height = 48;
    scene.render.samples_per_pixel = 16;
    scene.render.integrator = IntegratorKind::kAlbedo;
    const std::vector<float> image = render_image(scene);
    double covered = 0.0;  // alpha: the share of each pixel the square covers
    for (std::size_t i = 3; i < image.size(); i += 4) covered += image[i];
    areas.push_back(covered);
  }
  const double expected = (48.0 / 4.0) * (48.0 / 4.0);  // a 1 x 1 square at 12 px per unit
  EXPECT_NEAR(areas[0], expected, 0.01 * expected);
  EXPECT_NEAR(areas[1], expected, 0.01 * expected);
}

// The edge spread of a uniform disc of radius r at offset x from the edge: the share of the
// disc on the near side (the CDF of the semicircle distribution).
double disc_edge_spread(double x, double r) {
  if (r <= 0.0) return x >= 0.0 ? 1.0 : 0.0;
  const double t = std::clamp(x / r, -1.0, 1.0);
  return 0.5 + (t * std::sqrt(1.0 - t * t) + std::asin(t)) / std::numbers::pi;
}

// Columns, with sub-pixel interpolation, where a rising profile crosses 10% and 90%: the
// edge's 10-90% width.
double width_10_90(const std::vector<double>& profile) {
  const auto crossing = [&](double level) {
    for (std::size_t i = 1; i < profile.size(); ++i)
      if (profile[i - 1] < level && profile[i] >= level)
        return static_cast<double>(i - 1) +
               (level - profile[i - 1]) / (profile[i] - profile[i - 1]);
    return -1.0;
  };
  return crossing(0.9) - crossing(0.1);
}

// A thin lens focused at distance f renders an edge at depth z blurred by a disc whose
// radius on the image plane (at distance 1) is A |1/z - 1/f| (A: aperture radius): the lens
// point a shifts the image of a point at depth z by a (1/z - 1/f). The measured 10-90% width
// of the edge matches the disc's edge spread integrated over the pixel (the box filter),
// within 5% + 0.25 px; in focus the edge stays within a pixel.
TEST(Camera, ThinLensBlursAnEdgeAsTheCircleOfConfusionPredicts) {
  constexpr std::uint32_t kWidth = 160, kHeight = 24;
  constexpr double kFov = 30.0, kAperture = 1.0, kFocus = 4.0;
  const double pixels_per_unit = kHeight / (2.0 * std::tan(kFov * std::numbers::pi / 360.0));
  std::vector<double> measured_widths;
  for (double depth : {4.0, 2.5, 8.0}) {
    // The quad covers x >= 0 at depth `depth`: the edge runs down the image's middle.
    SceneDescription scene = quad_scene({0.0, -50.0, -depth}, {100.0, 0.0, 0.0}, {0.0, 100.0, 0.0});
    scene.camera.fov_degrees = kFov;
    scene.camera.aperture_radius = kAperture;
    scene.camera.focus_distance = kFocus;
    scene.render.width = kWidth;
    scene.render.height = kHeight;
    scene.render.samples_per_pixel = 64;
    scene.render.integrator = IntegratorKind::kAlbedo;
    const std::vector<float> image = render_image(scene);
    std::vector<double> profile(kWidth, 0.0);
    for (std::uint32_t y = 0; y < kHeight; ++y)
      for (std::uint32_t x = 0; x < kWidth; ++x)
        profile[x] += image[(y * kWidth + x) * 4] / static_cast<double>(kHeight);

    const double radius = kAperture * std::fabs(1.0 / depth - 1.0 / kFocus) * pixels_per_unit;
    std::vector<double> expected(kWidth, 0.0);
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      constexpr int kSteps = 64;  // the box filter: the spread averaged over the pixel
      for (int s = 0; s < kSteps; ++s)
        expected[x] += disc_edge_spread(x + (s + 0.5) / kSteps - 0.5 * kWidth, radius) / kSteps;
    }
    const double measured = width_10_90(profile);
    const double predicted = width_10_90(expected);
    SCOPED_TRACE("depth " + std::to_string(depth) + ": disc radius " + std::to_string(radius) +
                 " px, 10-90% width measured " + std::to_string(measured) + " predicted " +
                 std::to_string(predicted));
    RecordProperty("width_10_90_at_depth_" + std::to_string(static_cast<int>(depth * 10)),
                   std::to_string(measured) + " px measured, " + std::to_string(predicted) +
                       " px predicted (disc radius " + std::to_string(radius) + " px)");
    ASSERT_GT(measured, 0.0);
    EXPECT_NEAR(measured, predicted, 0.05 * predicted + 0.25);
    if (depth == kFocus) {
      EXPECT_LT(measured, 1.0);
    }
    measured_widths.push_back(measured);
  }
  // Blur grows with the distance from the focus plane (in 1/z): 2.5 is further than 8.
  EXPECT_GT(measured_widths[1], 4.0 * measured_widths[0]);
  EXPECT_GT(measured_widths[1], measured_widths[2]);
}

// The camera matrices of the EXR header agree with the rays: the point a pixel's ray
// reaches projects to that pixel's screen and NDC positions, for both projections.
TEST(Camera, MatricesMapWhatARayReachesToItsPixel) {
  for (const char* projection : {"perspective", "orthographic"}) {
    const CameraDesc desc{.position = {1.0, 2.0, 3.0},
                          .look_at = {-2.0, 0.5, -4.0},
                          .up = {0.0, 1.0, 0.0},
                          .fov_degrees = 50.0,
                          .projection = projection};
    const std::uint32_t width = 80, height = 50;
    const Camera camera = Camera::from_description(desc, width, height);
    const CameraMatrices m = camera_matrices(desc, width, height);
    for (float px : {0.0f, 20.5f, 80.0f})
      for (float py : {0.0f, 37.0f, 50.0f}) {
        const Ray ray = camera.generate(px, py);
        const glm::dvec3 point = glm::dvec3(ray.origin) + 6.0 * glm::dvec3(ray.direction);
        const glm::dvec4 clip = m.world_to_screen * glm::dvec4(point, 1.0);
        EXPECT_NEAR(clip.x / clip.w, 2.0 * px / width - 1.0, 1e-4) << projection;
        EXPECT_NEAR(clip.y / clip.w, 1.0 - 2.0 * py / height, 1e-4) << projection;
        const glm::dvec4 ndc = m.world_to_ndc * glm::dvec4(point, 1.0);
        EXPECT_NEAR(ndc.x / ndc.w, px / width, 1e-4) << projection;
        EXPECT_NEAR(ndc.y / ndc.w, py / height, 1e-4) << projection;
        const glm::dvec4 in_camera = m.world_to_camera * glm::dvec4(point, 1.0);
        EXPECT_LT(in_camera.z, 0.0) << "the camera looks down -Z";
      }
  }
}

}  // namespace
}  // namespace tessera
