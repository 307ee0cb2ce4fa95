// Polynomial solvers against analytic roots.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "tessera/math/solver_bracketed.hpp"
#include "tessera/math/solver_cubic.hpp"
#include "tessera/math/solver_quadratic.hpp"
#include "tessera/math/solver_quartic.hpp"

namespace tessera {
namespace {

TEST(SolveQuadratic, SmallRootKeepsItsDigitsWhenBIsHuge) {
  // x^2 - 1e8 x + 1: the textbook formula loses every digit of the root 1e-8.
  double roots[2];
  ASSERT_EQ(solve_quadratic(1.0, -1e8, 1.0, roots), 2);
  EXPECT_NEAR(roots[0], 1e-8, 1e-8 * 1e-15);
  EXPECT_NEAR(roots[1], 1e8, 1e8 * 1e-15);
}

TEST(SolveQuadratic, FloatCoefficientsUseAnExactDiscriminant) {
  // (x - 1)(x - (1 + 2^-12)): the discriminant 2^-24 is exact in double, not in float.
  const float r2 = 1.0f + 1.0f / 4096.0f;
  float roots[2];
  ASSERT_EQ(solve_quadratic(1.0f, -(1.0f + r2), r2, roots), 2);
  EXPECT_FLOAT_EQ(roots[0], 1.0f);
  EXPECT_FLOAT_EQ(roots[1], r2);
}

TEST(SolveQuadratic, NoRealRootsDoubleRootAndLinear) {
  double roots[2];
  EXPECT_EQ(solve_quadratic(1.0, 0.0, 1.0, roots), 0);
  ASSERT_EQ(solve_quadratic(1.0, -2.0, 1.0, roots), 2);
  EXPECT_DOUBLE_EQ(roots[0], 1.0);
  EXPECT_DOUBLE_EQ(roots[1], 1.0);
  ASSERT_EQ(solve_quadratic(0.0, 2.0, -4.0, roots), 1);
  EXPECT_DOUBLE_EQ(roots[0], 2.0);
  EXPECT_EQ(solve_quadratic(0.0, 0.0, 1.0, roots), 0);
}

TEST(SolveQuadratic, CoefficientsBeyondTheSquaresRangeAreBalancedFirst) {
  // 12 x^2 - 6e200 x + 1e200 (the second derivative of a quartic with a root at 1e200):
  // b^2 overflowed to inf, and the one root returned was 0.
  double roots[2];
  ASSERT_EQ(solve_quadratic(12.0, -6e200, 1e200, roots), 2);
  EXPECT_NEAR(roots[0], 1.0 / 6.0, 1e-16);
  EXPECT_NEAR(roots[1] / 5e199, 1.0, 1e-15);
  // (x - 1)(x - 2) times 1e-200: b^2 and 4ac underflowed into the subnormals and the
  // roots came back as 1.33 and 1.5.
  ASSERT_EQ(solve_quadratic(1e-200, -3e-200, 2e-200, roots), 2);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
  EXPECT_NEAR(roots[1], 2.0, 1e-15);
  // x^2 + 1 times 1e300 still has no real root, and 1e-300 (x^2 - 4) two (they were 0, 0).
  EXPECT_EQ(solve_quadratic(1e300, 0.0, 1e300, roots), 0);
  ASSERT_EQ(solve_quadratic(1e-300, 0.0, -4e-300, roots), 2);
  EXPECT_NEAR(roots[0], -2.0, 1e-15);
  EXPECT_NEAR(roots[1], 2.0, 1e-15);
}

TEST(SolveCubic, ThreeRealRootsOneRealRootAndTripleRoot) {
  double roots[3];
  ASSERT_EQ(solve_cubic(1.0, -6.0, 11.0, -6.0, roots), 3);  // (x-1)(x-2)(x-3)
  EXPECT_NEAR(roots[0], 1.0, 1e-14);
  EXPECT_NEAR(roots[1], 2.0, 1e-14);
  EXPECT_NEAR(roots[2], 3.0, 1e-14);
  ASSERT_EQ(solve_cubic(1.0, 0.0, 1.0, -2.0, roots), 1);  // (x-1)(x^2+x+2)
  EXPECT_NEAR(roots[0], 1.0, 1e-14);
  const int n = solve_cubic(1.0, -3.0, 3.0, -1.0, roots);  // (x-1)^3
  ASSERT_GE(n, 1);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(roots[i], 1.0, 1e-5);  // cube-root conditioning
}

TEST(SolveCubic, RootsOfVeryDifferentMagnitudesAreAllFound) {
  // (x - 1)(x - 2)(x - 1e200): the depressed form's shift^3 overflowed and the one root
  // returned was NaN. (x - 1e-150)(x - 1)(x - 1e150) came back as one infinite root.
  double roots[3];
  ASSERT_EQ(solve_cubic(1.0, -(1e200 + 3.0), 3e200 + 2.0, -2e200, roots), 3);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
  EXPECT_NEAR(roots[1], 2.0, 1e-15);
  EXPECT_NEAR(roots[2] / 1e200, 1.0, 1e-15);
  // Coefficients of (x - 1e-150)(x - 1)(x - 1e150), each rounded once.
  ASSERT_EQ(solve_cubic(1.0, -1e150, 1e150, -1.0, roots), 3);
  EXPECT_NEAR(roots[0] / 1e-150, 1.0, 1e-15);
  EXPECT_NEAR(roots[1], 1.0, 1e-15);
  EXPECT_NEAR(roots[2] / 1e150, 1.0, 1e-15);
  // A huge negative root beside a complex pair: x^2 + 1 times (x + 1e250).
  ASSERT_EQ(solve_cubic(1.0, 1e250, 1.0, 1e250, roots), 1);
  EXPECT_NEAR(roots[0] / -1e250, 1.0, 1e-15);
}

struct QuarticCase {
  double c[5];  // c[i] multiplies x^i
  std::vector<double> roots;
};

std::vector<QuarticCase> quartic_cases() {
  return {
      {{24.0, -50.0, 35.0, -10.0, 1.0}, {1.0, 2.0, 3.0, 4.0}},           // (x-1)(x-2)(x-3)(x-4)
      {{1.0, 0.0, 0.0, 0.0, 1.0}, {}},                                   // x^4 + 1
      {{4.0, 0.0, -5.0, 0.0, 1.0}, {-2.0, -1.0, 1.0, 2.0}},              // biquadratic
      {{-2.0, 0.0, -1.0, 0.0, 1.0}, {-std::sqrt(2.0), std::sqrt(2.0)}},  // (x^2-2)(x^2+1)
  };
}

TEST(SolveQuartic, Algorithm1010AndIsolationAgreeWithAnalyticRoots) {
  for (const QuarticCase& q : quartic_cases()) {
    double roots[4];
    const int n = solve_quartic(q.c[4], q.c[3], q.c[2], q.c[1], q.c[0], roots);
    ASSERT_EQ(n, static_cast<int>(q.roots.size()));
    for (int i = 0; i < n; ++i) EXPECT_NEAR(roots[i], q.roots[i], 1e-12);
    const Polynomial<4, double> p{{q.c[0], q.c[1], q.c[2], q.c[3], q.c[4]}};
    const int m = roots_in_interval(p, -10.0, 10.0, roots);
    ASSERT_EQ(m, static_cast<int>(q.roots.size()));
    for (int i = 0; i < m; ++i) EXPECT_NEAR(roots[i], q.roots[i], 1e-12);
  }
}

TEST(SolveQuartic, RootsSpanningEightOrdersOfMagnitude) {
  // (x - 1e-4)(x - 1)(x - 1e2)(x - 1e4), expanded exactly in long double then rounded.
  const long double r[4] = {1e-4L, 1.0L, 1e2L, 1e4L};
  long double c[5] = {1, 0, 0, 0, 0};
  for (long double root : r) {
    for (int i = 4; i > 0; --i) c[i] = c[i - 1] - root * c[i];
    c[0] = -root * c[0];
  }
  double roots[4];
  ASSERT_EQ(solve_quartic<double>(c[4], c[3], c[2], c[1], c[0], roots), 4);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(roots[i], static_cast<double>(r[i]), 1e-9 * static_cast<double>(r[i]));
  const Polynomial<4, double> p{{static_cast<double>(c[0]), static_cast<double>(c[1]),
                                 static_cast<double>(c[2]), static_cast<double>(c[3]),
                                 static_cast<double>(c[4])}};
  ASSERT_EQ(roots_in_interval(p, 0.0, 2e4, roots), 4);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(roots[i], static_cast<double>(r[i]), 1e-9 * static_cast<double>(r[i]));
}

TEST(SolveQuartic, HugeRootsDoNotOverflow) {
  // (x - 1e150)(x + 1e150)(x^2 + 1): coefficients near 1e300.
  double roots[4];
  ASSERT_EQ(solve_quartic(1.0, 0.0, 1.0 - 1e300, 0.0, -1e300, roots), 2);
  EXPECT_NEAR(roots[0], -1e150, 1e138);
  EXPECT_NEAR(roots[1], 1e150, 1e138);
}

// Expanded in long double from its roots (a monic quartic), then rounded to double.
std::array<double, 5> quartic_from_roots(const std::array<long double, 4>& r) {
  long double c[5] = {1, 0, 0, 0, 0};
  for (long double root : r) {
    for (int i = 4; i > 0; --i) c[i] = c[i - 1] - root * c[i];
    c[0] = -root * c[0];
  }
  return {static_cast<double>(c[0]), static_cast<double>(c[1]), static_cast<double>(c[2]),
          static_cast<double>(c[3]), static_cast<double>(c[4])};
}

TEST(SolveQuartic, ScalingDoesNotOverflowForExtremeMagnitudes) {
  // (x - 1)(x - 2)(x - 3)(x - 1e100): the scale is 2^333, whose fourth power overflows;
  // dividing by it zeroed c and d, and only the root 1e100 came back. The small roots are
  // well conditioned (the rounded coefficients decide them to ~1e-16), so all four must.
  const auto c = quartic_from_roots({1.0L, 2.0L, 3.0L, 1e100L});
  double roots[4];
  ASSERT_EQ(solve_quartic(c[4], c[3], c[2], c[1], c[0], roots), 4);
  EXPECT_NEAR(roots[0], 1.0, 1e-12);
  EXPECT_NEAR(roots[1], 2.0, 1e-12);
  EXPECT_NEAR(roots[2], 3.0, 1e-12);
  EXPECT_NEAR(roots[3], 1e100, 1e88);
  // The same polynomial times 2^-600 (every coefficient still normal): the same roots.
  ASSERT_EQ(solve_quartic(std::ldexp(c[4], -600), std::ldexp(c[3], -600), std::ldexp(c[2], -600),
                          std::ldexp(c[1], -600), std::ldexp(c[0], -600), roots),
            4);
  EXPECT_NEAR(roots[0], 1.0, 1e-12);
  EXPECT_NEAR(roots[3], 1e100, 1e88);
}

TEST(SolveQuartic, RootsBeyondOneScalingAreSolvedByIsolation) {
  // (x - 1)(x - 2)(x - 3)(x - 1e200): scaled to make 1e200 O(1), d = 6e200 / 2^2660 falls
  // below double's range and with it the three small roots. First one root (1e200) came
  // back as if it were all, then the solver said it failed; now isolation over Cauchy's
  // bound answers for Algorithm 1010.
  const auto c = quartic_from_roots({1.0L, 2.0L, 3.0L, 1e200L});
  double roots[4];
  // The coefficients are rounded, which moves the small roots by a few ulps.
  ASSERT_EQ(solve_quartic(c[4], c[3], c[2], c[1], c[0], roots), 4);
  EXPECT_NEAR(roots[0], 1.0, 1e-14);
  EXPECT_NEAR(roots[1], 2.0, 1e-14);
  EXPECT_NEAR(roots[2], 3.0, 1e-14);
  EXPECT_NEAR(roots[3] / 1e200, 1.0, 1e-15);
  // (x - 1e300)(x^3 + 1): c = 1 cannot be scaled by 2^-2991 either. Roots -1 and 1e300.
  ASSERT_EQ(solve_quartic(1.0, -1e300, 0.0, 1.0, -1e300, roots), 2);
  EXPECT_NEAR(roots[0], -1.0, 1e-15);
  EXPECT_NEAR(roots[1] / 1e300, 1.0, 1e-15);
}

// A huge root H = +-2^330..2^345 beside three dyadic roots in [-1, 1] (every coefficient
// exact but for the small terms the huge ones absorb): the scaled constant term lands below
// the normal range yet is exact, which the scaling used to accept, and Algorithm 1010's
// small factor then came out complex for 155 of these 896 quartics. Such scalings go to
// isolation now; so does the quartic of the stress suite's seed 146 (its huge-root row),
// whose root -0.2168 was lost the same way.
TEST(SolveQuartic, ExactButSubnormalScalingsAreSolvedByIsolation) {
  const double small[] = {-0.625, -0.21875, 0.8125, 0.375, -0.90625, 0.15625, -0.46875, 0.71875};
  for (int k = 330; k <= 345; ++k)
    for (int i = 0; i < 8; ++i)
      for (int j = i + 1; j < 8; ++j)
        for (int l = j + 1; l < 8; ++l) {
          const double H = std::ldexp(k % 2 ? -1.0 : 1.0, k);
          const double r1 = small[i], r2 = small[j], r3 = small[l];
          const double c3 = -(H + r1 + r2 + r3);
          const double c2 = H * (r1 + r2 + r3) + (r1 * r2 + r1 * r3 + r2 * r3);
          const double c1 = -(H * (r1 * r2 + r1 * r3 + r2 * r3) + r1 * r2 * r3);
          const double c0 = H * r1 * r2 * r3;
          double roots[4];
          ASSERT_EQ(solve_quartic(1.0, c3, c2, c1, c0, roots), 4) << k << " " << i << j << l;
          std::array<double, 4> expected = {H, r1, r2, r3};
          std::sort(expected.begin(), expected.end());
          for (int m = 0; m < 4; ++m)
            EXPECT_NEAR(roots[m], expected[m], 1e-14 * std::fabs(expected[m]))
                << k << " " << i << j << l;
        }
  // Seed 146's quartic (monic; ascending powers in the stress suite's hex), against the
  // stress suite's __float128 roots.
  double roots[4];
  ASSERT_EQ(solve_quartic(1.0, 0x1.b70bcb540ec2cp+339, -0x1.76844d1926976p+333,
                          -0x1.e8a352daf6c73p+338, -0x1.81c7b93bc3e18p+336, roots),
            4);
  const double expected[4] = {-1.9206076753036495e+102, -0.60591181850618758, -0.21681740086524948,
                              0.83605771814384733};
  for (int m = 0; m < 4; ++m) EXPECT_NEAR(roots[m], expected[m], 1e-14 * std::fabs(expected[m]));
}

TEST(RootsInInterval, NonConvergenceIsReportedNotReturned) {
  // (x - 1)(x^2 + 1e300) on [0, 1e300] (inside its Cauchy bound), searched as the torus
  // searches (RootSpan::kBounded: brackets halved arithmetically): p(1e300) overflows,
  // regula falsi and Newton creep down by a factor 2/3 per step, and after
  // kMaxBracketIterations the iterate (~1e270) was returned as the root. Now the search
  // says it did not converge.
  const Polynomial<3, double> p{{-1e300, 1e300, -1.0, 1.0}};
  int visited = 0;
  EXPECT_EQ(detail::visit_roots(
                p, 0.0, 1e300,
                [&](double) {
                  ++visited;
                  return false;
                },
                0.0),
            RootSearch::kNotConverged);
  EXPECT_EQ(visited, 0);
  // The public search halves such brackets in their exponent and finds the root.
  double roots[3];
  ASSERT_EQ(roots_in_interval(p, 0.0, 1e300, roots), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
  EXPECT_EQ(visit_roots_in_interval(p, 0.0, 1e300, [](double) { return false; }),
            RootSearch::kCompleted);
  ASSERT_EQ(roots_in_interval(p, 0.0, 1e3, roots), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
}

TEST(RootsInInterval, RootsEightyToThreeHundredOrdersApartAreAllFound) {
  // Three roots in [-1, 1] beside one of 1e80 to 1e300 (either sign). Before, the critical
  // points separating the small roots were found to 1e-10 of the interval (~1e190 off for
  // 1e200), and the closed-form quadratic of the second derivative overflowed in b^2: the
  // small roots were lost or the search stopped unconverged, on every such quartic.
  // Algorithm 1010 cannot factor these and hands them to this search
  // (SolveQuartic.RootsBeyondOneScalingAreSolvedByIsolation).
  for (const long double huge : {1e80L, -1e150L, 1e200L, -1e250L, 1e300L}) {
    const long double small[3] = {-0.5L, 0.3L, 0.7L};
    const auto c = quartic_from_roots({small[0], small[1], small[2], huge});
    const Polynomial<4, double> p{{c[0], c[1], c[2], c[3], c[4]}};
    const double bound = detail::cauchy_bound(p);
    double roots[4];
    ASSERT_EQ(roots_in_interval(p, -bound, bound, roots), 4) << static_cast<double>(huge);
    const int first_small = huge < 0 ? 1 : 0;
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(roots[first_small + i], static_cast<double>(small[i]), 1e-14);
    const double found_huge = roots[huge < 0 ? 0 : 3];
    EXPECT_NEAR(found_huge / static_cast<double>(huge), 1.0, 1e-14);
  }
}

TEST(RootsInInterval, IntervalsWiderThanTheRootsAreClippedToCauchysBound) {
  // (x - 1)(x^2 + 1) on [0, 1e300]: before, the same creep returned ~4e269 as the root;
  // (x - 0.5)(x - 1.5)(x^2 + 1) on [-1e300, 1e300]: its critical points were located to
  // 1e-10 of the interval (1e290), the pieces came out wrong and roots were lost. Within
  // Cauchy's bound (2 and 3.75 here) both are found to full precision.
  double roots[4];
  ASSERT_EQ(roots_in_interval(Polynomial<3, double>{{-1.0, 1.0, -1.0, 1.0}}, 0.0, 1e300, roots), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
  const Polynomial<4, double> two{{0.75, -2.0, 1.75, -2.0, 1.0}};  // (x^2 - 2x + 0.75)(x^2 + 1)
  ASSERT_EQ(roots_in_interval(two, -1e300, 1e300, roots), 2);
  EXPECT_NEAR(roots[0], 0.5, 1e-15);
  EXPECT_NEAR(roots[1], 1.5, 1e-15);
}

TEST(RootsInInterval, OnlyTheIntervalIsSearchedAndTheVisitorCanStop) {
  const Polynomial<4, double> p{{24.0, -50.0, 35.0, -10.0, 1.0}};  // roots 1, 2, 3, 4
  double roots[4];
  ASSERT_EQ(roots_in_interval(p, 1.5, 3.5, roots), 2);
  EXPECT_NEAR(roots[0], 2.0, 1e-14);
  EXPECT_NEAR(roots[1], 3.0, 1e-14);
  int visited = 0;
  double first = 0.0;
  const RootSearch search = visit_roots_in_interval(p, 0.0, 10.0, [&](double x) {
    ++visited;
    first = x;
    return true;
  });
  EXPECT_EQ(search, RootSearch::kStopped);
  EXPECT_EQ(visited, 1);
  EXPECT_NEAR(first, 1.0, 1e-14);
}

TEST(RootsInInterval, ClosePairsAreSeparatedAndNearMissesInventNothing) {
  // (x - 1)(x - 1 - 1e-6)(x - 2)(x - 2 - 1e-6): two pairs 1e-6 apart, all four found.
  long double c[5] = {1, 0, 0, 0, 0};
  for (long double root : {1.0L, 1.0L + 1e-6L, 2.0L, 2.0L + 1e-6L}) {
    for (int i = 4; i > 0; --i) c[i] = c[i - 1] - root * c[i];
    c[0] = -root * c[0];
  }
  const Polynomial<4, double> pairs{{static_cast<double>(c[0]), static_cast<double>(c[1]),
                                     static_cast<double>(c[2]), static_cast<double>(c[3]),
                                     static_cast<double>(c[4])}};
  double roots[4];
  ASSERT_EQ(roots_in_interval(pairs, 0.0, 3.0, roots), 4);
  // Conditioning: coefficient rounding (1e-16) over the slope at the root (1e-6) ~ 1e-9.
  EXPECT_NEAR(roots[0], 1.0, 1e-8);
  EXPECT_NEAR(roots[1], 1.0 + 1e-6, 1e-8);
  EXPECT_NEAR(roots[2], 2.0, 1e-8);
  EXPECT_NEAR(roots[3], 2.0 + 1e-6, 1e-8);
  // (x - 1)^2 (x - 2)^2 + 1e-10 has no real root (a ray missing a tangent point by a
  // hair): none may be reported.
  const Polynomial<4, double> near_miss{{4.0 + 1e-10, -12.0, 13.0, -6.0, 1.0}};
  EXPECT_EQ(roots_in_interval(near_miss, 0.0, 3.0, roots), 0);
}

TEST(RootsInInterval, AComplexPairBesideARootInventsNoRoot) {
  // Found by the stress suite: real roots 0.8489 and 0.9294, and a complex pair about
  // 0.0008 beyond the second, close to the real axis. At the critical points between them
  // p is ~1e-17 while Horner's rounding error is ~1e-15, so its sign there was noise and a
  // third root was reported at 0.93018. The quad-precision reference finds two.
  const Polynomial<4, double> p{
      {0.68261598893747066, -3.0063246628207003, 4.9623863220952025, -3.6386256258014926, 1.0}};
  double roots[4];
  ASSERT_EQ(roots_in_interval(p, -5.9623863220952025, 5.9623863220952025, roots), 2);
  EXPECT_NEAR(roots[0], 0.84888465388100298, 1e-9);
  // Ill-conditioned beside the pair: p' there is ~1e-8.
  EXPECT_NEAR(roots[1], 0.9293877804576226, 1e-7);
}

TEST(Polynomial, CompensatedHornerDecidesSignsHornerCannot) {
  // (x - 1)^4 at 1 + 2^-20 is 2^-80; Horner's terms there are ~16, so its rounding error
  // (~1e-15) swamps the value, and its running bound says so. Compensated Horner is as
  // accurate as Horner at twice the precision: within its bound of the exact value, and
  // that bound is small enough to give the sign.
  const Polynomial<4, double> p{{1.0, -4.0, 6.0, -4.0, 1.0}};
  const double x = 1.0 + std::ldexp(1.0, -20);
  const double exact = std::ldexp(1.0, -80);
  double horner_bound = 0.0;
  const double horner = p.evaluate_with_error(x, horner_bound);
  EXPECT_GT(horner_bound, std::fabs(horner - exact));
  EXPECT_GT(horner_bound, exact);  // Horner cannot decide the sign
  double bound = 0.0;
  const double compensated = p.evaluate_compensated(x, bound);
  EXPECT_LE(std::fabs(compensated - exact), bound);
  EXPECT_LT(bound, 1e-3 * exact);
  // On both sides of a simple root, signs that plain Horner gets right stay right.
  const Polynomial<2, double> line_pair{{-2.0, 0.0, 1.0}};  // x^2 - 2
  EXPECT_LT(line_pair.evaluate_compensated(1.4142135623730949, bound), 0.0);
  EXPECT_GT(line_pair.evaluate_compensated(1.4142135623730951, bound), 0.0);
}

TEST(PolishRoot, NewtonNeverMakesARootWorse) {
  const Polynomial<3, double> p{{-6.0, 11.0, -6.0, 1.0}};
  EXPECT_NEAR(polish_root(p, 2.001), 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(polish_root(p, 2.0), 2.0);
  const Polynomial<2, double> flat{{1.0, 0.0, 1.0}};  // no real root, p'(0) = 0
  EXPECT_TRUE(std::isfinite(polish_root(flat, 0.0)));
}

}  // namespace
}  // namespace tessera
