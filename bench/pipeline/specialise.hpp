#pragma once
#include <cstdint>
#include <string>

namespace tessera::bench {

struct SpecialiseOptions {
  std::uint32_t width = 96;
  std::uint32_t height = 72;
  std::uint32_t spp = 4;
  int repeats = 3;
  std::string sampler = "sobol";  // render.sampler of every scene
  bool light_tree = true;         // PrepareOptions::light_tree
  // When set: render only this scene with only this renderer (specialised, all or
  // virtual), once and untimed, so a profiler such as callgrind counts just that work.
  std::string only_scene;
  std::string only_renderer;
};

// Prints one line per scene and ends with
// `speedup_vs_all_features=X speedup_vs_virtual=Y` (geometric means). Returns non-zero
// when the three renderers disagree on an image.
int run_specialise(const SpecialiseOptions& options);

}  // namespace tessera::bench
