// The Owen-scrambled Sobol sampler (math/sobol.hpp): the generator matrices, the scramble's
// nesting, the net and stratification properties of every pixel's power-of-two prefixes,
// joined pairs' 4D nets, independence between dimension pairs, and faster convergence than
// white noise.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "tessera/math/rng.hpp"
#include "tessera/math/sobol.hpp"

namespace tessera {
namespace {

struct Pixel {
  std::uint64_t seed;
  std::uint32_t x, y;
};
constexpr Pixel kPixels[] = {{0, 0, 0}, {0, 1, 0}, {7, 17, 923}, {12345678901ull, 4095, 4095}};

TEST(Sobol, MatrixColumnsFollowTheDirectionNumberRecurrence) {
  // Dimension 1 from x + 1, m_1 = 1, m_k = 2 m_{k-1} xor m_{k-1}: m = 1, 3, 5, 15, 17, 51.
  const std::uint32_t m[] = {1, 3, 5, 15, 17, 51};
  for (std::uint32_t k = 0; k < 6; ++k) {
    EXPECT_EQ(sobol_matrix_column(0, k), 1U << (31 - k));
    EXPECT_EQ(sobol_matrix_column(1, k), m[k] << (31 - k)) << k;
  }
  // sobol_2d generates the columns on the fly; it must be the matrix product.
  for (std::uint32_t index : {0U, 1U, 2U, 3U, 77U, 0x80000001U, 0xdeadbeefU, 0xffffffffU}) {
    std::uint32_t x = 0, y = 0, ex = 0, ey = 0;
    sobol_2d(index, x, y);
    for (std::uint32_t bit = 0; bit < 32; ++bit)
      if ((index >> bit) & 1U) {
        ex ^= sobol_matrix_column(0, bit);
        ey ^= sobol_matrix_column(1, bit);
      }
    EXPECT_EQ(x, ex) << index;
    EXPECT_EQ(y, ey) << index;
  }
  // The first points of the sequence: (0, 0), (1/2, 1/2), (1/4, 3/4), (3/4, 1/4).
  const std::uint32_t first[4][2] = {
      {0, 0}, {0x80000000U, 0x80000000U}, {0x40000000U, 0xc0000000U}, {0xc0000000U, 0x40000000U}};
  for (std::uint32_t i = 0; i < 4; ++i) {
    std::uint32_t x = 0, y = 0;
    sobol_2d(i, x, y);
    EXPECT_EQ(x, first[i][0]);
    EXPECT_EQ(y, first[i][1]);
  }
}

TEST(Sobol, ReverseBitsMirrors) {
  EXPECT_EQ(reverse_bits(1U), 0x80000000U);
  EXPECT_EQ(reverse_bits(0x0000000fU), 0xf0000000U);
  EXPECT_EQ(reverse_bits(0x12345678U), 0x1e6a2c48U);
}

TEST(Sobol, PartialMirrorsAreTheFullMirrorsBits) {
  // The table mirrors the sampler uses where it keeps 16 or 24 bits: every bit of every
  // byte position (single bits, all ones, hashed values).
  std::vector<std::uint32_t> values = {0U, ~0U};
  for (std::uint32_t bit = 0; bit < 32; ++bit) values.push_back(1U << bit);
  for (std::uint32_t i = 0; i < 4096; ++i) values.push_back(mix32(i));
  for (std::uint32_t x : values) {
    EXPECT_EQ(reverse_high_16_bits(x), reverse_bits(x) & 0xffffU) << x;
    EXPECT_EQ(reverse_low_24_bits(x), reverse_bits(x) >> 8) << x;
    EXPECT_EQ(unit_float_from_mirrored(x), uint_to_unit_float(reverse_bits(x))) << x;
  }
}

TEST(Sobol, NestedUniformScrambleKeepsPrefixesAndPermutes) {
  for (std::uint32_t seed : {0U, 1U, 0x9e3779b9U, 0xffffffffU}) {
    // Values sharing their first k binary digits share them after the scramble...
    for (std::uint32_t k = 1; k < 32; k += 3) {
      const std::uint32_t keep = ~0U << (32 - k);
      for (std::uint32_t i = 0; i < 64; ++i) {
        const std::uint32_t a = mix32(i * 2 + 1);
        const std::uint32_t b = (a & keep) | (mix32(i * 2 + 2) & ~keep);
        EXPECT_EQ(nested_uniform_scramble(a, seed) & keep, nested_uniform_scramble(b, seed) & keep)
            << "seed " << seed << " k " << k;
      }
    }
    // ...and the 2^12 intervals of width 2^-12 are permuted, none merged.
    std::vector<bool> seen(4096, false);
    for (std::uint32_t i = 0; i < 4096; ++i)
      seen[nested_uniform_scramble(i << 20, seed) >> 20] = true;
    for (std::uint32_t i = 0; i < 4096; ++i) ASSERT_TRUE(seen[i]) << seed;
  }
  // The seed matters: a scramble that ignored it would make every pixel the same.
  EXPECT_NE(nested_uniform_scramble(0x12345678U, 1), nested_uniform_scramble(0x12345678U, 2));
}

// Exactly one of the first 2^k points in each elementary interval of area 2^-k: for every
// split k = a + b, the grid of 2^a columns by 2^b rows has one point per cell.
bool is_0_k_2_net(const std::vector<float>& xs, const std::vector<float>& ys, std::uint32_t k) {
  const std::uint32_t n = 1U << k;
  for (std::uint32_t a = 0; a <= k; ++a) {
    const std::uint32_t b = k - a;
    std::vector<int> count(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      // Exact: the values are multiples of 2^-24 and k <= 24.
      const auto cx = static_cast<std::uint32_t>(xs[i] * static_cast<float>(1U << a));
      const auto cy = static_cast<std::uint32_t>(ys[i] * static_cast<float>(1U << b));
      if (++count[(cy << a) | cx] > 1) return false;
    }
  }
  return true;
}

TEST(Sobol, UnscrambledPrefixesAreNets) {
  for (std::uint32_t k = 1; k <= 10; ++k) {
    std::vector<float> xs, ys;
    for (std::uint32_t i = 0; i < (1U << k); ++i) {
      std::uint32_t x = 0, y = 0;
      sobol_2d(i, x, y);
      xs.push_back(uint_to_unit_float(x));
      ys.push_back(uint_to_unit_float(y));
    }
    EXPECT_TRUE(is_0_k_2_net(xs, ys, k)) << k;
  }
}

TEST(Sobol, EveryPairOfEveryPixelIsANetAtEveryPowerOfTwo) {
  for (const Pixel& p : kPixels)
    for (std::uint32_t first_dimension : {0U, 2U, 6U, 30U})
      for (std::uint32_t k = 4; k <= 8; ++k) {
        std::vector<float> xs, ys;
        for (std::uint32_t i = 0; i < (1U << k); ++i) {
          SampleStream s(p.seed, p.x, p.y, i, SamplerKind::kSobol);
          s.set_dimension(first_dimension);
          float a = 0.0f, b = 0.0f;
          s.next_2d(a, b);
          xs.push_back(a);
          ys.push_back(b);
        }
        EXPECT_TRUE(is_0_k_2_net(xs, ys, k))
            << "pixel (" << p.x << ", " << p.y << ") seed " << p.seed << ", dimensions "
            << first_dimension << " and " << first_dimension + 1 << ", 2^" << k << " samples";
      }
}

TEST(Sobol, EveryDimensionIsStratifiedAtEveryPowerOfTwo) {
  for (const Pixel& p : kPixels)
    for (std::uint32_t dimension : {0U, 1U, 2U, 5U, 31U})
      for (std::uint32_t k = 4; k <= 10; ++k) {
        const std::uint32_t n = 1U << k;
        std::vector<bool> hit(n, false);
        for (std::uint32_t i = 0; i < n; ++i) {
          const auto cell = static_cast<std::uint32_t>(
              sobol_sample(p.seed, p.x, p.y, i, dimension) * static_cast<float>(n));
          EXPECT_FALSE(hit[cell]) << "dimension " << dimension << ", 2^" << k << " samples";
          hit[cell] = true;
        }
      }
}

TEST(Sobol, DimensionPairsAreUncorrelated) {
  // Pearson correlation over 4096 samples. Independent uniforms give a standard deviation of
  // 1/sqrt(4096) = 0.016; the bound is about 4 of those. Pairs that shared their shuffle
  // (one Sobol index for all dimensions) correlate far more than that, since dimension 0
  // and dimension 2 would then be scrambles of one value.
  constexpr std::uint32_t kSamples = 4096;
  constexpr double kBound = 0.06;
  const std::uint32_t pairs[][2] = {{0, 2}, {1, 3}, {0, 3}, {2, 4}, {1, 9}};
  for (const Pixel& p : kPixels)
    for (const auto& dims : pairs) {
      double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
      for (std::uint32_t i = 0; i < kSamples; ++i) {
        const double x = sobol_sample(p.seed, p.x, p.y, i, dims[0]);
        const double y = sobol_sample(p.seed, p.x, p.y, i, dims[1]);
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
      }
      const double n = kSamples;
      const double r = (sxy / n - sx / n * sy / n) /
                       std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
      EXPECT_LT(std::abs(r), kBound) << "dimensions " << dims[0] << " and " << dims[1]
                                     << ", pixel (" << p.x << ", " << p.y << ")";
    }
}

// Sobol dimensions 2 and 3 from their direction numbers by Bratley and Fox's integer
// recurrence, m_k = 2 a_1 m_{k-1} ^ 4 a_2 m_{k-2} ^ ... ^ 2^s m_{k-s} ^ m_{k-s}: an
// independent formulation of what sobol_dimensions23 computes.
std::uint32_t reference_upper_column(std::uint32_t dimension, std::uint32_t bit) {
  // Joe and Kuo: dimension 2 is x^2 + x + 1 (s = 2, a = 1, m = 1, 3); dimension 3 is
  // x^3 + x + 1 (s = 3, a = 1: inner coefficients 0, 1; m = 1, 3, 1).
  const std::uint32_t s = dimension == 2 ? 2 : 3;
  const std::vector<std::uint32_t> inner =
      dimension == 2 ? std::vector<std::uint32_t>{1} : std::vector<std::uint32_t>{0, 1};
  std::vector<std::uint64_t> m =
      dimension == 2 ? std::vector<std::uint64_t>{1, 3} : std::vector<std::uint64_t>{1, 3, 1};
  for (std::uint32_t k = s; k <= bit; ++k) {
    std::uint64_t next = (m[k - s] << s) ^ m[k - s];
    for (std::uint32_t j = 1; j < s; ++j)
      if (inner[j - 1] != 0) next ^= m[k - j] << j;
    m.push_back(next);
  }
  return static_cast<std::uint32_t>(m[bit] << (31 - bit));
}

TEST(Sobol, JoinedDimensionsFollowTheDirectionNumbers) {
  // Index 2^bit is column `bit` of each dimension.
  for (std::uint32_t bit = 0; bit < 32; ++bit) {
    std::uint32_t x = 0, y = 0;
    sobol_dimensions23(1U << bit, x, y);
    EXPECT_EQ(x, reference_upper_column(2, bit)) << "dimension 2 bit " << bit;
    EXPECT_EQ(y, reference_upper_column(3, bit)) << "dimension 3 bit " << bit;
  }
  // The first points, worked by hand from the columns v_1 = 1/2, v_2 = 3/4 of both and
  // v_3 = m_3 / 8 (m_3 = 3 for dimension 2, 1 for dimension 3): 0, 1/2, 3/4, 1/4, then 3/8
  // and 1/8. The loop (the device's) and the host's mirrored tables agree.
  const std::uint32_t first2[] = {0, 0x80000000U, 0xc0000000U, 0x40000000U, 0x60000000U};
  const std::uint32_t first3[] = {0, 0x80000000U, 0xc0000000U, 0x40000000U, 0x20000000U};
  for (std::uint32_t i = 0; i < 5; ++i) {
    std::uint32_t x = 0, y = 0;
    sobol_dimensions23(i, x, y);
    EXPECT_EQ(x, first2[i]) << i;
    EXPECT_EQ(y, first3[i]) << i;
  }
  for (std::uint32_t index = 0; index < (1U << kSobolIndexBits); index += 7) {
    std::uint32_t x = 0, y = 0, mx = 0, my = 0;
    sobol_dimensions23(index, x, y);
    sobol_dimensions23_mirrored(index, mx, my);
    ASSERT_EQ(reverse_bits(x), mx) << index;
    ASSERT_EQ(reverse_bits(y), my) << index;
  }
}

// Whether the first 2^k points are a (t, k, 4)-net: every elementary interval of volume
// 2^(t - k) (a grid of 2^d_j cells along axis j, d_0 + ... + d_3 = k - t) holds 2^t points.
bool is_t_k_4_net(const std::vector<std::array<float, 4>>& points, std::uint32_t t,
                  std::uint32_t k) {
  const std::uint32_t total = k - t;
  for (std::uint32_t d0 = 0; d0 <= total; ++d0)
    for (std::uint32_t d1 = 0; d0 + d1 <= total; ++d1)
      for (std::uint32_t d2 = 0; d0 + d1 + d2 <= total; ++d2) {
        const std::uint32_t d[4] = {d0, d1, d2, total - d0 - d1 - d2};
        std::vector<std::uint32_t> count(std::size_t{1} << total, 0);
        for (std::uint32_t i = 0; i < (1U << k); ++i) {
          std::uint32_t cell = 0;
          for (int j = 0; j < 4; ++j)
            cell = (cell << d[j]) |
                   static_cast<std::uint32_t>(points[i][j] * static_cast<float>(1U << d[j]));
          if (++count[cell] > (1U << t)) return false;
        }
      }
  return true;
}

TEST(Sobol, JoinedPairsFormA4DNetWithTheirPartner) {
  // Sobol dimensions 0-3 are a (3, 4)-sequence (t = 0 + 0 + 1 + 2 from the polynomials'
  // degrees); the shared index shuffle and the nested scrambles keep every power-of-two
  // prefix a (3, k, 4)-net. Two pairs drawn independently (each its own shuffle) fail this
  // at once: their cells hold Poisson-like counts.
  for (const Pixel& p : kPixels)
    for (std::uint32_t partner : {0U, 2U, 8U, 20U})
      for (std::uint32_t k = 6; k <= 9; ++k) {
        std::vector<std::array<float, 4>> joined, unjoined;
        for (std::uint32_t i = 0; i < (1U << k); ++i) {
          SampleStream s(p.seed, p.x, p.y, i, SamplerKind::kSobol);
          std::array<float, 4> point{};
          s.set_dimension(partner);
          s.next_2d(point[0], point[1]);
          s.set_dimension(partner + 4);
          std::array<float, 4> other = point;
          s.next_2d_joined(partner, point[2], point[3]);
          s.set_dimension(partner + 4);
          s.next_2d(other[2], other[3]);
          joined.push_back(point);
          unjoined.push_back(other);
        }
        EXPECT_TRUE(is_t_k_4_net(joined, 3, k))
            << "pixel (" << p.x << ", " << p.y << ") partner " << partner << ", 2^" << k;
        EXPECT_FALSE(is_t_k_4_net(unjoined, 3, k)) << "partner " << partner << ", 2^" << k;
      }
}

TEST(Sobol, AKeptShuffleGivesTheSameValuesAsAFreshOne) {
  // next_2d_kept keeps its pair's index shuffle for next_2d_joined. The values must be those
  // next_2d and a joined pair formed from scratch give, whether the kept pair is the partner
  // (the shuffle is reused) or another pair (it must not be).
  for (const Pixel& p : kPixels)
    for (std::uint32_t partner : {0U, 2U, 8U, 20U})
      for (std::uint32_t i = 0; i < 256; ++i) {
        SampleStream fresh(p.seed, p.x, p.y, i, SamplerKind::kSobol);
        SampleStream kept = fresh, other = fresh;
        float f[4], k[4], o[4];
        fresh.set_dimension(partner);
        fresh.next_2d(f[0], f[1]);
        fresh.set_dimension(partner + 4);
        fresh.next_2d_joined(partner, f[2], f[3]);
        kept.set_dimension(partner);
        kept.next_2d_kept(k[0], k[1]);
        kept.set_dimension(partner + 4);
        kept.next_2d_joined(partner, k[2], k[3]);
        other.set_dimension(partner + 2);
        other.next_2d_kept(o[0], o[1]);
        other.set_dimension(partner + 4);
        other.next_2d_joined(partner, o[2], o[3]);
        for (int d = 0; d < 4; ++d) EXPECT_EQ(k[d], f[d]) << "sample " << i << " dimension " << d;
        EXPECT_EQ(o[2], f[2]) << "sample " << i;
        EXPECT_EQ(o[3], f[3]) << "sample " << i;
      }
}

TEST(Sobol, JoinedPairsAreStratifiedOnTheirOwn) {
  // The joined pair alone (Sobol dimensions 2 and 3) is a (1, k, 2)-net: every elementary
  // interval of area 2^(1 - k) holds two points, and each coordinate is a (0, k, 1)-net.
  for (const Pixel& p : kPixels)
    for (std::uint32_t k = 4; k <= 10; ++k) {
      const std::uint32_t n = 1U << k;
      for (std::uint32_t a = 0; a + 1 <= k; ++a) {
        const std::uint32_t b = k - 1 - a;
        std::vector<int> count(n / 2, 0);
        for (std::uint32_t i = 0; i < n; ++i) {
          SampleStream s(p.seed, p.x, p.y, i, SamplerKind::kSobol);
          float u = 0.0f, v = 0.0f;
          s.next_2d_joined(2, u, v);
          const auto cu = static_cast<std::uint32_t>(u * static_cast<float>(1U << a));
          const auto cv = static_cast<std::uint32_t>(v * static_cast<float>(1U << b));
          ++count[(cv << a) | cu];
        }
        for (int c : count) ASSERT_EQ(c, 2) << "2^" << k << " split " << a << "+" << b;
      }
      std::vector<int> u_cells(n, 0), v_cells(n, 0);
      for (std::uint32_t i = 0; i < n; ++i) {
        SampleStream s(p.seed, p.x, p.y, i, SamplerKind::kSobol);
        float u = 0.0f, v = 0.0f;
        s.next_2d_joined(2, u, v);
        ++u_cells[static_cast<std::uint32_t>(u * static_cast<float>(n))];
        ++v_cells[static_cast<std::uint32_t>(v * static_cast<float>(n))];
      }
      for (std::uint32_t c = 0; c < n; ++c) {
        ASSERT_EQ(u_cells[c], 1) << "2^" << k;
        ASSERT_EQ(v_cells[c], 1) << "2^" << k;
      }
    }
}

// RMS error over 64 pixels of the mean of f over each pixel's first n samples (dimensions
// 0 and 1).
template <typename F>
double rms_error(SamplerKind kind, std::uint32_t n, F f, double exact) {
  double sum_squares = 0.0;
  constexpr std::uint32_t kPixelCount = 64;
  for (std::uint32_t pixel = 0; pixel < kPixelCount; ++pixel) {
    double sum = 0.0;
    for (std::uint32_t i = 0; i < n; ++i) {
      SampleStream s(2024, pixel % 8, pixel / 8, i, kind);
      float x = 0.0f, y = 0.0f;
      s.next_2d(x, y);
      sum += f(x, y);
    }
    const double error = sum / n - exact;
    sum_squares += error * error;
  }
  return std::sqrt(sum_squares / kPixelCount);
}

TEST(Sobol, SmoothIntegrandsConvergeFasterThanWhiteNoise) {
  struct Case {
    const char* name;
    double (*f)(double, double);
    double exact;
  };
  const Case cases[] = {
      {"sin(pi x) sin(pi y)",
       [](double x, double y) {
         return std::sin(std::numbers::pi * x) * std::sin(std::numbers::pi * y);
       },
       4.0 / (std::numbers::pi * std::numbers::pi)},
      // Not separable, so 1D stratification alone does not explain the result.
      {"1 / (1 + x + y)", [](double x, double y) { return 1.0 / (1.0 + x + y); },
       3.0 * std::log(3.0) - 4.0 * std::log(2.0)},
  };
  for (const Case& c : cases) {
    const double independent_64 = rms_error(SamplerKind::kIndependent, 64, c.f, c.exact);
    const double independent_1024 = rms_error(SamplerKind::kIndependent, 1024, c.f, c.exact);
    const double sobol_64 = rms_error(SamplerKind::kSobol, 64, c.f, c.exact);
    const double sobol_1024 = rms_error(SamplerKind::kSobol, 1024, c.f, c.exact);
    // At 1024 samples white noise has error ~ sigma / 32 and scrambled nets ~ N^-1.5 for
    // smooth integrands: require at least 10x less error.
    EXPECT_LT(sobol_1024 * 10.0, independent_1024) << c.name;
    // Sixteen times the samples: white noise gains ~4x (N^-0.5). Require Sobol to gain at
    // least 16x, i.e. converge at least as fast as N^-1 (it should be ~N^-1.5, 64x).
    EXPECT_GT(sobol_64 / sobol_1024, 16.0) << c.name;
    EXPECT_LT(independent_64 / independent_1024, 8.0) << c.name;
    std::printf("%s: RMS error independent %.3g -> %.3g, sobol %.3g -> %.3g (64 -> 1024 spp)\n",
                c.name, independent_64, independent_1024, sobol_64, sobol_1024);
  }
}

}  // namespace
}  // namespace tessera
