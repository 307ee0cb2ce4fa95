// build_alias_table and alias_pick: draws follow the weights (chi-square), zero and
// negative weights are never drawn.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "chi2.hpp"
#include "tessera/math/alias_table.hpp"

namespace tessera {
namespace {

// Draws `draws` indices and returns how often each came up.
std::vector<double> draw_counts(const std::vector<AliasSlot>& table, int draws,
                                std::uint64_t seed) {
  test::UniformFloats u(seed);
  std::vector<double> counts(table.size(), 0.0);
  for (int i = 0; i < draws; ++i) {
    const std::uint32_t index =
        alias_pick(table.data(), static_cast<std::uint32_t>(table.size()), u());
    if (index >= table.size()) {
      ADD_FAILURE() << "index " << index << " out of range";
      return counts;
    }
    counts[index] += 1.0;
  }
  return counts;
}

// Two tables (skewed weights with zeros; many nearly equal weights) are tested: Bonferroni
// over 2 tests.
constexpr int kChi2Tests = 2;

TEST(AliasTable, DrawsFollowTheWeightsAndNeverZeroWeights) {
  const std::vector<double> weights = {5.0, 0.0, 1.0, 0.25, 100.0, 0.0, -3.0, 7.5, 0.01, 42.0};
  const auto table = build_alias_table(weights);
  ASSERT_EQ(table.size(), weights.size());
  constexpr int kDraws = 1000000;
  const std::vector<double> counts = draw_counts(table, kDraws, 42);
  double total = 0.0;
  for (double w : weights) total += w > 0.0 ? w : 0.0;
  std::vector<double> expected(weights.size());
  for (std::size_t i = 0; i < weights.size(); ++i) {
    expected[i] = weights[i] > 0.0 ? kDraws * weights[i] / total : 0.0;
    if (weights[i] <= 0.0) {
      EXPECT_EQ(counts[i], 0.0) << "weight " << weights[i] << " at " << i;
    }
  }
  const test::Chi2Result chi2 = test::pearson_chi2(counts, expected);
  std::printf("[chi2] alias skewed p = %.4g (%s)\n", chi2.p_value, chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << chi2.summary;
}

TEST(AliasTable, ManyNearlyEqualWeights) {
  std::vector<double> weights(1000);
  for (std::size_t i = 0; i < weights.size(); ++i)
    weights[i] = i % 7 == 3 ? 0.0 : 1.0 + 1e-3 * static_cast<double>(i % 13);
  const auto table = build_alias_table(weights);
  constexpr int kDraws = 1000000;
  const std::vector<double> counts = draw_counts(table, kDraws, 4242);
  double total = 0.0;
  for (double w : weights) total += w;
  std::vector<double> expected(weights.size());
  for (std::size_t i = 0; i < weights.size(); ++i) {
    expected[i] = kDraws * weights[i] / total;
    if (weights[i] == 0.0) {
      EXPECT_EQ(counts[i], 0.0) << "at " << i;
    }
  }
  const test::Chi2Result chi2 = test::pearson_chi2(counts, expected);
  std::printf("[chi2] alias equal p = %.4g (%s)\n", chi2.p_value, chi2.summary.c_str());
  EXPECT_GT(chi2.p_value, test::bonferroni_alpha(kChi2Tests)) << chi2.summary;
}

TEST(AliasTable, AllZeroWeightsAreUniformAndEdgesStayInRange) {
  const auto table = build_alias_table(std::vector<double>{0.0, 0.0, 0.0, 0.0});
  for (float u : {0.0f, 0.2499f, 0.25f, 0.5f, 0.999f, 0x1.fffffep-1f}) {
    const std::uint32_t i = alias_pick(table.data(), 4, u);
    EXPECT_EQ(i, std::min(3u, static_cast<std::uint32_t>(u * 4.0f)));
  }
  const auto single = build_alias_table(std::vector<double>{3.0});
  EXPECT_EQ(alias_pick(single.data(), 1, 0x1.fffffep-1f), 0u);
}

}  // namespace
}  // namespace tessera
