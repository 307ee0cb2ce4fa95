// The three LightStrategy values estimate the same image: a closed box lit by a small and a
// large area light and a sphere light, with diffuse, coated and rough metal surfaces and
// indirect light (max_depth 5), rendered with kMis, kLight and kBsdf from independent seeds.
// Also: the same scene renders bit for bit the same whatever the tile size.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "path_statistics.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

using glm::dvec3;
using test::PixelStatistics;

SceneDescription lit_box() {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 3.3};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 40.0;
  const auto material = [&](const char* name, MaterialType type, dvec3 albedo,
                            dvec3 emission = dvec3(0.0), double roughness = 0.0) {
    MaterialDesc m;
    m.name = name;
    m.type = type;
    m.albedo = albedo;
    m.emission = emission;
    m.roughness = roughness;
    scene.materials.push_back(m);
    return static_cast<std::uint32_t>(scene.materials.size() - 1);
  };
  const auto white = material("white", MaterialType::kLambertian, dvec3(0.7));
  const auto red = material("red", MaterialType::kLambertian, dvec3(0.7, 0.2, 0.2));
  const auto small_light = material("small", MaterialType::kLight, dvec3(0), dvec3(40.0));
  const auto large_light = material("large", MaterialType::kLight, dvec3(0), dvec3(0.8));
  const auto sphere_light = material("bulb", MaterialType::kLight, dvec3(0), dvec3(6.0));
  const auto coat = material("coat", MaterialType::kClearCoat, dvec3(0.3, 0.5, 0.7), {}, 0.15);
  const auto metal = material("metal", MaterialType::kMetal, dvec3(0.9), {}, 0.3);
  // The box [-1, 1]^3, open towards the camera (+z).
  const auto quad = [&](dvec3 corner, dvec3 u, dvec3 v, std::uint32_t m) {
    scene.quads.push_back(QuadDesc{.corner = corner, .u = u, .v = v, .material = m});
  };
  quad({-1, -1, -1}, {2, 0, 0}, {0, 0, 2}, white);  // floor
  quad({-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, white);   // ceiling
  quad({-1, -1, -1}, {2, 0, 0}, {0, 2, 0}, white);  // back
  quad({-1, -1, -1}, {0, 2, 0}, {0, 0, 2}, red);    // left
  quad({1, -1, -1}, {0, 2, 0}, {0, 0, 2}, white);   // right
  quad({-0.1, 0.99, -0.3}, {0.2, 0, 0}, {0, 0, 0.2}, small_light);
  quad({-0.5, -0.4, -0.99}, {1.0, 0, 0}, {0, 0.9, 0}, large_light);
  scene.spheres.push_back(
      SphereDesc{.center = {0.6, -0.75, 0.3}, .radius = 0.12, .material = sphere_light});
  scene.spheres.push_back(
      SphereDesc{.center = {-0.45, -0.6, -0.2}, .radius = 0.4, .material = coat});
  scene.disks.push_back(DiskDesc{
      .center = {0.3, -0.99, -0.4}, .normal = {0, 1, 0}, .radius = 0.35, .material = metal});
  scene.render.width = 32;
  scene.render.height = 32;
  scene.render.max_depth = 5;
  return scene;
}

const char* name(LightStrategy s) {
  return s == LightStrategy::kMis ? "mis" : s == LightStrategy::kLight ? "light" : "bsdf";
}

// Every pair of strategies agrees on the image mean and on each 8 x 8 block's mean within
// 4.5 combined standard errors (sqrt(var_a + var_b), from per-pixel sample variances;
// independent seeds). 17 regions x 3 pairs: a false failure has probability ~4e-4.
void expect_strategies_agree(const SceneDescription& scene, std::uint32_t lights) {
  const auto prepared = PreparedScene::build(scene);
  ASSERT_EQ(prepared->required_features().shapes & ~test::kStatisticsFeatures.shapes, 0u);
  ASSERT_EQ(prepared->view().light_count, lights);
  constexpr std::uint32_t kSpp = 384;
  const LightStrategy strategies[] = {LightStrategy::kMis, LightStrategy::kLight,
                                      LightStrategy::kBsdf};
  PixelStatistics images[3];
  for (int i = 0; i < 3; ++i) {
    images[i] = test::render_statistics(*prepared, strategies[i], kSpp, 100 + i);
    EXPECT_EQ(images[i].dropped, 0u) << name(strategies[i]);
  }
  const std::uint32_t w = images[0].width, h = images[0].height;
  const auto region_mean = [&](const PixelStatistics& image, std::uint32_t x0, std::uint32_t y0,
                               std::uint32_t x1, std::uint32_t y1, double& variance) {
    double sum = 0.0, n = 0.0;
    variance = 0.0;
    for (std::uint32_t y = y0; y < y1; ++y)
      for (std::uint32_t x = x0; x < x1; ++x) {
        sum += image.at(x, y);
        variance += image.variance_of_mean[y * w + x];
        n += 1.0;
      }
    variance /= n * n;
    return sum / n;
  };
  double worst = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      for (int region = -1; region < 16; ++region) {
        std::uint32_t x0 = 0, y0 = 0, x1 = w, y1 = h;
        if (region >= 0) {
          x0 = (region % 4) * w / 4;
          y0 = (region / 4) * h / 4;
          x1 = x0 + w / 4;
          y1 = y0 + h / 4;
        }
        double va = 0.0, vb = 0.0;
        const double ma = region_mean(images[a], x0, y0, x1, y1, va);
        const double mb = region_mean(images[b], x0, y0, x1, y1, vb);
        const double sigma = std::sqrt(va + vb);
        worst = std::max(worst, std::fabs(ma - mb) / sigma);
        if (region < 0)
          std::printf("[strategies] image mean %s %.5f (sigma %.1e), %s %.5f (sigma %.1e)\n",
                      name(strategies[a]), ma, std::sqrt(va), name(strategies[b]), mb,
                      std::sqrt(vb));
        EXPECT_LT(std::fabs(ma - mb), 4.5 * sigma)
            << name(strategies[a]) << " " << ma << " against " << name(strategies[b]) << " " << mb
            << " in region " << region << " (-1: whole image), sigma " << sigma;
      }
    }
  std::printf("[strategies] largest difference %.2f sigma\n", worst);
}

