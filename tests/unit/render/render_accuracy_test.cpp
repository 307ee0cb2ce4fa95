// The path tracer against analytic answers: direct irradiance from sphere, disk and
// rectangle emitters on a Lambertian plane (hidden emitters included), and a white furnace,
// each under every LightStrategy. Tolerances are in standard errors measured from the
// per-pixel sample variance (path_statistics.hpp), plus a stated bound on the reference's
// own error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "path_statistics.hpp"
#include "scene_materials.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

using glm::dvec3;
using test::PixelStatistics;
using test::render_statistics;

constexpr double kPi = std::numbers::pi;
constexpr double kAlbedo = 0.5;    // the plane's
constexpr double kRadiance = 4.0;  // every emitter's
constexpr LightStrategy kStrategies[] = {LightStrategy::kMis, LightStrategy::kLight,
                                         LightStrategy::kBsdf};

const char* strategy_name(LightStrategy s) {
  switch (s) {
    case LightStrategy::kMis:
      return "mis";
    case LightStrategy::kLight:
      return "light";
    case LightStrategy::kBsdf:
      return "bsdf";
  }
  return "?";
}

enum class Emitter { kSphere, kHiddenSphere, kDisk, kRectangle };

// Emitters above the plane y = 0, all facing it: a sphere of radius 0.3 centred 1.2 up
// (it never dips below the horizon of any plane point), a disk of radius 0.35 and a 0.8 x
// 0.6 rectangle, both 1 up and parallel to the plane.
const dvec3 kSphereCentre(0.1, 1.2, -0.1);
constexpr double kSphereRadius = 0.3;
const dvec3 kDiskCentre(0.1, 1.0, -0.1);
constexpr double kDiskRadius = 0.35;
constexpr double kRectX0 = -0.3, kRectX1 = 0.5, kRectZ0 = -0.4, kRectZ1 = 0.2, kRectHeight = 1.0;

// Irradiance at a point of the plane y = 0 (normal +y).
// Sphere: pi L (R / d)^2 cos theta, exact for a point that sees the whole sphere.
double sphere_irradiance(const dvec3& p) {
  const dvec3 d = kSphereCentre - p;
  const double dist = glm::length(d);
  return kPi * kRadiance * (kSphereRadius / dist) * (kSphereRadius / dist) * (d.y / dist);
}

// Rectangle parallel to the plane: the differential-area-to-parallel-rectangle form factor
// for a rectangle with a corner above the point (Howell's catalogue, C-11), combined over
// the four corners with signs; E = pi L F.
double corner_form_factor(double a, double b, double c) {
  const double x = std::fabs(a) / c, y = std::fabs(b) / c;
  const double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  const double f = (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * kPi);
  return (a < 0.0) != (b < 0.0) ? -f : f;
}
double rectangle_irradiance(const dvec3& p) {
  const double x0 = kRectX0 - p.x, x1 = kRectX1 - p.x, z0 = kRectZ0 - p.z, z1 = kRectZ1 - p.z;
  const double h = kRectHeight - p.y;
  const double f = corner_form_factor(x1, z1, h) - corner_form_factor(x0, z1, h) -
                   corner_form_factor(x1, z0, h) + corner_form_factor(x0, z0, h);
  return kPi * kRadiance * f;
}

// Disk parallel to the plane: double-precision midpoint quadrature of L cos cos / r^2 over
// its area in polar coordinates (the integrand is smooth; checked against the on-axis
// closed form pi L R^2 / (h^2 + R^2) below).
double disk_irradiance(const dvec3& p) {
  constexpr int kRings = 64, kSectors = 128;
  const double h = kDiskCentre.y - p.y;
  double sum = 0.0;
  for (int i = 0; i < kRings; ++i) {
    const double rho = (i + 0.5) / kRings * kDiskRadius;
    for (int j = 0; j < kSectors; ++j) {
      const double phi = (j + 0.5) / kSectors * 2.0 * kPi;
      const dvec3 q = kDiskCentre + dvec3(rho * std::cos(phi), 0.0, rho * std::sin(phi));
      const double r2 = glm::dot(q - p, q - p);
      sum += h * h / (r2 * r2) * rho;
    }
  }
  return kRadiance * sum * (kDiskRadius / kRings) * (2.0 * kPi / kSectors);
}

