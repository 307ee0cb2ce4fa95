// Regression references for every material: a small render of each (a sphere of the
// material over a ground, lit by a rectangle light and a gradient sky) against a stored
// reference EXR (tests/data/material_references/NAME.exr: the mean of 16 seeds x 2048 spp
// and the variance of that mean, channels R, G, B, Variance.R/G/B).
//
// The test renders 8 seeds x 128 spp and takes the variance of their mean from the spread
// between seeds (or from the reference's variance scaled to the test's sample count, when
// that is larger). Tolerance, per pixel and channel: z = (test - reference) /
// sqrt(var_test + var_ref + floor^2), floor = 1e-4 (1 + |reference|) for deterministic pixels.
// With 7 degrees of freedom in var_test, |z| > 5 has probability about 0.2%; the test fails
// when more than 1% of the values exceed it, or when an image's mean in any channel is more
// than 5 standard errors from the reference's. A change that alters a material's look fails
// here; when the change is intended, regenerate with
//   TESSERA_UPDATE_MATERIAL_REFERENCES=1 build/tests/unit_render
//   --gtest_filter='MaterialReference*'
// and say why in the commit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tessera/image/exr.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kWidth = 32, kHeight = 24;
// Samples per pixel behind the reference (16 seeds x 2048) over the test's (8 x 128).
constexpr double kSampleRatio = (16.0 * 2048.0) / (8.0 * 128.0);

struct MaterialCase {
  const char* name;
  const char* yaml;  // the material's fields after `name: probe`
};

const MaterialCase kCases[] = {
    {"lambertian", "type: lambertian, albedo: [0.7, 0.45, 0.3]"},
    {"metal_gold", "type: metal, preset: gold, roughness: 0.3"},
    {"metal_rayon", "type: metal, albedo: [0.8, 0.8, 0.9], roughness: 0.15"},
    {"rough_mirror", "type: rough_mirror, albedo: 0.9, roughness: 0.05"},
    {"anisotropic_metal",
     "type: anisotropic_metal, albedo: [0.9, 0.7, 0.5], roughness: 0.5, "
     "anisotropy: 0.8"},
    {"mirror", "type: mirror, albedo: [0.95, 0.95, 0.9]"},
    {"glass", "type: glass, refractive_index: 1.5"},
    {"rough_glass", "type: glass, refractive_index: 1.5, roughness: 0.4"},
    {"absorbing_glass",
     "type: dielectric, refractive_index: 1.45, transmittance: [0.3, 0.6, 0.9], "
     "transmittance_distance: 0.5"},
    {"clear_coat", "type: clear_coat, albedo: [0.6, 0.1, 0.1], roughness: 0.1"},
    {"thin_film", "type: thin_film, film_thickness: 350, film_ior: 1.33"},
    {"constant", "type: constant, albedo: [0.2, 0.5, 0.8]"},
    {"show_normals", "type: show_normals"},
    {"light", "type: light, emission: [3, 2.5, 2]"},
    {"dots",
     "type: lambertian, albedo: 0.8, pattern: { type: fibonacci_dots, color: [0.1, 0.2, "
     "0.7], dot_count: 40, dot_radius: 0.25 }"},
    {"textured", "type: metal, albedo: 0.9, albedo_texture: checks, roughness_texture: checks"},
};

SceneDescription probe_scene(const MaterialCase& c, std::uint64_t seed, std::uint32_t spp) {
  const std::string text = R"(
camera: { position: [0, 1.1, 3.2], look_at: [0, 0.45, 0], fov: 38 }
environment: { type: gradient, intensity: 0.5 }
textures: [ { name: checks, type: checker, color_a: 0.9, color_b: 0.2, scale: 6 } ]
materials:
  - { name: ground, type: lambertian, albedo_texture: checks }
  - { name: lamp, type: light, emission: [12, 11, 10] }
  - { name: probe, )" + std::string(c.yaml) +
                           R"( }
geometry:
  - { type: rectangle, material: ground, corner: [-3, 0, 2], u: [6, 0, 0], v: [0, 0, -6] }
  - { type: rectangle, material: lamp, corner: [-0.5, 2.5, -0.5], u: [1, 0, 0], v: [0, 0, 1] }
  - { type: sphere, material: probe, center: [0, 0.5, 0], radius: 0.5 }
render: { width: 32, height: 24, spp: 16, max_depth: 8, tile_size: 8 }
)";
  SceneDescription scene = load_scene_yaml(text, c.name, ".").scene;
  scene.render.seed = seed;
  scene.render.samples_per_pixel = spp;
  return scene;
}

// The mean of `seeds` renders and the variance of that mean (from their spread), per pixel
// and channel, RGB only.
struct Estimate {
  std::vector<float> mean, variance;
};

