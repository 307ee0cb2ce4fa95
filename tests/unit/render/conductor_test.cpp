// The GGX conductor (bsdf.hpp, microfacet.hpp, fresnel.hpp): sampling against its pdf by a
// chi-square test (isotropic and anisotropic), every sample carrying eval and pdf, the pdf
// integrating to the share of samples that survive, reciprocity, the furnace (a smooth
// white conductor returns exactly what it receives; a rough one only loses GGX's known
// single-scattering energy, measured by quadrature of eval independently of the sampler;
// none ever returns more), and the Fresnel terms against closed forms.
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

using test::direction;

// A conductor Bsdf with GGX roughness (ax, ay); gold's measured index when `complex`, else
// the albedo alone (RayON's metal).
Bsdf conductor(float ax, float ay, bool complex, vec3 albedo = vec3(1.0f)) {
  Material m;
  m.kind = BsdfKind::kConductor;
  m.albedo = albedo;
  m.alpha_x = ax;
  m.alpha_y = ay;
  m.complex_fresnel = complex;
  m.eta = vec3(0.166f, 0.3455f, 1.5021f);
  m.k = vec3(3.150f, 2.7306f, 1.8759f);
  return Bsdf::of(m, true);
}

struct ConductorCase {
  float alpha_x, alpha_y;
  double theta_o, phi_o;  // degrees
  std::string name() const {
    return "ax" + std::to_string(alpha_x).substr(0, 4) + "_ay" +
           std::to_string(alpha_y).substr(0, 4) + "_wo" +
           std::to_string(static_cast<int>(theta_o)) + "_" +
           std::to_string(static_cast<int>(phi_o));
  }
};

std::vector<ConductorCase> chi2_cases() {
  std::vector<ConductorCase> cases;
  for (float alpha : {0.1f, 0.4f, 1.0f})
    for (double theta : {0.0, 45.0, 80.0}) cases.push_back({alpha, alpha, theta, 0.0});
  for (double theta : {30.0, 70.0}) {
    cases.push_back({0.1f, 0.5f, theta, 35.0});
    cases.push_back({0.6f, 0.15f, theta, 120.0});
  }
  return cases;
}

const int kChi2Tests = static_cast<int>(chi2_cases().size()) + 1;  // + the fine-lobe case