// The references against independent forms: the disk quadrature against the on-axis closed
// form, the signed four-corner rectangle form factor against quadrature off-centre.
TEST(RenderAccuracy, IrradianceReferencesAgreeWithIndependentForms) {
  const dvec3 below(kDiskCentre.x, 0.0, kDiskCentre.z);
  const double h = kDiskCentre.y, r = kDiskRadius;
  const double exact = kPi * kRadiance * r * r / (h * h + r * r);
  EXPECT_NEAR(disk_irradiance(below), exact, 2e-5 * exact);

  const dvec3 p(0.7, 0.0, 0.3);
  constexpr int kN = 400;
  double sum = 0.0;
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) {
      const dvec3 q(kRectX0 + (i + 0.5) / kN * (kRectX1 - kRectX0), kRectHeight,
                    kRectZ0 + (j + 0.5) / kN * (kRectZ1 - kRectZ0));
      const double r2 = glm::dot(q - p, q - p);
      sum += kRectHeight * kRectHeight / (r2 * r2);
    }
  sum *= kRadiance * (kRectX1 - kRectX0) * (kRectZ1 - kRectZ0) / (kN * kN);
  EXPECT_NEAR(rectangle_irradiance(p), sum, 1e-5 * sum);
}

SceneDescription lit_plane_scene(Emitter emitter) {
  SceneDescription scene;
  // Looks down at the plane from the side; the emitters stay above the top of the view.
  scene.camera.position = {0.0, 0.6, 2.5};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 20.0;
  scene.materials = {test::lambertian_material("plane", dvec3(kAlbedo)),
                     test::light_material("light", dvec3(kRadiance))};
  scene.quads.push_back(
      QuadDesc{.corner = {-10, 0, -10}, .u = {20, 0, 0}, .v = {0, 0, 20}, .material = 0});
  switch (emitter) {
    case Emitter::kSphere:
    case Emitter::kHiddenSphere:
      scene.spheres.push_back(SphereDesc{.center = kSphereCentre,
                                         .radius = kSphereRadius,
                                         .material = 1,
                                         .visible = emitter == Emitter::kSphere});
      break;
    case Emitter::kDisk:
      scene.disks.push_back(DiskDesc{
          .center = kDiskCentre, .normal = {0, -1, 0}, .radius = kDiskRadius, .material = 1});
      break;
    case Emitter::kRectangle:
      scene.quads.push_back(QuadDesc{.corner = {kRectX0, kRectHeight, kRectZ0},
                                     .u = {kRectX1 - kRectX0, 0, 0},
                                     .v = {0, 0, kRectZ1 - kRectZ0},
                                     .material = 1});
      break;
  }
  scene.render.width = 24;
  scene.render.height = 24;
  scene.render.max_depth = 2;  // depth 0 hits the plane, depth 1 the light: direct only
  scene.render.seed = 7;
  return scene;
}

// Each pixel's expected value: a / pi * E averaged over a 2 x 2 grid of the pixel's
// footprint (the renderer jitters uniformly over it), the plane point found in double
// from the renderer's own camera ray.
std::vector<double> expected_plane_radiance(const SceneDescription& scene,
                                            double (*irradiance)(const dvec3&)) {
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
          const dvec3 p = o - (o.y / d.y) * d;
          sum += kAlbedo / kPi * irradiance(p);
        }
      out.push_back(sum / 4.0);
    }
  return out;
}

// Compares the image mean and each quadrant's mean with the expected values: within 4
// standard errors (from the per-pixel variances) plus 2e-4 of the expected mean for the
// reference (closed forms exact to rounding; disk quadrature 2e-5; the 2 x 2 footprint
// average: E varies by < 1% across a pixel, so its second-order error is < 1e-5).
void expect_matches(const PixelStatistics& image, const std::vector<double>& expected,
                    const std::string& what) {
  const std::uint32_t w = image.width, h = image.height;
  struct Region {
    const char* name;
    std::uint32_t x0, y0, x1, y1;
  };
  const Region regions[] = {{"image", 0, 0, w, h},
                            {"top left", 0, 0, w / 2, h / 2},
                            {"top right", w / 2, 0, w, h / 2},
                            {"bottom left", 0, h / 2, w / 2, h},
                            {"bottom right", w / 2, h / 2, w, h}};
  for (const Region& r : regions) {
    double diff = 0.0, variance = 0.0, reference = 0.0;
    double n = 0.0;
    for (std::uint32_t y = r.y0; y < r.y1; ++y)
      for (std::uint32_t x = r.x0; x < r.x1; ++x) {
        diff += image.at(x, y) - expected[y * w + x];
        variance += image.variance_of_mean[y * w + x];
        reference += expected[y * w + x];
        n += 1.0;
      }
    diff /= n;
    reference /= n;
    const double sigma = std::sqrt(variance) / n;
    if (std::string(r.name) == "image")
      std::printf("[accuracy] %-28s mean %.5f expected %.5f: error %+.2e = %+.2f sigma\n",
                  what.c_str(), reference + diff, reference, diff / reference, diff / sigma);
    EXPECT_LT(std::fabs(diff), 4.0 * sigma + 2e-4 * reference)
        << what << ", " << r.name << ": mean " << reference + diff << ", expected " << reference
        << ", sigma " << sigma;
  }
  EXPECT_EQ(image.dropped, 0u) << what;
}

