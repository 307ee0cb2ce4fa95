// The PNG preview's exposure and tone curves.
#include <gtest/gtest.h>

#include <cmath>

#include "tessera/image/exr.hpp"

namespace tessera {
namespace {

TEST(PreviewTone, ClampIsThePlainClipAndExposureIsInStops) {
  const PreviewOptions plain;
  EXPECT_EQ(tone_map(0.25f, plain), 0.25f);
  EXPECT_EQ(tone_map(3.0f, plain), 1.0f);
  EXPECT_EQ(tone_map(-1.0f, plain), 0.0f);
  EXPECT_EQ(tone_map(std::nanf(""), plain), 0.0f);
  const PreviewOptions two_stops{.exposure = 2.0f};
  EXPECT_FLOAT_EQ(tone_map(0.125f, two_stops), 0.5f);
  const PreviewOptions darker{.exposure = -1.0f};
  EXPECT_FLOAT_EQ(tone_map(1.5f, darker), 0.75f);
}

// Narkowicz's ACES fit: 0 stays black, the curve rises monotonically, highlights roll off
// towards (not past) white instead of clipping, and mid grey 0.18 lands near the fit's
// value (0.18 (2.51 0.18 + 0.03) / (0.18 (2.43 0.18 + 0.59) + 0.14) = 0.26690).
TEST(PreviewTone, AcesRollsHighlightsOffMonotonically) {
  const PreviewOptions aces{.curve = ToneCurve::kAces};
  EXPECT_EQ(tone_map(0.0f, aces), 0.0f);
  EXPECT_NEAR(tone_map(0.18f, aces), 0.26690f, 1e-4f);
  float previous = 0.0f;
  for (float c = 0.01f; c < 64.0f; c *= 1.25f) {
    const float v = tone_map(c, aces);
    EXPECT_GE(v, previous) << c;
    EXPECT_LE(v, 1.0f);
    previous = v;
  }
  EXPECT_LT(tone_map(1.0f, aces), 0.81f);  // where the clamp would already be white
  EXPECT_GT(tone_map(16.0f, aces), 0.99f);
}

}  // namespace
}  // namespace tessera
