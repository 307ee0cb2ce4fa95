// The path tracer's sample dimensions (BounceSamples, render/path_tracer.hpp): each vertex's
// point on a light is the Sobol pair joined to the pair that led to the vertex (the pixel
// position at the first vertex, the previous vertex's BSDF direction after), which
// Sobol.JoinedPairsFormA4DNetWithTheirPartner shows to be stratified jointly with it.
#include <gtest/gtest.h>

#include <cstdint>

#include "tessera/math/rng.hpp"
#include "tessera/render/path_tracer.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kSamples = 64;

TEST(BounceSamples, LightPointIsJoinedToThePairThatLedToTheVertex) {
  for (std::uint32_t depth = 0; depth < 4; ++depth) {
    const std::uint32_t light_dimension = kCameraDimensions + depth * kBounceDimensions +
                                          2 * static_cast<std::uint32_t>(BouncePair::kLightPoint);
    const std::uint32_t partner =
        depth == 0 ? 0u : kCameraDimensions + (depth - 1) * kBounceDimensions;
    std::uint32_t differs_from_unjoined = 0;
    for (std::uint32_t i = 0; i < kSamples; ++i) {
      SampleStream drawn(99, 5, 7, i, SamplerKind::kSobol);
      float a = 0.0f, b = 0.0f;
      BounceSamples::draw(drawn, depth, BouncePair::kLightPoint, a, b);
      SampleStream joined(99, 5, 7, i, SamplerKind::kSobol);
      joined.set_dimension(light_dimension);
      float ja = 0.0f, jb = 0.0f;
      joined.next_2d_joined(partner, ja, jb);
      EXPECT_EQ(a, ja) << "depth " << depth << " sample " << i;
      EXPECT_EQ(b, jb) << "depth " << depth << " sample " << i;
      SampleStream plain(99, 5, 7, i, SamplerKind::kSobol);
      plain.set_dimension(light_dimension);
      float pa = 0.0f, pb = 0.0f;
      plain.next_2d(pa, pb);
      if (pa != a || pb != b) ++differs_from_unjoined;
    }
    // The joined pair is another set than the light dimensions' own pair.
    EXPECT_GT(differs_from_unjoined, kSamples / 2) << "depth " << depth;
  }
}

TEST(BounceSamples, OtherPairsAndTheIndependentSamplerAreUnjoined) {
  for (std::uint32_t i = 0; i < kSamples; ++i)
    for (BouncePair pair : {BouncePair::kBsdfDirection, BouncePair::kLobeAndPick}) {
      SampleStream drawn(3, 1, 2, i, SamplerKind::kSobol);
      float a = 0.0f, b = 0.0f;
      BounceSamples::draw(drawn, 2, pair, a, b);
      SampleStream plain(3, 1, 2, i, SamplerKind::kSobol);
      plain.set_dimension(kCameraDimensions + 2 * kBounceDimensions +
                          2 * static_cast<std::uint32_t>(pair));
      float pa = 0.0f, pb = 0.0f;
      plain.next_2d(pa, pb);
      EXPECT_EQ(a, pa);
      EXPECT_EQ(b, pb);
    }
  // White noise has nothing to join: the light point is the dimensions' own values.
  for (std::uint32_t i = 0; i < kSamples; ++i) {
    SampleStream drawn(3, 1, 2, i, SamplerKind::kIndependent);
    float a = 0.0f, b = 0.0f;
    BounceSamples::draw(drawn, 1, BouncePair::kLightPoint, a, b);
    SampleStream plain(3, 1, 2, i, SamplerKind::kIndependent);
    plain.set_dimension(kCameraDimensions + kBounceDimensions +
                        2 * static_cast<std::uint32_t>(BouncePair::kLightPoint));
    float pa = 0.0f, pb = 0.0f;
    plain.next_2d(pa, pb);
    EXPECT_EQ(a, pa);
    EXPECT_EQ(b, pb);
  }
}

}  // namespace
}  // namespace tessera
