// SobolSeedMemo: a sample stream that reads its pair seeds through a pixel's memo gives the
// values one that hashes them gives, in the order a tile's loop asks for them: all the
// samples of one pixel, then the next pixel, pairs from the camera's to past the memo's
// end, kept and joined pairs, and a job seed that changes under the same pixel.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "tessera/math/rng.hpp"
#include "tessera/math/sobol.hpp"
#include "tessera/math/sobol_seed_memo.hpp"

namespace tessera {
namespace {

// Draws what a path of `depth` vertices draws (the path tracer's order: the camera's kept
// pair; per vertex a kept direction pair, the light point joined to the pair before it and
// a lobe/pick pair; then single values and a far pair like the lens') and returns them.
std::vector<float> draw_path(SampleStream& s, std::uint32_t depth) {
  std::vector<float> values;
  float a = 0.0f, b = 0.0f;
  const auto keep = [&] {
    values.push_back(a);
    values.push_back(b);
  };
  s.set_dimension(0);
  s.next_2d_kept(a, b);
  keep();
  for (std::uint32_t vertex = 0; vertex < depth; ++vertex) {
    const std::uint32_t block = 2 + 6 * vertex;
    const std::uint32_t partner = vertex == 0 ? 0 : block - 6;
    s.set_dimension(block + 2);
    s.next_2d_joined(partner, a, b);  // the light point comes before the direction is drawn
    keep();
    s.set_dimension(block + 4);
    s.next_2d(a, b);
    keep();
    s.set_dimension(block);
    s.next_2d_kept(a, b);
    keep();
  }
  // A pair joined to one that was not kept last, single values, and pairs past the memo.
  s.set_dimension(7);
  s.next_2d_joined(2, a, b);
  keep();
  s.set_dimension(5);
  values.push_back(s.next());
  values.push_back(s.next());
  for (std::uint32_t dimension :
       {2 * SobolSeedMemo::kPairs - 2, 2 * SobolSeedMemo::kPairs, 0x7fff0000U}) {
    s.set_dimension(dimension);
    s.next_2d(a, b);
    keep();
    s.set_dimension(dimension + 4);
    s.next_2d_joined(dimension, a, b);
    keep();
  }
  return values;
}

TEST(SobolSeedMemo, AStreamThroughTheMemoGivesTheValuesOfOneWithout) {
  SobolSeedMemo memo;
  struct Visit {
    std::uint64_t seed;
    std::uint32_t x, y;
  };
  // Pixels in a tile's order, a pixel visited again after another, and a second job seed on
  // a pixel the memo has just held.
  const Visit visits[] = {{7, 0, 0},
                          {7, 1, 0},
                          {7, 0, 1},
                          {7, 0, 0},
                          {8, 0, 0},
                          {7, 0, 0},
                          {0x123456789abcdefULL, 40, 17},
                          {0x223456789abcdefULL, 40, 17}};
  for (const Visit& v : visits)
    for (std::uint32_t sample = 0; sample < 40; ++sample) {
      // Deeper paths on later samples, so pairs are first asked for mid-pixel too.
      const std::uint32_t depth = 1 + (sample * 7) % 25;
      SampleStream plain(v.seed, v.x, v.y, sample, SamplerKind::kSobol);
      SampleStream memoized(v.seed, v.x, v.y, sample, SamplerKind::kSobol, &memo);
      const std::vector<float> expected = draw_path(plain, depth);
      const std::vector<float> got = draw_path(memoized, depth);
      ASSERT_EQ(got.size(), expected.size());
      for (std::size_t i = 0; i < got.size(); ++i)
        ASSERT_EQ(got[i], expected[i]) << "seed " << v.seed << " pixel (" << v.x << ", " << v.y
                                       << ") sample " << sample << " value " << i;
    }
}

TEST(SobolSeedMemo, HoldsThePairSeedsOfThePixelLastAsked) {
  SobolSeedMemo memo;
  const std::uint32_t key = memo.pixel_key(99, 3, 4);
  EXPECT_EQ(key, sobol_pixel_key(99, 3, 4));
  for (std::uint32_t pair = 0; pair < SobolSeedMemo::kPairs; ++pair) {
    const SobolPairSeeds& got = memo.seeds(pair);
    const SobolPairSeeds expected = sobol_pair_seeds(key, pair);
    EXPECT_EQ(got.shuffle, expected.shuffle) << pair;
    EXPECT_EQ(got.x, expected.x) << pair;
    EXPECT_EQ(got.y, expected.y) << pair;
    EXPECT_EQ(got.joined_x, expected.joined_x) << pair;
    EXPECT_EQ(got.joined_y, expected.joined_y) << pair;
  }
  // Another pixel: its own seeds, not the ones just filled.
  const std::uint32_t other = memo.pixel_key(99, 4, 3);
  EXPECT_NE(other, key);
  EXPECT_EQ(memo.seeds(5).x, sobol_pair_seeds(other, 5).x);
}

// The independent sampler ignores the memo: the same values as the four-argument stream.
TEST(SobolSeedMemo, TheIndependentSamplerIsUnchanged) {
  SobolSeedMemo memo;
  for (std::uint32_t sample = 0; sample < 8; ++sample) {
    SampleStream plain(5, 2, 3, sample);
    SampleStream with_memo(5, 2, 3, sample, SamplerKind::kIndependent, &memo);
    for (int i = 0; i < 16; ++i) EXPECT_EQ(with_memo.next(), plain.next());
  }
}

}  // namespace
}  // namespace tessera