struct IrradianceCase {
  std::string name;
  Emitter emitter;
  double (*irradiance)(const dvec3&);
};

void check_irradiance(const IrradianceCase& c) {
  SCOPED_TRACE(c.name);
  const SceneDescription description = lit_plane_scene(c.emitter);
  const auto prepared = PreparedScene::build(description);
  ASSERT_EQ(prepared->required_features().shapes & ~test::kStatisticsFeatures.shapes, 0u);
  const std::vector<double> expected = expected_plane_radiance(description, c.irradiance);
  for (LightStrategy strategy : kStrategies) {
    const PixelStatistics image = render_statistics(*prepared, strategy, 96);
    expect_matches(image, expected, c.name + " " + strategy_name(strategy));
  }
}

// The plane's radiance is a / pi * E under each emitter and each strategy.
TEST(RenderAccuracy, DirectIrradianceFromEachEmitterOnALambertianPlane) {
  const IrradianceCase cases[] = {
      IrradianceCase{"Sphere", Emitter::kSphere, &sphere_irradiance},
      // A hidden emitter (visible: false) lights the plane exactly as a visible
      // one: it once counted twice.
      IrradianceCase{"HiddenSphere", Emitter::kHiddenSphere, &sphere_irradiance},
      IrradianceCase{"Disk", Emitter::kDisk, &disk_irradiance},
      IrradianceCase{"Rectangle", Emitter::kRectangle, &rectangle_irradiance}};
  for (const IrradianceCase& c : cases) check_irradiance(c);
}

// White furnace: a white (albedo 1) Lambertian sphere inside an emitting sphere of radiance
// 1 that encloses it and the camera. The object is convex and loses nothing, so every
// point of it reflects radiance exactly 1, as does every direction that sees the
// enclosure: every pixel is 1. max_depth 8 (a convex object needs 2: one bounce off it,
// then the enclosure). Each pixel within 5 of its own standard errors, the image mean
// within 4 (plus 1e-4 of float rounding).
TEST(RenderAccuracy, WhiteFurnaceIsOneEverywhere) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 40.0;
  MaterialDesc white;
  white.name = "white";
  white.albedo = dvec3(1.0);
  MaterialDesc enclosure;
  enclosure.name = "enclosure";
  enclosure.type = MaterialType::kLight;
  enclosure.emission = dvec3(1.0);
  scene.materials = {white, enclosure};
  scene.spheres.push_back(SphereDesc{.center = {0.2, -0.1, 0.0}, .radius = 1.0, .material = 0});
  scene.spheres.push_back(SphereDesc{.center = {0.0, 0.0, 0.0}, .radius = 10.0, .material = 1});
  scene.render.width = 24;
  scene.render.height = 24;
  scene.render.max_depth = 8;
  const auto prepared = PreparedScene::build(scene);
  for (LightStrategy strategy : kStrategies) {
    const PixelStatistics image = render_statistics(*prepared, strategy, 128);
    double sum = 0.0, variance = 0.0, worst = 0.0;
    int object_pixels = 0;
    for (std::size_t i = 0; i < image.mean.size(); ++i) {
      const double sigma = std::sqrt(image.variance_of_mean[i]);
      EXPECT_LT(std::fabs(image.mean[i] - 1.0), 5.0 * sigma + 1e-4)
          << strategy_name(strategy) << " pixel " << i << " sigma " << sigma;
      sum += image.mean[i];
      variance += image.variance_of_mean[i];
      worst = std::max(worst, std::fabs(image.mean[i] - 1.0));
      if (sigma > 0.0) ++object_pixels;
    }
    const double n = static_cast<double>(image.mean.size());
    std::printf("[furnace] %-6s image mean %.6f (sigma %.1e), worst pixel |error| %.4f\n",
                strategy_name(strategy), sum / n, std::sqrt(variance) / n, worst);
    EXPECT_LT(std::fabs(sum / n - 1.0), 4.0 * std::sqrt(variance) / n + 1e-4);
    // The object fills part of the view (noisy pixels): the test is not all enclosure. Under
    // kBsdf every object sample is exactly 1 (f cos / pdf = 1, the enclosure's radiance),
    // so only the other two strategies are noisy there.
    if (strategy != LightStrategy::kBsdf) {
      EXPECT_GT(object_pixels, 50);
    }
  }
  EXPECT_EQ(prepared->view().light_count, 1u);
}

}  // namespace
}  // namespace tessera
