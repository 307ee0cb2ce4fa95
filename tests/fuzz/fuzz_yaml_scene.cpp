// libFuzzer target: the YAML scene loader and validate_scene on arbitrary text. Any input
// must end in a scene or a SceneError naming the problem; anything else escaping (another
// exception type, a crash, a sanitizer report, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tessera/scene/scene_error.hpp"
#include "tessera/scene/yaml_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tessera::SceneLoadOptions options;
  // Files only from a folder that does not exist: the input cannot make the loader read
  // the machine's files.
  options.allowed_roots = {"/nonexistent-tessera-fuzz"};
  // Small limits, as a daemon on a small node would set them: the fuzzer explores the
  // checks, not how much memory a legal scene may take.
  options.limits.max_triangles = 100'000;
  options.limits.max_primitives = 100'000;
  options.limits.max_patch_control_points = 10'000;
  options.limits.max_trim_points = 100'000;
  options.limits.max_environment_pixels = 1 << 16;
  try {
    (void)tessera::load_scene_yaml(text, "fuzz.yaml", "/nonexistent-tessera-fuzz", options);
  } catch (const tessera::SceneError&) {
    // The expected outcome for most inputs.
  }
  return 0;
}
