// RayON's own scene files (TESSERA_SHARED_DIR/rayon-scenes, not part of this repository)
// must load unchanged and render; the one whose OBJ model is not shipped must fail naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

const std::filesystem::path kRayonDir = std::filesystem::path(TESSERA_SHARED_DIR) / "rayon-scenes";
constexpr const char* kMissingModelScene = "04_obj_dragon.yaml";

std::vector<std::filesystem::path> rayon_scenes() {
  std::vector<std::filesystem::path> scenes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(kRayonDir, ec))
    if (entry.path().extension() == ".yaml") scenes.push_back(entry.path());
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

TEST(RayonScenes, LoadAndRenderATinyImageWithoutNan) {
  const auto scenes = rayon_scenes();
  if (scenes.empty()) GTEST_SKIP() << "no RayON scenes in " << kRayonDir;
  int rendered = 0;
  for (const auto& path : scenes) {
    if (path.filename() == kMissingModelScene) continue;
    SCOPED_TRACE(path.filename().string());
    LoadedScene loaded;
    try {
      loaded = load_scene_file(path);
    } catch (const SceneError& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    RenderSettings& r = loaded.scene.render;
    r.width = 24;
    r.height = 16;
    r.samples_per_pixel = 2;
    r.max_depth = 4;
    r.tile_size = 8;
    const std::vector<float> image = render_image(*PreparedScene::build(loaded.scene));
    ASSERT_EQ(image.size(), 24u * 16u * 4u);
    double sum = 0.0;
    for (std::size_t i = 0; i < image.size(); ++i) {
      ASSERT_TRUE(std::isfinite(image[i]) && image[i] >= 0.0f)
          << "value " << image[i] << " at float " << i;
      if (i % 4 != 3) sum += image[i];
    }
    // Every one of these scenes has a light or a lit background in view.
    EXPECT_GT(sum, 0.0);
    ++rendered;
  }
  EXPECT_EQ(rendered, static_cast<int>(scenes.size()) - 1);
}

// The material laboratory and the soap bubbles use every material key RayON documents for
// them; none may be dropped with a warning (settings such as use_bvh still warn).
TEST(RayonScenes, MaterialScenesLoadWithoutMaterialWarnings) {
  for (const char* name : {"05_material_laboratory.yaml", "11_soap_bubbles.yaml"}) {
    const std::filesystem::path path = kRayonDir / name;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    SCOPED_TRACE(name);
    const LoadedScene loaded = load_scene_file(path);
    EXPECT_FALSE(loaded.scene.materials.empty());
    for (const SceneIssue& warning : loaded.warnings) {
      EXPECT_NE(warning.field.rfind("materials", 0), 0u) << warning.to_string();
      EXPECT_EQ(warning.message.find("unknown key"), std::string::npos) << warning.to_string();
    }
  }
}

TEST(RayonScenes, DragonSceneFailsNamingTheMissingModel) {
  const std::filesystem::path path = kRayonDir / kMissingModelScene;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  try {
    load_scene_file(path);
    FAIL() << "loading " << path << " should fail: its OBJ model is not shipped";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("xyzrgb_dragon.obj"), std::string::npos) << message;
    EXPECT_NE(message.find(kMissingModelScene), std::string::npos) << message;
    EXPECT_NE(message.find("].file"), std::string::npos) << message;
    EXPECT_GT(e.issue().line, 0) << message;
  }
}

}  // namespace
}  // namespace tessera