// The lobe binned about the mirror direction over the whole sphere: rows of cos about it,
// so narrow lobes still fall into many cells.
void check_conductor_sampling(const ConductorCase& c, int samples) {
  SCOPED_TRACE(c.name());
  const Bsdf bsdf = conductor(c.alpha_x, c.alpha_y, true, vec3(0.9f, 0.8f, 0.7f));
  ASSERT_TRUE(bsdf.has_non_specular());
  const vec3 wo = direction(c.theta_o, c.phi_o);
  DirectionCap cap;
  cap.axis = glm::dvec3(-wo.x, -wo.y, wo.z);
  cap.cos_min = -1.0;
  const float narrow = std::min(c.alpha_x, c.alpha_y);
  const int rows = narrow < 0.05f ? 1500 : narrow < 0.2f ? 240 : 64;
  const CapHistogram histogram(cap, rows, 48);

  test::UniformFloats u(0xc0d0c7u + static_cast<std::uint64_t>(c.theta_o * 10) +
                        static_cast<std::uint64_t>(c.alpha_x * 1000) * 7919u +
                        static_cast<std::uint64_t>(c.alpha_y * 1000) * 104729u);
  std::vector<double> observed(histogram.cells(), 0.0);
  int valid = 0, mismatches = 0;
  double max_weight = 0.0;
  std::string first_mismatch;
  for (int i = 0; i < samples; ++i) {
    const float u_lobe = u(), u1 = u(), u2 = u();
    const BsdfSample s = bsdf.sample(wo, u_lobe, u1, u2);
    if (!s.valid()) continue;
    ASSERT_FALSE(s.specular());
    ASSERT_GT(s.wi.z, 0.0f);
    ++valid;
    observed[histogram.cell_of(glm::dvec3(s.wi))] += 1.0;
    max_weight = std::max(max_weight, static_cast<double>(max_component(s.weight())));
    const vec3 f = bsdf.eval(wo, s.wi);
    const float pdf = bsdf.pdf(wo, s.wi);
    const auto close = [](float a, float b) {
      return std::fabs(a - b) <= 2e-4f * std::max(std::fabs(a), std::fabs(b));
    };
    if (!(close(s.f.x, f.x) && close(s.f.y, f.y) && close(s.f.z, f.z) && close(s.pdf, pdf))) {
      if (mismatches++ == 0)
        first_mismatch = "sample f.x " + std::to_string(s.f.x) + " pdf " + std::to_string(s.pdf) +
                         ", eval " + std::to_string(f.x) + " pdf " + std::to_string(pdf);
    }
  }
  EXPECT_EQ(mismatches, 0) << "first: " << first_mismatch;
  // f cos / pdf = F G2 / G1(wo) <= F: no sample carries more than the Fresnel term.
  EXPECT_LE(max_weight, 0.9 * (1.0 + 1e-5));

  std::vector<double> expected =
      histogram.integrate([&](const glm::dvec3& w) { return double(bsdf.pdf(wo, vec3(w))); });
  double integral = 0.0;
  for (double& e : expected) {
    integral += e;
    e *= samples;
  }
  // The pdf integrates to the share of samples not lost below the horizon (reflections
  // about a visible normal that leave under the surface): 4 binomial sigmas + 2e-3 for the
  // quadrature.
  const double n = samples;
  const double fraction = valid / n;
  const double p = std::clamp(integral, 0.0, 1.0);
  EXPECT_NEAR(fraction, integral, 4.0 * std::sqrt(p * (1.0 - p) / n) + 2e-3);

  const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
  std::printf("[chi2] ggx conductor %-26s p = %.4g (%s)\n", c.name().c_str(), chi2.p_value,
              chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << chi2.summary;
}

TEST(GgxConductor, SamplesFollowThePdfIsotropicAndAnisotropic) {
  for (const ConductorCase& c : chi2_cases()) check_conductor_sampling(c, 150000);
}

TEST(GgxConductor, NarrowLobeFollowsThePdf) {
  check_conductor_sampling({0.02f, 0.02f, 40.0, 0.0}, 150000);
}

// Directional albedo: int f(wo, wi) cos dwi by quadrature of eval (CapHistogram's adaptive
// midpoint rule about the mirror direction), independent of the sampler.
double albedo_by_quadrature(const Bsdf& bsdf, const vec3& wo) {
  DirectionCap cap;
  cap.axis = glm::dvec3(-wo.x, -wo.y, wo.z);
  cap.cos_min = -1.0;
  const CapHistogram histogram(cap, 240, 48);
  double sum = 0.0;
  for (double v : histogram.integrate([&](const glm::dvec3& w) {
         const vec3 wi(w);
         return wi.z > 0.0f ? double(bsdf.eval(wo, wi).x) * wi.z : 0.0;
       }))
    sum += v;
  return sum;
}

// The sampled estimate of the same albedo: the mean weight, and its standard error.
void albedo_by_sampling(const Bsdf& bsdf, const vec3& wo, int samples, double& mean,
                        double& sigma) {
  test::UniformFloats u(0xfa11u);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    const float u_lobe = u(), u1 = u(), u2 = u();
    const BsdfSample s = bsdf.sample(wo, u_lobe, u1, u2);
    const double w = s.valid() ? s.weight().x : 0.0;
    sum += w;
    sum2 += w * w;
  }
  mean = sum / samples;
  sigma = std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples);
}