// Seeds first_seed, first_seed + 1, ...: the test and the reference use disjoint ones, so
// their errors are independent.
Estimate estimate(const MaterialCase& c, std::uint64_t first_seed, std::uint32_t seeds,
                  std::uint32_t spp) {
  const std::size_t values = std::size_t{kWidth} * kHeight * 3;
  std::vector<double> sum(values, 0.0), sum_sq(values, 0.0);
  for (std::uint32_t s = 0; s < seeds; ++s) {
    const std::vector<float> image =
        render_image(*PreparedScene::build(probe_scene(c, first_seed + s, spp)));
    for (std::size_t p = 0; p < std::size_t{kWidth} * kHeight; ++p)
      for (int ch = 0; ch < 3; ++ch) {
        const double v = image[4 * p + ch];
        sum[3 * p + ch] += v;
        sum_sq[3 * p + ch] += v * v;
      }
  }
  Estimate e;
  e.mean.resize(values);
  e.variance.resize(values);
  for (std::size_t i = 0; i < values; ++i) {
    const double mean = sum[i] / seeds;
    const double sample_variance = std::max(0.0, (sum_sq[i] - seeds * mean * mean) / (seeds - 1));
    e.mean[i] = static_cast<float>(mean);
    e.variance[i] = static_cast<float>(sample_variance / seeds);
  }
  return e;
}

const std::vector<std::string> kChannels = {"R",          "G",          "B",
                                            "Variance.R", "Variance.G", "Variance.B"};

std::filesystem::path reference_path(const MaterialCase& c) {
  return std::filesystem::path(TESSERA_SOURCE_DIR) / "tests/data/material_references" /
         (std::string(c.name) + ".exr");
}

void write_reference(const MaterialCase& c, const Estimate& e) {
  std::vector<float> pixels;
  for (std::size_t p = 0; p < std::size_t{kWidth} * kHeight; ++p) {
    for (int ch = 0; ch < 3; ++ch) pixels.push_back(e.mean[3 * p + ch]);
    for (int ch = 0; ch < 3; ++ch) pixels.push_back(e.variance[3 * p + ch]);
  }
  const std::vector<std::uint8_t> bytes = encode_exr(pixels, kWidth, kHeight, kChannels, 0, 0);
  std::filesystem::create_directories(reference_path(c).parent_path());
  std::ofstream(reference_path(c), std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

Estimate read_reference(const MaterialCase& c) {
  std::ifstream in(reference_path(c), std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  Estimate e;
  if (bytes.empty()) return e;
  const ChannelImage image = select_channels(decode_exr_channels(bytes), kChannels);
  for (std::size_t p = 0; p < std::size_t{kWidth} * kHeight; ++p) {
    for (int ch = 0; ch < 3; ++ch) e.mean.push_back(image.pixels[6 * p + ch]);
    for (int ch = 0; ch < 3; ++ch) e.variance.push_back(image.pixels[6 * p + 3 + ch]);
  }
  return e;
}

class MaterialReference : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(MaterialReference, MatchesItsStoredRender) {
  const MaterialCase& c = GetParam();
  if (std::getenv("TESSERA_UPDATE_MATERIAL_REFERENCES") != nullptr) {
    write_reference(c, estimate(c, 5000, 16, 2048));
    GTEST_SKIP() << "wrote " << reference_path(c);
  }
  const Estimate reference = read_reference(c);
  ASSERT_EQ(reference.mean.size(), std::size_t{kWidth} * kHeight * 3)
      << "no reference at " << reference_path(c)
      << "; generate it with TESSERA_UPDATE_MATERIAL_REFERENCES=1";
  const Estimate test = estimate(c, 1000, 8, 128);
  int outliers = 0;
  double worst = 0.0;
  double diff_sum[3] = {0, 0, 0}, variance_sum[3] = {0, 0, 0};
  for (std::size_t i = 0; i < test.mean.size(); ++i) {
    const double floor = 1e-4 * (1.0 + std::fabs(reference.mean[i]));
    // The test's variance from 8 seeds is itself noisy (a pixel on an edge can land the same
    // way in all 8); the reference's, from 16 seeds of 16x the samples, scaled to the
    // test's sample count, is the better estimate of the same quantity, so take the larger.
    const double test_variance =
        std::max(double{test.variance[i]}, double{reference.variance[i]} * kSampleRatio);
    const double sigma = std::sqrt(test_variance + double{reference.variance[i]} + floor * floor);
    const double z = (double{test.mean[i]} - reference.mean[i]) / sigma;
    worst = std::max(worst, std::fabs(z));
    outliers += std::fabs(z) > 5.0;
    diff_sum[i % 3] += double{test.mean[i]} - reference.mean[i];
    variance_sum[i % 3] += test_variance + reference.variance[i] + floor * floor;
  }
  EXPECT_LE(outliers, static_cast<int>(test.mean.size() / 100))
      << c.name << ": " << outliers << " of " << test.mean.size() << " values beyond 5 sigma "
      << "(worst " << worst << ")";
  for (int ch = 0; ch < 3; ++ch)
    EXPECT_LT(std::fabs(diff_sum[ch]) / std::sqrt(variance_sum[ch]), 5.0)
        << c.name << " channel " << ch << ": the image mean moved";
}

INSTANTIATE_TEST_SUITE_P(EveryMaterial, MaterialReference, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<MaterialCase>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace tessera
