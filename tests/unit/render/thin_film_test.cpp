// Thin-film interference against independent answers: the characteristic-matrix (transfer
// matrix) solution of a single layer in double-precision complex arithmetic, the closed
// forms at zero and quarter-wave thickness, and the thin film BSDF's energy balance.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "tessera/render/bsdf.hpp"
#include "tessera/render/thin_film.hpp"

namespace tessera {
namespace {

using Complex = std::complex<double>;

// Reflectance of one layer by its characteristic matrix (Born & Wolf 1.6), for s (tilted
// admittance n cos) or p (n / cos) polarisation; unrelated to the Airy sum under test.
double matrix_reflectance(double cos0, double n0, double n1, double n2, double d, double lambda,
                          bool p) {
  const double sin0 = std::sqrt(1.0 - cos0 * cos0);
  const Complex cos1 = std::sqrt(Complex(1.0 - (n0 * sin0 / n1) * (n0 * sin0 / n1)));
  const Complex cos2 = std::sqrt(Complex(1.0 - (n0 * sin0 / n2) * (n0 * sin0 / n2)));
  const auto admittance = [p](double n, Complex c) { return p ? n / c : n * c; };
  const Complex y0 = admittance(n0, Complex(cos0)), y1 = admittance(n1, cos1),
                y2 = admittance(n2, cos2);
  const Complex phase = 2.0 * std::numbers::pi * n1 * d * cos1 / lambda;
  const Complex i(0.0, 1.0);
  const Complex b = std::cos(phase) + i * std::sin(phase) / y1 * y2;
  const Complex c = i * y1 * std::sin(phase) + std::cos(phase) * y2;
  const Complex r = (y0 * b - c) / (y0 * b + c);
  return std::norm(r);
}

double unpolarised_matrix_reflectance(double cos0, double n0, double n1, double n2, double d,
                                      double lambda) {
  return 0.5 * (matrix_reflectance(cos0, n0, n1, n2, d, lambda, false) +
                matrix_reflectance(cos0, n0, n1, n2, d, lambda, true));
}

// Exact unpolarised Fresnel reflectance of a bare interface n0 -> n2.
double bare_interface(double cos0, double n0, double n2) {
  const double sin2 = n0 / n2 * std::sqrt(1.0 - cos0 * cos0);
  const double cos2 = std::sqrt(1.0 - sin2 * sin2);
  const double rs = (n0 * cos0 - n2 * cos2) / (n0 * cos0 + n2 * cos2);
  const double rp = (n2 * cos0 - n0 * cos2) / (n2 * cos0 + n0 * cos2);
  return 0.5 * (rs * rs + rp * rp);
}

TEST(ThinFilm, ZeroThicknessIsTheBareInterface) {
  for (double degrees : {0.0, 30.0, 60.0, 85.0}) {
    const float cos0 = static_cast<float>(std::cos(degrees * std::numbers::pi / 180.0));
    // A free-standing film that vanishes leaves air against air: nothing reflects.
    EXPECT_NEAR(airy_reflectance(cos0, 1.0f, 1.33f, 1.0f, 0.0f, 550.0f), 0.0, 1e-6) << degrees;
    EXPECT_NEAR(airy_reflectance(cos0, 1.0f, 1.33f, 1.5f, 0.0f, 550.0f),
                bare_interface(cos0, 1.0, 1.5), 1e-5)
        << degrees;
  }
}

TEST(ThinFilm, QuarterWaveMatchesTheClosedForm) {
  // At normal incidence a layer of optical thickness lambda / 4 reflects
  // ((n0 n2 - n1^2) / (n0 n2 + n1^2))^2.
  struct Stack {
    double n0, n1, n2;
  };
  for (const Stack s : {Stack{1.0, 1.33, 1.0}, Stack{1.0, 1.38, 1.5}, Stack{1.33, 2.0, 1.0}}) {
    const double lambda = 550.0;
    const double quarter = lambda / (4.0 * s.n1);
    const double closed = std::pow((s.n0 * s.n2 - s.n1 * s.n1) / (s.n0 * s.n2 + s.n1 * s.n1), 2.0);
    EXPECT_NEAR(airy_reflectance(1.0f, static_cast<float>(s.n0), static_cast<float>(s.n1),
                                 static_cast<float>(s.n2), static_cast<float>(quarter),
                                 static_cast<float>(lambda)),
                closed, 1e-5)
        << s.n0 << " " << s.n1 << " " << s.n2;
  }
}

TEST(ThinFilm, AiryMatchesTheCharacteristicMatrixAtEveryAngleAndThickness) {
  struct Stack {
    double n0, n1, n2;
  };
  int compared = 0;
  for (const Stack s : {Stack{1.0, 1.33, 1.0}, Stack{1.0, 1.38, 1.5}, Stack{1.0, 2.4, 1.5}}) {
    for (double degrees = 0.0; degrees < 89.0; degrees += 7.5) {
      const double cos0 = std::cos(degrees * std::numbers::pi / 180.0);
      for (double d : {25.0, 120.0, 250.0, 400.0, 655.0, 1000.0}) {
        for (double lambda : {450.0, 550.0, 650.0}) {
          const double expected = unpolarised_matrix_reflectance(cos0, s.n0, s.n1, s.n2, d, lambda);
          const float got = airy_reflectance(static_cast<float>(cos0), static_cast<float>(s.n0),
                                             static_cast<float>(s.n1), static_cast<float>(s.n2),
                                             static_cast<float>(d), static_cast<float>(lambda));
          ASSERT_NEAR(got, expected, 2e-5)
              << "n " << s.n0 << "/" << s.n1 << "/" << s.n2 << " at " << degrees << " deg, d " << d
              << " nm, lambda " << lambda;
          ++compared;
        }
      }
    }
  }
  EXPECT_EQ(compared, 3 * 12 * 6 * 3);
}

TEST(ThinFilm, ChannelsAreTheRepresentativeWavelengths) {
  const vec3 rgb = thin_film_reflectance(0.8f, 1.0f, 1.33f, 400.0f);
  EXPECT_FLOAT_EQ(rgb.x, airy_reflectance(0.8f, 1.0f, 1.33f, 1.0f, 400.0f, 650.0f));
  EXPECT_FLOAT_EQ(rgb.y, airy_reflectance(0.8f, 1.0f, 1.33f, 1.0f, 400.0f, 550.0f));
  EXPECT_FLOAT_EQ(rgb.z, airy_reflectance(0.8f, 1.0f, 1.33f, 1.0f, 400.0f, 450.0f));
  // Interference colours: a soap film of 400 nm is not grey.
  EXPECT_GT(max_component(rgb) - glm::min(rgb.x, glm::min(rgb.y, rgb.z)), 0.02f);
}

// The BSDF picks reflection with the largest channel's reflectance and weights each lobe by
// its share, so summed over the lobe choice every channel returns exactly what arrives
// (R + T = 1), and the reflected part alone is R. No sample returns more than its lobe's
// share allows: at most 1 for reflection (a pick by the channels' mean gave up to 3x the
// light in one channel, coloured fireflies in soap bubbles), at most 1 / (1 - max R) for
// transmission.
TEST(ThinFilm, BsdfConservesEnergyPerChannel) {
  Material m;
  m.kind = BsdfKind::kThinDielectric;
  m.ior = 1.33f;
  m.exterior_ior = 1.0f;
  m.film_thickness_nm = 380.0f;
  for (bool front : {true, false}) {
    const Bsdf bsdf = Bsdf::of(m, front);
    for (float cos_o : {1.0f, 0.7f, 0.3f, 0.05f}) {
      const vec3 wo(std::sqrt(1.0f - cos_o * cos_o), 0.0f, cos_o);
      const vec3 r = thin_film_reflectance(cos_o, 1.0f, 1.33f, 380.0f);
      constexpr int kStrata = 4096;
      dvec3 total(0.0), reflected(0.0);
      for (int i = 0; i < kStrata; ++i) {
        const BsdfSample s = bsdf.sample(wo, (static_cast<float>(i) + 0.5f) / kStrata, 0.5f, 0.5f);
        ASSERT_TRUE(s.valid());
        ASSERT_TRUE(s.specular());
        const dvec3 w(s.weight());
        total += w;
        if ((s.lobe & kLobeReflection) != 0) {
          EXPECT_FLOAT_EQ(s.wi.z, wo.z);
          EXPECT_LE(max_component(s.weight()), 1.0f + 1e-5f) << cos_o;
          reflected += w;
        } else {
          EXPECT_EQ(s.wi, -wo);  // straight through
          EXPECT_LE(max_component(s.weight()), (1.0f + 1e-5f) / (1.0f - max_component(r))) << cos_o;
        }
      }
      for (int c = 0; c < 3; ++c) {
        // Stratified lobe choice: off by at most one stratum of each lobe, whose weights are
        // at most 1 and 1 / (1 - max R).
        EXPECT_NEAR(total[c] / kStrata, 1.0, 5.0 / kStrata) << cos_o << " channel " << c;
        EXPECT_NEAR(reflected[c] / kStrata, r[c], 4.0 / kStrata) << cos_o << " channel " << c;
      }
    }
  }
}

}  // namespace
}  // namespace tessera
