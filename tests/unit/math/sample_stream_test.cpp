// SampleStream: both kinds are pure functions of (seed, pixel, sample index, dimension);
// the four-argument form is the independent sampler, value for value as before kinds.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>

#include "tessera/math/rng.hpp"
#include "tessera/math/sobol.hpp"

namespace tessera {
namespace {

constexpr SamplerKind kKinds[] = {SamplerKind::kIndependent, SamplerKind::kSobol};

TEST(SampleStream, FourArgumentsKeepTheIndependentValues) {
  // Values the stream gave before it had kinds (times 2^24, so they compare exactly):
  // renders with the independent sampler stay the same image.
  SampleStream a(0, 3, 7, 11);
  EXPECT_EQ(a.kind(), SamplerKind::kIndependent);
  for (std::uint32_t expected : {4320463u, 353025u, 14505605u, 6607684u})
    EXPECT_EQ(a.next() * 16777216.0f, static_cast<float>(expected));
  SampleStream b(12345678901ull, 3, 7, 11, SamplerKind::kIndependent);
  for (std::uint32_t expected : {5136652u, 2618936u, 10198333u, 14403161u})
    EXPECT_EQ(b.next() * 16777216.0f, static_cast<float>(expected));
}

TEST(SampleStream, SameInputsSameValuesOtherPixelsOtherValues) {
  for (SamplerKind kind : kKinds) {
    SampleStream a(42, 5, 9, 3, kind);
    SampleStream b(42, 5, 9, 3, kind);
    SampleStream other_x(42, 6, 9, 3, kind);
    SampleStream other_y(42, 5, 10, 3, kind);
    SampleStream other_seed(43, 5, 9, 3, kind);
    SampleStream other_sample(42, 5, 9, 4, kind);
    int differ_x = 0, differ_y = 0, differ_seed = 0, differ_sample = 0;
    for (int d = 0; d < 32; ++d) {
      const float v = a.next();
      EXPECT_EQ(v, b.next());
      differ_x += v != other_x.next();
      differ_y += v != other_y.next();
      differ_seed += v != other_seed.next();
      differ_sample += v != other_sample.next();
    }
    // 24-bit values: a coincidence in one of 32 dimensions is possible but rare; most
    // must differ.
    EXPECT_GE(differ_x, 30) << static_cast<int>(kind);
    EXPECT_GE(differ_y, 30) << static_cast<int>(kind);
    EXPECT_GE(differ_seed, 30) << static_cast<int>(kind);
    EXPECT_GE(differ_sample, 30) << static_cast<int>(kind);
  }
}

TEST(SampleStream, ValuesAreInTheUnitInterval) {
  for (SamplerKind kind : kKinds)
    for (std::uint32_t sample = 0; sample < 2048; ++sample) {
      SampleStream s(7, sample % 13, sample / 13, sample, kind);
      for (int d = 0; d < 24; ++d) {
        const float v = s.next();
        ASSERT_GE(v, 0.0f);
        ASSERT_LT(v, 1.0f);
      }
    }
}

TEST(SampleStream, SobolValuesAreSobolSampleOfTheirDimension) {
  SampleStream s(99, 12, 34, 56, SamplerKind::kSobol);
  for (std::uint32_t d = 0; d < 10; ++d) EXPECT_EQ(s.next(), sobol_sample(99, 12, 34, 56, d));
  s.set_dimension(40);
  EXPECT_EQ(s.dimension(), 40u);
  EXPECT_EQ(s.next(), sobol_sample(99, 12, 34, 56, 40));
}

TEST(SampleStream, Next2dReadsOnePairStartingAtAnEvenDimension) {
  for (SamplerKind kind : kKinds) {
    SampleStream pairs(5, 1, 2, 3, kind);
    SampleStream singles(5, 1, 2, 3, kind);
    float a = 0.0f, b = 0.0f;
    pairs.next_2d(a, b);  // dimensions 0, 1
    EXPECT_EQ(pairs.dimension(), 2u);
    EXPECT_EQ(a, singles.next());
    EXPECT_EQ(b, singles.next());
    (void)pairs.next();  // dimension 2; the next pair skips 3
    pairs.next_2d(a, b);
    EXPECT_EQ(pairs.dimension(), 6u);
    singles.set_dimension(4);
    EXPECT_EQ(a, singles.next());
    EXPECT_EQ(b, singles.next());
  }
}

TEST(SampleStream, SetDimensionMakesABlockIndependentOfWhatCameBefore) {
  for (SamplerKind kind : kKinds) {
    SampleStream long_path(8, 4, 4, 9, kind);
    SampleStream short_path(8, 4, 4, 9, kind);
    for (int i = 0; i < 7; ++i) (void)long_path.next();
    long_path.set_dimension(16);
    short_path.set_dimension(16);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(long_path.next(), short_path.next());
  }
}

}  // namespace
}  // namespace tessera