// Furnace, smooth: a perfectly reflecting conductor (albedo 1, no Fresnel) at roughness 0
// is a mirror with weight exactly 1 at every angle.
TEST(GgxConductor, SmoothWhiteConductorReturnsExactlyWhatItReceives) {
  const Bsdf bsdf = conductor(0.0f, 0.0f, false);
  EXPECT_FALSE(bsdf.has_non_specular());
  for (double theta : {0.0, 30.0, 60.0, 85.0, 89.9}) {
    const vec3 wo = direction(theta, 20.0);
    const BsdfSample s = bsdf.sample(wo, 0.3f, 0.5f, 0.5f);
    ASSERT_TRUE(s.valid() && s.specular());
    EXPECT_NEAR(glm::length(s.wi - vec3(-wo.x, -wo.y, wo.z)), 0.0f, 1e-6f);
    EXPECT_NEAR(s.weight().x, 1.0f, 1e-6f) << theta;
    EXPECT_EQ(bsdf.eval(wo, s.wi), vec3(0.0f));
    EXPECT_EQ(bsdf.pdf(wo, s.wi), 0.0f);
  }
}

// Furnace, rough: the white GGX conductor (F = 1) loses exactly its single-scattering
// energy, the share of light that the microsurface masks or shadows. The sampled albedo
// (mean weight G2 / G1) agrees with the quadrature of eval within 4 sigma + 2e-3 (the
// quadrature's error), neither exceeds 1, and the figures are printed for the record.
TEST(GgxConductor, RoughWhiteConductorLosesOnlyItsSingleScatteringEnergy) {
  struct Row {
    float alpha;
    double theta;
  };
  double albedo_alpha1_normal = 0.0;
  for (const Row r : {Row{0.05f, 0.0}, Row{0.3f, 0.0}, Row{0.3f, 70.0}, Row{0.6f, 45.0},
                      Row{1.0f, 0.0}, Row{1.0f, 60.0}, Row{1.0f, 85.0}}) {
    const Bsdf bsdf = conductor(r.alpha, r.alpha, false);
    const vec3 wo = direction(r.theta, 0.0);
    const double quadrature = albedo_by_quadrature(bsdf, wo);
    double mean = 0.0, sigma = 0.0;
    albedo_by_sampling(bsdf, wo, 200000, mean, sigma);
    std::printf(
        "[furnace] ggx alpha %.2f theta %4.1f: albedo quadrature %.4f sampled %.4f "
        "(sigma %.1e), loss %.1f%%\n",
        r.alpha, r.theta, quadrature, mean, sigma, 100.0 * (1.0 - quadrature));
    EXPECT_NEAR(mean, quadrature, 4.0 * sigma + 2e-3) << r.alpha << " " << r.theta;
    EXPECT_LE(quadrature, 1.0 + 2e-3);
    EXPECT_LE(mean, 1.0);
    if (r.alpha == 1.0f && r.theta == 0.0) albedo_alpha1_normal = quadrature;
    // Narrow lobes lose almost nothing.
    if (r.alpha <= 0.05f) {
      EXPECT_GT(quadrature, 0.995);
    }
  }
  // At alpha 1 the normals are distributed as cos(theta_m) / pi about the pole; seen from
  // straight above, half of them reflect below the horizon and the rest are shadowed with
  // G2 = 2 - 1 / cos^2(theta_m): the albedo is the closed form 1 - ln 2 = 0.3069.
  EXPECT_NEAR(albedo_alpha1_normal, 1.0 - std::log(2.0), 2e-3);
}

// No conductor returns more than it receives: every sample's weight is at most the
// Fresnel term's largest channel (<= 1), over a grid of roughness, anisotropy and angle.
TEST(GgxConductor, NeverReturnsMoreThanItReceives) {
  test::UniformFloats u(99);
  for (float ax : {0.002f, 0.05f, 0.3f, 1.0f})
    for (float ay : {0.002f, 0.3f, 1.0f})
      for (double theta : {0.0, 30.0, 60.0, 80.0, 89.0})
        for (bool complex : {false, true}) {
          const Bsdf bsdf = conductor(ax, ay, complex);
          const vec3 wo = direction(theta, 40.0);
          double sum = 0.0;
          const int n = 2000;
          for (int i = 0; i < n; ++i) {
            const BsdfSample s = bsdf.sample(wo, u(), u(), u());
            if (!s.valid()) continue;
            const float w = max_component(s.weight());
            ASSERT_LE(w, 1.0f + 1e-5f) << ax << " " << ay << " " << theta << " " << complex;
            ASSERT_TRUE(std::isfinite(w));
            sum += w;
          }
          EXPECT_LE(sum / n, 1.0);
        }
}

