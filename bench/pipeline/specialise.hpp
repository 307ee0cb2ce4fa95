#pragma once
#include <cstdint>

namespace tessera::bench {

struct SpecialiseOptions {
  std::uint32_t width = 96;
  std::uint32_t height = 72;
  std::uint32_t spp = 4;
  int repeats = 3;
};

// Prints one line per scene and ends with
// `speedup_vs_all_features=X speedup_vs_virtual=Y` (geometric means). Returns non-zero
// when the three renderers disagree on an image.
int run_specialise(const SpecialiseOptions& options);

}  // namespace tessera::bench