TEST(LightStrategies, AgreeOnEveryRegionOfALitBox) {
  expect_strategies_agree(lit_box(), 3);
}

// The same box lit only by an emitting capped cylinder and an open cone frustum (area
// samplers over the wall and the caps): light sampling alone must find what BSDF sampling
// alone finds by hitting them.
TEST(LightStrategies, AgreeWithCylinderAndConeLights) {
  SceneDescription scene = lit_box();
  scene.quads.resize(5);                       // the box without its two rectangle lights
  scene.spheres.erase(scene.spheres.begin());  // nor the sphere light
  const auto tube = static_cast<std::uint32_t>(scene.materials.size());
  MaterialDesc glow;
  glow.name = "tube";
  glow.type = MaterialType::kLight;
  glow.emission = dvec3(3.0, 2.5, 2.0);
  scene.materials.push_back(glow);
  CylinderDesc cylinder;
  cylinder.base = {-0.7, 0.6, -0.6};
  cylinder.axis = {1.0, 0.2, 0.3};
  cylinder.radius = 0.06;
  cylinder.height = 0.8;
  cylinder.caps = true;
  cylinder.material = tube;
  scene.cylinders.push_back(cylinder);
  ConeDesc cone;
  cone.base = {0.5, -0.2, -0.7};
  cone.axis = {0.0, 1.0, 0.2};
  cone.base_radius = 0.2;
  cone.top_radius = 0.05;
  cone.height = 0.4;
  cone.caps = false;
  cone.material = tube;
  scene.cones.push_back(cone);
  expect_strategies_agree(scene, 2);
}

// Soap bubbles and a film sheet between the lights and the box: light sampling's shadow
// rays cross the films (times 1 - R of each), BSDF sampling's paths pass straight through
// them; both must find the same light. Three sheets cover the ceiling light, a bubble
// encloses the sphere light, another floats in the middle.
TEST(LightStrategies, AgreeThroughThinFilms) {
  SceneDescription scene = lit_box();
  const auto film = static_cast<std::uint32_t>(scene.materials.size());
  MaterialDesc bubble;
  bubble.name = "bubble";
  bubble.type = MaterialType::kThinFilm;
  bubble.film_thickness = 380.0;
  bubble.film_ior = 2.4;  // reflects 20-50%: a transmittance off by R shows
  bubble.refractive_index = 1.0;
  scene.materials.push_back(bubble);
  for (const double y : {0.9, 0.8, 0.7})
    scene.quads.push_back(
        QuadDesc{.corner = {-0.3, y, -0.5}, .u = {0.6, 0, 0}, .v = {0, 0, 0.6}, .material = film});
  scene.spheres.push_back(SphereDesc{.center = {0.6, -0.75, 0.3}, .radius = 0.2, .material = film});
  scene.spheres.push_back(SphereDesc{.center = {0.2, 0.1, -0.2}, .radius = 0.3, .material = film});
  expect_strategies_agree(scene, 3);
}

// A point light and a spot beside the box's lights: they are sampled at every vertex, the
// others picked, and light sampling alone, BSDF sampling alone (which still takes the delta
// lights by light sampling) and MIS agree.
TEST(LightStrategies, AgreeWithDeltaLightsSampledAtEveryVertex) {
  SceneDescription scene = lit_box();
  scene.lights.push_back(LightDesc{
      .type = "point", .position = {0.5, 0.6, 0.2}, .color = {1.0, 0.8, 0.6}, .intensity = 0.3});
  scene.lights.push_back(LightDesc{.type = "spot",
                                   .position = {-0.6, 0.8, 0.5},
                                   .direction = {0.3, -1.0, -0.4},
                                   .intensity = 0.8,
                                   .cone_angle_degrees = 35.0,
                                   .cone_falloff_degrees = 10.0});
  expect_strategies_agree(scene, 5);
}

// Determinism with every light type and the glossy materials: tile sizes 8 and 13 give the
// same image bit for bit (the Cornell test in render_determinism_test.cpp has quad lights
// and Lambertian walls only).
TEST(LightStrategies, LitBoxIsTheSameForAnyTileSize) {
  SceneDescription a = lit_box(), b = lit_box();
  a.render.samples_per_pixel = b.render.samples_per_pixel = 4;
  a.render.tile_size = 8;
  b.render.tile_size = 13;
  const auto image_a = render_image(*PreparedScene::build(a));
  const auto image_b = render_image(*PreparedScene::build(b));
  ASSERT_EQ(image_a.size(), image_b.size());
  for (std::size_t i = 0; i < image_a.size(); ++i) ASSERT_EQ(image_a[i], image_b[i]) << i;
  double sum = 0.0;
  for (std::size_t i = 0; i < image_a.size(); i += 4) sum += image_a[i];
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace tessera
