// Writes the proto fuzz target's seed corpus: each YAML scene given, as the bytes of the
// SubmitJobRequest `tessera render` would send for it. Usage: make_proto_seeds OUT_DIR
// SCENE.yaml...
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_proto_seeds OUT_DIR SCENE.yaml...\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  std::filesystem::create_directories(out);
  for (int i = 2; i < argc; ++i) {
    const std::filesystem::path scene_path = argv[i];
    const tessera::SceneDescription scene = tessera::load_scene_file(scene_path).scene;
    const std::string bytes =
        tessera::make_submit_request(scene, scene_path.stem().string(), 0).SerializeAsString();
    std::ofstream(out / (scene_path.stem().string() + ".pb"), std::ios::binary) << bytes;
  }
  return 0;
}
