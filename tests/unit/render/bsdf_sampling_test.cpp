// Bsdf::sample against Bsdf::pdf and Bsdf::eval: a chi-square goodness-of-fit test of the
// sampled directions against the pdf (chi2.hpp), that every non-specular sample carries
// eval(wo, wi) and pdf(wo, wi), and that the pdf integrates to the fraction of samples that
// are neither absorbed nor specular. The GGX conductor and rough glass have their own files
// (conductor_test.cpp, dielectric_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "chi2.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/fresnel.hpp"

namespace tessera {
namespace {

using test::CapHistogram;
using test::DirectionCap;

struct BsdfCase {
  std::string name;
  BsdfKind kind;
  float roughness;
  float theta_o_degrees;
  int samples;
};

std::vector<BsdfCase> bsdf_cases() {
  std::vector<BsdfCase> cases;
  cases.push_back({"Diffuse_wo45", BsdfKind::kDiffuse, 0.0f, 45.0f, 400000});
  for (float roughness : {0.2f, 0.0f})
    for (float theta : {0.0f, 45.0f, 80.0f})
      cases.push_back({"Coated_r" + std::to_string(static_cast<int>(roughness * 100)) + "_wo" +
                           std::to_string(static_cast<int>(theta)),
                       BsdfKind::kCoated, roughness, theta, 400000});
  return cases;
}

// Every chi-square test in this file, for the Bonferroni correction.
const int kChi2Tests = static_cast<int>(bsdf_cases().size());

// Sampled directions follow the pdf, samples carry eval and pdf, the pdf integrates to the
// share of samples that survive.
void check_bsdf(const BsdfCase& c) {
  SCOPED_TRACE(c.name);
  Material material;
  material.kind = c.kind;
  material.albedo = vec3(0.7f, 0.5f, 0.3f);
  material.roughness = c.roughness;
  material.alpha_x = material.alpha_y = c.roughness;  // the coat's GGX lobe
  material.ior = 1.5f;
  const Bsdf bsdf = Bsdf::of(material, true);
  const double theta_o = c.theta_o_degrees * std::numbers::pi / 180.0;
  const vec3 wo(static_cast<float>(std::sin(theta_o)), 0.0f, static_cast<float>(std::cos(theta_o)));
  const glm::dvec3 mirror(-wo.x, -wo.y, wo.z);

  // Binned over the whole sphere.
  DirectionCap cap;
  int rows = 32, columns = 64;
  if (c.kind == BsdfKind::kCoated) {
    rows = 48;  // the 0.2 coat lobe is ~0.13 sr: finer cells so it covers dozens of them
    columns = 96;
  }
  const CapHistogram histogram(cap, rows, columns);

  test::UniformFloats u(0x5eed0000u + static_cast<std::uint64_t>(c.theta_o_degrees * 10) +
                        static_cast<std::uint64_t>(c.roughness * 1000) * 7919u +
                        static_cast<std::uint64_t>(c.kind) * 104729u);
  std::vector<double> observed(histogram.cells(), 0.0);
  int non_specular = 0, specular = 0, mismatches = 0;
  std::string first_mismatch;
  for (int i = 0; i < c.samples; ++i) {
    const float u_lobe = u(), u1 = u(), u2 = u();
    const BsdfSample s = bsdf.sample(wo, u_lobe, u1, u2);
    if (!s.valid()) continue;
    if (s.specular()) {
      ++specular;
      // A smooth coat's mirror lobe: the mirror direction, throughput weight 1 (f |cos| / pdf).
      EXPECT_NEAR(glm::length(s.wi - vec3(mirror)), 0.0f, 1e-5f);
      EXPECT_NEAR(s.weight().x, 1.0f, 1e-4f);
      continue;
    }
    ++non_specular;
    observed[histogram.cell_of(glm::dvec3(s.wi))] += 1.0;
    const vec3 f = bsdf.eval(wo, s.wi);
    const float pdf = bsdf.pdf(wo, s.wi);
    const auto close = [](float a, float b) {
      return std::fabs(a - b) <= 1e-4f * std::max(std::fabs(a), std::fabs(b));
    };
    if (!(close(s.f.x, f.x) && close(s.f.y, f.y) && close(s.f.z, f.z) && close(s.pdf, pdf))) {
      if (mismatches++ == 0)
        first_mismatch = "wi (" + std::to_string(s.wi.x) + ", " + std::to_string(s.wi.y) + ", " +
                         std::to_string(s.wi.z) + "): sample f.x " + std::to_string(s.f.x) +
                         " pdf " + std::to_string(s.pdf) + ", eval " + std::to_string(f.x) +
                         " pdf " + std::to_string(pdf);
    }
  }
  EXPECT_EQ(mismatches, 0) << "first: " << first_mismatch;

  const auto density = [&](const glm::dvec3& w) {
    return static_cast<double>(bsdf.pdf(wo, vec3(w)));
  };
  std::vector<double> expected = histogram.integrate(density);
  double integral = 0.0;
  for (double& e : expected) {
    integral += e;
    e *= c.samples;
  }

  // Energy: the pdf integrates to the share of samples that are neither absorbed (coat
  // reflections about a visible normal ending below the surface) nor specular. Tolerance: 4
  // binomial standard deviations plus 2e-3 for the numerical integration (midpoint rule, 48 x 48 in
  // cells where the density is not smooth).
  const double n = c.samples;
  const double fraction = non_specular / n;
  const double p = std::clamp(integral, 0.0, 1.0);
  EXPECT_NEAR(fraction, integral, 4.0 * std::sqrt(p * (1.0 - p) / n) + 2e-3)
      << "non-specular, non-absorbed share of samples against the pdf's integral";

  if (c.kind == BsdfKind::kCoated && c.roughness == 0.0f) {
    // The smooth coat is a mirror taken with the exact Fresnel probability F (index 1.5);
    // the count is binomial: within 4 standard deviations.
    const double fresnel = fresnel_dielectric(wo.z, 1.5f);
    EXPECT_NEAR(specular, n * fresnel, 4.0 * std::sqrt(n * fresnel * (1.0 - fresnel)) + 1.0);
    EXPECT_NEAR(integral, 1.0 - fresnel, 2e-3);
  } else {
    EXPECT_EQ(specular, 0);
  }
  // The diffuse lobe loses nothing.
  if (c.kind == BsdfKind::kDiffuse) {
    EXPECT_NEAR(integral, 1.0, 2e-3);
  }

  const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
  std::printf("[chi2] bsdf %-22s p = %.4g (%s)\n", c.name.c_str(), chi2.p_value,
              chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << chi2.summary;
}

// One test per family (each case is traced by name on failure): fewer test processes.
TEST(BsdfSampling, DiffuseFollowsItsPdf) {
  for (const BsdfCase& c : bsdf_cases())
    if (c.kind == BsdfKind::kDiffuse) check_bsdf(c);
}

TEST(BsdfSampling, CoatedFollowsItsPdfRoughAndSmooth) {
  for (const BsdfCase& c : bsdf_cases())
    if (c.kind == BsdfKind::kCoated) check_bsdf(c);
}

// The specular-only kinds have nothing for eval and pdf to see.
TEST(BsdfSampling, SpecularKindsHaveNoDensity) {
  for (BsdfKind kind : {BsdfKind::kDielectric, BsdfKind::kThinDielectric}) {
    Material m;
    m.kind = kind;
    const Bsdf bsdf = Bsdf::of(m, true);
    EXPECT_FALSE(bsdf.has_non_specular());
    const vec3 wo = glm::normalize(vec3(0.3f, 0.1f, 0.8f));
    test::UniformFloats u(7);
    for (int i = 0; i < 1000; ++i) {
      const BsdfSample s = bsdf.sample(wo, u(), u(), u());
      ASSERT_TRUE(s.valid());
      EXPECT_TRUE(s.specular());
      EXPECT_EQ(bsdf.pdf(wo, s.wi), 0.0f);
      EXPECT_EQ(bsdf.eval(wo, s.wi), vec3(0.0f));
    }
  }
}

}  // namespace
}  // namespace tessera