// Reciprocity: eval(wo, wi) == eval(wi, wo) (F depends on wo.m = wi.m, D on m, G2 is
// symmetric), with and without the complex Fresnel term, isotropic and anisotropic.
TEST(GgxConductor, IsReciprocal) {
  test::UniformFloats u(5);
  int compared = 0;
  for (const Bsdf& bsdf : {conductor(0.3f, 0.3f, true), conductor(0.1f, 0.7f, true),
                           conductor(0.5f, 0.5f, false, vec3(0.9f, 0.6f, 0.2f))}) {
    for (int i = 0; i < 2000; ++i) {
      const vec3 a = sample_cosine_hemisphere(u(), u());
      const vec3 b = sample_cosine_hemisphere(u(), u());
      if (a.z <= 1e-3f || b.z <= 1e-3f) continue;
      const vec3 fab = bsdf.eval(a, b), fba = bsdf.eval(b, a);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(fab[c], fba[c], 1e-4f * std::max(1.0f, fab[c])) << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 5000);
}

// Fresnel: the conductor formula with k = 0 is the dielectric one; at normal incidence it is
// ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2); at grazing incidence 1. The dielectric one is
// ((eta - 1) / (eta + 1))^2 at normal incidence and 1 beyond the critical angle.
TEST(Fresnel, MatchesClosedForms) {
  for (double theta = 0.0; theta < 90.0; theta += 5.0) {
    const float c = static_cast<float>(std::cos(theta * std::numbers::pi / 180.0));
    EXPECT_NEAR(fresnel_conductor(c, 1.5f, 0.0f), fresnel_dielectric(c, 1.5f), 1e-5f) << theta;
  }
  const float n = 0.166f, k = 3.15f;
  EXPECT_NEAR(fresnel_conductor(1.0f, n, k),
              ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-5f);
  EXPECT_NEAR(fresnel_conductor(0.0f, n, k), 1.0f, 1e-5f);
  EXPECT_NEAR(fresnel_conductor(1.0f, 1.0f, 0.0f), 0.0f, 1e-7f);
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  // Inside glass (eta 1/1.5) the critical angle is asin(1/1.5) = 41.8 degrees.
  EXPECT_EQ(fresnel_dielectric(std::cos(0.75f), 1.0f / 1.5f), 1.0f);
  EXPECT_LT(fresnel_dielectric(std::cos(0.70f), 1.0f / 1.5f), 1.0f);
  // Brewster's angle: the p-polarised reflectance vanishes, so F = r_s^2 / 2 there.
  const float brewster = std::atan(1.5f);
  const float ci = std::cos(brewster), ct = std::cos(std::asin(std::sin(brewster) / 1.5f));
  const float rs = (ci - 1.5f * ct) / (ci + 1.5f * ct);
  EXPECT_NEAR(fresnel_dielectric(ci, 1.5f), 0.5f * rs * rs, 1e-5f);
}

// An anisotropic lobe is stretched along the tangent: with alpha_x > alpha_y, light from
// straight above spreads further along x than along y.
TEST(GgxConductor, AnisotropyStretchesAlongTheTangent) {
  const Bsdf bsdf = conductor(0.5f, 0.05f, false);
  test::UniformFloats u(11);
  double spread_x = 0.0, spread_y = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const BsdfSample s = bsdf.sample(vec3(0.0f, 0.0f, 1.0f), u(), u(), u());
    if (!s.valid()) continue;
    spread_x += s.wi.x * s.wi.x;
    spread_y += s.wi.y * s.wi.y;
  }
  EXPECT_GT(spread_x, 20.0 * spread_y);
}

}  // namespace
}  // namespace tessera
