#include "tessera/render/output_channels.hpp"

#include <gtest/gtest.h>

#include "tessera/image/exr.hpp"

namespace tessera {
namespace {

TEST(OutputChannels, NamesFollowTheAovMaskInOrder) {
  EXPECT_EQ(output_channels(0), (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(output_channels(kAovNormal | kAovAlbedo),
            (std::vector<std::string>{"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B",
                                      "normal.X", "normal.Y", "normal.Z"}));
  EXPECT_EQ(output_channels(kAllAovs).size(), 16u);
}

TEST(OutputChannels, InterleavesEveryPlaneAndRoundTripsThroughExr) {
  TilePasses passes;
  passes.beauty = {1, 2, 3, 4, 5, 6, 7, 8};
  passes.aovs[2] = {9, 9, 9, 1, 10, 10, 10, 1};     // depth
  passes.aovs[3] = {11, 11, 11, 1, 12, 12, 12, 1};  // primitive id
  const std::uint32_t mask = kAovDepth | kAovPrimitiveId;
  const std::vector<float> interleaved = interleave_passes(passes, mask);
  EXPECT_EQ(interleaved, (std::vector<float>{1, 2, 3, 4, 9, 11, 5, 6, 7, 8, 10, 12}));

  const auto bytes = encode_exr(interleaved, 2, 1, output_channels(mask), 0, 0);
  const ChannelImage decoded = select_channels(decode_exr_channels(bytes), output_channels(mask));
  EXPECT_EQ(decoded.pixels, interleaved);
  // The RGBA reader still sees the beauty pass.
  const RgbaImage rgba = decode_exr(bytes);
  EXPECT_EQ(rgba.pixels, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8}));
}

}  // namespace
}  // namespace tessera
