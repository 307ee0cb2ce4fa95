// The clear coat (bsdf.hpp, kCoated): a dielectric coat with exact Fresnel reflectance F and
// a GGX lobe over a diffuse base that receives the rest. Furnace: over a white base, a
// smooth coat returns exactly what it receives (F + (1 - F) = 1, every sample weight 1); a
// rough one never more, sample by sample (the mixture's weight is at most the larger of the
// lobes' weights, G2 / G1 <= 1 and 1) and by quadrature of eval, over a grid of roughness,
// index and angle. (Its sampling against its pdf is in bsdf_sampling_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "chi2.hpp"
#include "tessera/render/bsdf.hpp"
#include "tessera/render/fresnel.hpp"

namespace tessera {
namespace {

Bsdf coat(float alpha, float ior, vec3 base = vec3(1.0f)) {
  Material m;
  m.kind = BsdfKind::kCoated;
  m.albedo = base;
  m.ior = ior;
  m.alpha_x = m.alpha_y = alpha;
  return Bsdf::of(m, true);
}

vec3 direction(double theta_degrees) {
  const double t = theta_degrees * std::numbers::pi / 180.0;
  return vec3(static_cast<float>(std::sin(t)), 0.0f, static_cast<float>(std::cos(t)));
}

TEST(ClearCoat, SmoothCoatOverWhiteIsLossless) {
  test::UniformFloats u(21);
  for (float ior : {1.2f, 1.5f, 2.5f})
    for (double theta : {0.0, 45.0, 80.0, 89.0}) {
      const Bsdf bsdf = coat(0.0f, ior);
      const vec3 wo = direction(theta);
      int coat_samples = 0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        const BsdfSample s = bsdf.sample(wo, u(), u(), u());
        ASSERT_TRUE(s.valid());
        ASSERT_NEAR(s.weight().x, 1.0f, 1e-5f) << ior << " " << theta;
        if (s.specular()) ++coat_samples;
      }
      const double f = fresnel_dielectric(wo.z, ior);
      EXPECT_NEAR(coat_samples, n * f, 4.0 * std::sqrt(n * f * (1.0 - f)) + 0.5);
    }
}

TEST(ClearCoat, RoughCoatNeverReturnsMoreThanItReceives) {
  test::UniformFloats u(22);
  for (float alpha : {0.02f, 0.1f, 0.4f, 1.0f})
    for (float ior : {1.2f, 1.5f, 2.5f})
      for (double theta : {0.0, 45.0, 80.0, 89.0}) {
        const Bsdf bsdf = coat(alpha, ior);
        const vec3 wo = direction(theta);
        double sum = 0.0;
        const int n = 4000;
        for (int i = 0; i < n; ++i) {
          const BsdfSample s = bsdf.sample(wo, u(), u(), u());
          if (!s.valid()) continue;
          ASSERT_LE(s.weight().x, 1.0f + 1e-5f) << alpha << " " << ior << " " << theta;
          sum += s.weight().x;
        }
        EXPECT_LE(sum / n, 1.0);
      }
  // The same by quadrature of eval over the hemisphere (independent of the sampler), for
  // the grazing case where the coat is strongest, printed for the record.
  for (float alpha : {0.1f, 1.0f}) {
    const Bsdf bsdf = coat(alpha, 1.5f);
    const vec3 wo = direction(80.0);
    test::DirectionCap cap;
    cap.axis = glm::dvec3(-wo.x, -wo.y, wo.z);
    const test::CapHistogram histogram(cap, 160, 48);
    double albedo = 0.0;
    for (double v : histogram.integrate([&](const glm::dvec3& w) {
           const vec3 wi(w);
           return wi.z > 0.0f ? double(bsdf.eval(wo, wi).x) * wi.z : 0.0;
         }))
      albedo += v;
    std::printf("[furnace] clear coat over white, alpha %.2f, 80 degrees: albedo %.4f\n", alpha,
                albedo);
    EXPECT_LE(albedo, 1.0 + 2e-3);
    EXPECT_GT(albedo, 0.8);
  }
}

}  // namespace
}  // namespace tessera
