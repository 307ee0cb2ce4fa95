#include "tessera/render/output_channels.hpp"

#include <gtest/gtest.h>

#include "tessera/image/exr.hpp"
#include "tessera/render/film.hpp"

namespace tessera {
namespace {

TEST(OutputChannels, NamesFollowTheAovMaskInOrder) {
  EXPECT_EQ(output_channels(0), (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(output_channels(kAovNormal | kAovAlbedo),
            (std::vector<std::string>{"R", "G", "B", "A", "Albedo.R", "Albedo.G", "Albedo.B",
                                      "Normal.X", "Normal.Y", "Normal.Z"}));
  EXPECT_EQ(output_channels(kAllAovs).size(), 16u);
}

TEST(OutputChannels, InterleavesEveryPlaneAndRoundTripsThroughExr) {
  TilePasses passes;
  passes.beauty = {1, 2, 3, 4, 5, 6, 7, 8};
  passes.aovs[2] = {9, 9, 9, 1, 10, 10, 10, 1};  // depth
  // Primitive IDs travel as integer bits, so they come back exact whatever their size.
  const float big_id = id_as_float(0xfffffff0u);
  passes.aovs[3] = {id_as_float(11), 0, 0, 0, big_id, 0, 0, 0};
  const std::uint32_t mask = kAovDepth | kAovPrimitiveId;
  const std::vector<float> interleaved = interleave_passes(passes, mask);
  ASSERT_EQ(interleaved.size(), 12u);
  EXPECT_EQ(float_as_id(interleaved[5]), 11u);
  EXPECT_EQ(float_as_id(interleaved[11]), 0xfffffff0u);

  const auto bytes = encode_exr(interleaved, 2, 1, output_channels(mask), 0, 0);
  const ChannelImage decoded = select_channels(decode_exr_channels(bytes), output_channels(mask));
  ASSERT_EQ(decoded.pixels.size(), interleaved.size());
  for (std::size_t i = 0; i < interleaved.size(); ++i)
    EXPECT_EQ(float_as_id(decoded.pixels[i]), float_as_id(interleaved[i])) << i;
  // The RGBA reader still sees the beauty pass.
  const RgbaImage rgba = decode_exr(bytes);
  EXPECT_EQ(rgba.pixels, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8}));
}

}  // namespace
}  // namespace tessera
