#include "tessera/render/output_channels.hpp"

namespace tessera {

namespace {
// Channels each AOV contributes, and which components of its RGBA plane they take.
struct AovChannels {
  std::vector<std::string> names;
};
const AovChannels kAovChannels[] = {
    {{"Albedo.R", "Albedo.G", "Albedo.B"}},
    {{"Normal.X", "Normal.Y", "Normal.Z"}},
    {{"Z"}},
    {{"PrimitiveID.X"}},
    {{"Variance.R", "Variance.G", "Variance.B"}},
    {{"SampleCount.X"}},
};
static_assert(std::size(kAovChannels) == kAovCount);
}  // namespace

std::vector<std::string> output_channels(std::uint32_t aovs) {
  std::vector<std::string> names = {"R", "G", "B", "A"};
  for (std::size_t i = 0; i < std::size(kAovChannels); ++i)
    if ((aovs & (1u << i)) != 0)
      names.insert(names.end(), kAovChannels[i].names.begin(), kAovChannels[i].names.end());
  return names;
}

std::vector<float> interleave_passes(const TilePasses& passes, std::uint32_t aovs) {
  const std::size_t pixels = passes.beauty.size() / 4;
  const std::size_t stride = output_channels(aovs).size();
  std::vector<float> out(pixels * stride);
  for (std::size_t p = 0; p < pixels; ++p) {
    float* dst = &out[p * stride];
    for (int c = 0; c < 4; ++c) *dst++ = passes.beauty[p * 4 + c];
    for (std::size_t i = 0; i < std::size(kAovChannels); ++i) {
      if ((aovs & (1u << i)) == 0) continue;
      for (std::size_t c = 0; c < kAovChannels[i].names.size(); ++c)
        *dst++ = passes.aovs[i][p * 4 + c];
    }
  }
  return out;
}

}  // namespace tessera
