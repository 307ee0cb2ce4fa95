// Sampling of the lights that are not shapes (render/analytic_light.hpp) and of the
// environment against their pdfs: chi-square goodness of fit (chi2.hpp) of a sun's cone
// and of the environment's directions, each sample's pdf equal to light_pdf for its
// direction, and pick_light's probabilities with lights at infinity beside a light tree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "chi2.hpp"
#include "tessera/render/light_sampling.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

using glm::dvec3;

constexpr int kChi2Tests = 4;

AnalyticLight sun(const vec3& towards_light, double radius_degrees, const vec3& irradiance) {
  AnalyticLight light;
  light.kind = AnalyticLightKind::kDistant;
  light.direction = glm::normalize(towards_light);
  light.emission = irradiance;
  const double half = 0.5 * radius_degrees * std::numbers::pi / 180.0;
  light.one_minus_cos_radius = static_cast<float>(2.0 * std::sin(half) * std::sin(half));
  return light;
}

// Draws `count` directions from `light` and tests them against analytic_light_pdf over a
// cap about `cap`; every sample's own pdf must be the pdf of its direction.
void check_directions(const AnalyticLight& light, const Environment& env,
                      const test::DirectionCap& cap, const char* name,
                      const vec3& ref_normal = vec3(0.0f)) {
  constexpr int kSamples = 200000;
  const test::CapHistogram bins(cap, 16, 24);
  std::vector<double> observed(bins.cells(), 0.0);
  test::UniformFloats u(0x5eed + static_cast<std::uint64_t>(light.kind));
  int pdf_mismatch = 0, failed = 0;
  for (int i = 0; i < kSamples; ++i) {
    LightSample s;
    if (!sample_analytic_light(light, env, vec3(0.3f, -0.2f, 1.0f), u(), u(), s, ref_normal)) {
      ++failed;
      continue;
    }
    observed[bins.cell_of(dvec3(s.wi))] += 1.0;
    const float pdf = analytic_light_pdf(light, env, s.wi, ref_normal);
    if (!(std::fabs(pdf - s.pdf) <= 1e-4f * s.pdf)) ++pdf_mismatch;
  }
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(pdf_mismatch, 0);
  std::vector<double> expected = bins.integrate([&](const dvec3& w) {
    return static_cast<double>(analytic_light_pdf(light, env, glm::normalize(vec3(w)), ref_normal));
  });
  double integral = 0.0;
  for (double& e : expected) {
    integral += e;
    e *= kSamples;
  }
  EXPECT_NEAR(integral, 1.0, 2e-3) << name;
  const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
  std::printf("[chi2] %-28s p = %.4g (%s)\n", name, chi2.p_value, chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << name << ": " << chi2.summary;
}

TEST(AnalyticLightSampling, SunConeFollowsItsPdf) {
  const AnalyticLight light = sun(vec3(0.3f, 1.0f, -0.4f), 4.0, vec3(2.0f));
  // A cap twice the cone's 1 - cos: half its rows inside the cone, half outside (empty).
  const test::DirectionCap cap{dvec3(light.direction), 1.0 - 2.0 * light.one_minus_cos_radius};
  check_directions(light, Environment{}, cap, "sun 4 degrees");
  // Inside the cone the radiance is E / (pi sin^2 radius), so that it integrates to E
  // over a surface facing the sun.
  LightSample s;
  ASSERT_TRUE(sample_analytic_light(light, Environment{}, vec3(0.0f), 0.3f, 0.7f, s));
  const double sin_radius = std::sin(4.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(s.radiance.x, 2.0 / (std::numbers::pi * sin_radius * sin_radius),
              1e-4 * s.radiance.x);
}

AnalyticLight environment_light() {
  AnalyticLight light;
  light.kind = AnalyticLightKind::kEnvironment;
  return light;
}

Environment gradient_sky() {
  Environment env;
  env.kind = EnvironmentKind::kGradient;
  env.scale = vec3(0.8f);
  return env;
}

TEST(AnalyticLightSampling, EnvironmentDirectionsFollowItsPdf) {
  const AnalyticLight light = environment_light();
  const Environment env = gradient_sky();
  check_directions(light, env, test::DirectionCap{dvec3(0.0, 1.0, 0.0), -1.0}, "environment");
  LightSample s;
  ASSERT_TRUE(sample_analytic_light(light, env, vec3(0.0f), 0.2f, 0.4f, s));
  EXPECT_EQ(s.radiance, env.radiance(s.wi));
}

// Seen from a surface, a constant or gradient environment is sampled by the cosine about
// the surface's normal: no direction below it, pdf cos / pi.
TEST(AnalyticLightSampling, EnvironmentFromASurfaceFollowsTheCosine) {
  const AnalyticLight light = environment_light();
  const Environment env = gradient_sky();
  const vec3 normal = glm::normalize(vec3(0.4f, 0.8f, -0.3f));
  check_directions(light, env, test::DirectionCap{dvec3(normal), 0.0}, "environment, cosine",
                   normal);
  LightSample s;
  ASSERT_TRUE(sample_analytic_light(light, env, vec3(0.0f), 0.2f, 0.4f, s, normal));
  EXPECT_GT(glm::dot(s.wi, normal), 0.0f);
  EXPECT_NEAR(s.pdf, glm::dot(s.wi, normal) / 3.14159265f, 1e-6f);
  EXPECT_EQ(analytic_light_pdf(light, env, -normal, normal), 0.0f);
  EXPECT_EQ(s.radiance, env.radiance(s.wi));
}

TEST(AnalyticLightSampling, DeltaLightsGiveIntensityOverDistanceSquared) {
  AnalyticLight point;
  point.kind = AnalyticLightKind::kPoint;
  point.position = vec3(1.0f, 2.0f, 2.0f);  // 3 from the origin
  point.emission = vec3(9.0f, 18.0f, 27.0f);
  LightSample s;
  ASSERT_TRUE(sample_analytic_light(point, Environment{}, vec3(0.0f), 0.5f, 0.5f, s));
  EXPECT_NEAR(s.distance, 3.0f, 1e-5f);
  EXPECT_NEAR(s.radiance.x, 1.0f, 1e-5f);
  EXPECT_NEAR(s.radiance.z, 3.0f, 1e-5f);
  EXPECT_EQ(s.pdf, 1.0f);
  EXPECT_EQ(analytic_light_pdf(point, Environment{}, s.wi), 0.0f);  // no ray can hit it

  // A spot's falloff: full inside the inner cone, smoothstep in cos between, none outside.
  EXPECT_EQ(spot_falloff(0.99f, 0.8f, 0.9f), 1.0f);
  EXPECT_EQ(spot_falloff(0.7f, 0.8f, 0.9f), 0.0f);
  EXPECT_NEAR(spot_falloff(0.85f, 0.8f, 0.9f), 0.5f, 1e-5f);
  EXPECT_NEAR(spot_falloff(0.825f, 0.8f, 0.9f), 0.25f * 0.25f * (3.0f - 0.5f), 1e-5f);
}

// pick_light with a light tree over the bounded lights and the lights at infinity beside
// it: the pick's pmf is light_pick_pmf of what it picked, the pmfs of all lights sum to 1,
// and the picks follow them (chi-square).
TEST(AnalyticLightSampling, PicksWithLightsAtInfinityFollowTheirPmf) {
  SceneDescription scene;
  MaterialDesc white;
  white.name = "white";
  MaterialDesc lamp;
  lamp.name = "lamp";
  lamp.type = MaterialType::kLight;
  lamp.emission = dvec3(3.0);
  scene.materials = {white, lamp};
  scene.quads.push_back(
      QuadDesc{.corner = {-5, 0, -5}, .u = {10, 0, 0}, .v = {0, 0, 10}, .material = 0});
  scene.spheres.push_back(SphereDesc{.center = {1, 2, 0}, .radius = 0.3, .material = 1});
  scene.spheres.push_back(SphereDesc{.center = {-2, 1, 1}, .radius = 0.2, .material = 1});
  scene.lights.push_back(LightDesc{.type = "point", .position = {0, 3, 0}, .intensity = 5.0});
  scene.lights.push_back(LightDesc{.type = "sun",
                                   .direction = {0.2, -1, 0.1},
                                   .irradiance = 2.0,
                                   .angular_radius_degrees = 1.0});
  scene.environment = EnvironmentDesc{.type = "gradient", .intensity = 0.5};
  const auto prepared = PreparedScene::build(scene);
  const SceneView view = prepared->view();
  ASSERT_EQ(view.light_count, 5u);
  ASSERT_NE(view.light_tree, nullptr);
  EXPECT_EQ(view.first_infinite_light, 3u);
  EXPECT_EQ(view.environment_light, 4u);
  EXPECT_GT(view.infinite_pick, 0.0f);

  const vec3 p(0.5f, 0.0f, 0.5f), n(0.0f, 1.0f, 0.0f);
  double sum = 0.0;
  std::vector<double> expected(view.light_count);
  for (std::uint32_t i = 0; i < view.light_count; ++i)
    sum += expected[i] = light_pick_pmf(view, p, n, i);
  EXPECT_NEAR(sum, 1.0, 1e-5);
  constexpr int kPicks = 100000;
  std::vector<double> observed(view.light_count, 0.0);
  test::UniformFloats u(77);
  int mismatch = 0;
  for (int i = 0; i < kPicks; ++i) {
    const LightPick pick = pick_light(view, p, n, u());
    observed[pick.index] += 1.0;
    if (std::fabs(pick.pmf - light_pick_pmf(view, p, n, pick.index)) > 1e-6f * pick.pmf) ++mismatch;
  }
  EXPECT_EQ(mismatch, 0);
  for (double& e : expected) e *= kPicks;
  const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
  std::printf("[chi2] %-28s p = %.4g (%s)\n", "picks with infinite lights", chi2.p_value,
              chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << chi2.summary;
}

}  // namespace
}  // namespace tessera
