// Furnace images through the real path tracer: objects of each new material inside an
// emitting sphere of radiance 1 (render_accuracy_test.cpp's WhiteFurnaceIsOneEverywhere,
// with other materials). Lossless materials render exactly 1; lossy ones never more than 1,
// and every light strategy agrees (next-event estimation through rough glass included).
// Tolerances are in standard errors measured per pixel (path_statistics.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "path_statistics.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

using glm::dvec3;
using test::PixelStatistics;
using test::render_statistics;

constexpr LightStrategy kStrategies[] = {LightStrategy::kMis, LightStrategy::kLight,
                                         LightStrategy::kBsdf};

// The object material `m` as a unit sphere (and, for the conductor's anisotropy, a sphere
// whose tangents turn around +y), inside a radius-10 emitter of radiance 1 that also holds
// the camera.
std::shared_ptr<const PreparedScene> furnace(const MaterialDesc& object) {
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 40.0;
  MaterialDesc enclosure;
  enclosure.name = "enclosure";
  enclosure.type = MaterialType::kLight;
  enclosure.emission = dvec3(1.0);
  scene.materials = {object, enclosure};
  scene.spheres.push_back(SphereDesc{.center = {0.2, -0.1, 0.0}, .radius = 1.0, .material = 0});
  scene.spheres.push_back(SphereDesc{.center = {0.0, 0.0, 0.0}, .radius = 10.0, .material = 1});
  scene.render.width = 20;
  scene.render.height = 20;
  scene.render.max_depth = 64;
  return PreparedScene::build(scene);
}

struct ImageSummary {
  double mean = 0.0, sigma = 0.0;
};

ImageSummary summarise(const PixelStatistics& image) {
  ImageSummary s;
  double variance = 0.0;
  for (std::size_t i = 0; i < image.mean.size(); ++i) {
    s.mean += image.mean[i];
    variance += image.variance_of_mean[i];
  }
  const double n = static_cast<double>(image.mean.size());
  s.mean /= n;
  s.sigma = std::sqrt(variance) / n;
  return s;
}

MaterialDesc material(MaterialType type, double roughness) {
  MaterialDesc m;
  m.name = "object";
  m.type = type;
  apply_type_defaults(m);
  m.roughness = roughness;
  return m;
}

// RayON's `glass` with no albedo (the 0.64): lossless, so exactly 1 in every pixel.
// Every sample is exactly 1 (weights 1, radiance 1): the tolerance is float rounding.
TEST(MaterialFurnace, SmoothGlassSphereIsOne) {
  const auto prepared = furnace(material(MaterialType::kGlass, 0.0));
  for (LightStrategy strategy : kStrategies) {
    const PixelStatistics image = render_statistics(*prepared, strategy, 16);
    for (std::size_t i = 0; i < image.mean.size(); ++i)
      ASSERT_NEAR(image.mean[i], 1.0, 1e-4) << "pixel " << i;
    std::printf("[furnace] smooth glass sphere: image mean %.6f\n", summarise(image).mean);
  }
}

// A white mirror (rough_mirror, albedo 1, roughness 0) is lossless too.
TEST(MaterialFurnace, SmoothWhiteConductorSphereIsOne) {
  MaterialDesc m = material(MaterialType::kRoughMirror, 0.0);
  m.albedo = dvec3(1.0);
  const auto prepared = furnace(m);
  const PixelStatistics image = render_statistics(*prepared, LightStrategy::kMis, 16);
  for (std::size_t i = 0; i < image.mean.size(); ++i)
    ASSERT_NEAR(image.mean[i], 1.0, 1e-4) << "pixel " << i;
}

// Rough white GGX conductors (isotropic and anisotropic) and rough glass lose only their
// single-scattering energy: every pixel is at most 1 (within 5 of its standard errors), the
// object darker than 1 on the whole, and the three light strategies agree within 4 combined
// standard errors of the image mean, which checks light sampling and its MIS weights
// (through rough glass as well) against BSDF sampling.
TEST(MaterialFurnace, RoughMaterialsNeverGainAndStrategiesAgree) {
  struct Case {
    std::string name;
    MaterialDesc m;
  };
  MaterialDesc rough_metal = material(MaterialType::kAnisotropicMetal, 0.9);
  MaterialDesc brushed = material(MaterialType::kAnisotropicMetal, 0.6);
  brushed.anisotropy = 0.8;
  MaterialDesc rough_glass = material(MaterialType::kGlass, 0.7);
  for (const Case& c : {Case{"rough metal", rough_metal}, Case{"brushed metal", brushed},
                        Case{"rough glass", rough_glass}}) {
    SCOPED_TRACE(c.name);
    const auto prepared = furnace(c.m);
    ImageSummary by_strategy[3];
    for (int s = 0; s < 3; ++s) {
      const PixelStatistics image = render_statistics(*prepared, kStrategies[s], 128);
      for (std::size_t i = 0; i < image.mean.size(); ++i)
        EXPECT_LT(image.mean[i], 1.0 + 5.0 * std::sqrt(image.variance_of_mean[i]) + 1e-4)
            << "pixel " << i;
      by_strategy[s] = summarise(image);
      std::printf("[furnace] %-13s strategy %d: image mean %.5f (sigma %.1e)\n", c.name.c_str(), s,
                  by_strategy[s].mean, by_strategy[s].sigma);
      EXPECT_LT(by_strategy[s].mean, 1.0);
    }
    for (int s = 1; s < 3; ++s) {
      const double sigma = std::hypot(by_strategy[0].sigma, by_strategy[s].sigma);
      EXPECT_NEAR(by_strategy[s].mean, by_strategy[0].mean, 4.0 * sigma + 1e-4) << s;
    }
  }
}

// Beer's law: glass of index 1 (no interface: no reflection, no bending) that keeps half
// of the light per unit length, a unit sphere seen through its centre. The centre pixel's
// rays cross a chord of 2 sqrt(1 - b^2) for impact parameters b below 0.04 (its footprint
// at the sphere), so the pixel is exp(-2 ln 2) = 0.25 within 0.2%; every sample of it is the
// same up to that spread, so the tolerance is 3e-3 absolute.
TEST(MaterialFurnace, AbsorbingGlassFollowsBeersLaw) {
  MaterialDesc m = material(MaterialType::kGlass, 0.0);
  m.refractive_index = 1.0;
  m.transmittance = dvec3(0.5);
  m.transmittance_distance = 1.0;
  SceneDescription scene;
  scene.camera.position = {0.0, 0.0, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.camera.fov_degrees = 20.0;
  MaterialDesc enclosure;
  enclosure.name = "enclosure";
  enclosure.type = MaterialType::kLight;
  enclosure.emission = dvec3(1.0);
  scene.materials = {m, enclosure};
  scene.spheres.push_back(SphereDesc{.center = {0.0, 0.0, 0.0}, .radius = 1.0, .material = 0});
  scene.spheres.push_back(SphereDesc{.center = {0.0, 0.0, 0.0}, .radius = 10.0, .material = 1});
  scene.render.width = 21;
  scene.render.height = 21;
  scene.render.max_depth = 8;
  const auto prepared = PreparedScene::build(scene);
  const PixelStatistics image = render_statistics(*prepared, LightStrategy::kMis, 16);
  std::printf("[beer] centre pixel %.5f (expected 0.25)\n", image.at(10, 10));
  EXPECT_NEAR(image.at(10, 10), 0.25, 3e-3);
  // Through the rim less is absorbed than through the centre.
  EXPECT_GT(image.at(10, 4), image.at(10, 10));
}

}  // namespace
}  // namespace tessera
