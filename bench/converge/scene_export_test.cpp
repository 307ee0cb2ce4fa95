// The scene export the Cycles peer reads (bench/peers/cycles_render.py): parsed back here,
// so the format is checked without Blender.
#include "scene_export.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tessera/scene/yaml_loader.hpp"

namespace tessera::bench {
namespace {

using nlohmann::json;

json exported(const SceneDescription& scene) {
  return json::parse(scene_to_json(scene));
}

TEST(SceneExport, CornellBoxRoundTripsItsSettingsShapesAndMaterials) {
  const SceneDescription scene =
      load_scene_file(TESSERA_SOURCE_DIR "/examples/scenes/cornell.yaml").scene;
  const json j = exported(scene);
  EXPECT_EQ(j["format"], "tessera-scene-export");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["render"]["width"], 320);
  EXPECT_EQ(j["render"]["height"], 240);
  EXPECT_EQ(j["render"]["max_depth"], 8);
  EXPECT_EQ(j["render"]["integrator"], "path");
  EXPECT_DOUBLE_EQ(j["camera"]["fov_degrees"].get<double>(), 41.0);
  EXPECT_DOUBLE_EQ(j["camera"]["position"][2].get<double>(), 5.2);

  ASSERT_EQ(j["materials"].size(), scene.materials.size());
  std::map<std::string, json> by_name;
  for (const json& m : j["materials"]) by_name[m["name"]] = m;
  EXPECT_EQ(by_name["white"]["bsdf"], "diffuse");
  EXPECT_EQ(by_name["light"]["bsdf"], "emitter");
  EXPECT_FLOAT_EQ(by_name["light"]["emission"][0].get<float>(), 16.0f);
  EXPECT_EQ(by_name["mirror"]["bsdf"], "conductor");
  EXPECT_FLOAT_EQ(by_name["mirror"]["roughness"].get<float>(), 0.02f);
  EXPECT_EQ(by_name["glass"]["bsdf"], "dielectric");
  EXPECT_FLOAT_EQ(by_name["glass"]["ior"].get<float>(), 1.5f);

  std::map<std::string, int> counts;
  for (const json& s : j["shapes"]) {
    ++counts[s["type"].get<std::string>()];
    EXPECT_LT(s["material"].get<std::size_t>(), scene.materials.size());
    EXPECT_TRUE(s["visible"].get<bool>());
    EXPECT_TRUE(s["matrix"].is_null());
  }
  EXPECT_EQ(counts["quad"], 6);
  EXPECT_EQ(counts["sphere"], 2);
  EXPECT_EQ(counts.size(), 2u);
}

TEST(SceneExport, MeshesTransformsHiddenAndUnsupportedShapes) {
  SceneDescription scene;
  scene.materials.emplace_back().name = "m";
  TriangleMeshDesc mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.visible = false;
  mesh.transform = TransformDesc{.translate = {1, 2, 3}, .scale = {2, 2, 2}};
  scene.meshes.push_back(mesh);
  scene.cylinders.push_back(CylinderDesc{.source_index = 7});
  const json j = exported(scene);

  ASSERT_EQ(j["shapes"].size(), 2u);
  const json& m = j["shapes"][0];
  EXPECT_EQ(m["type"], "mesh");
  EXPECT_FALSE(m["visible"].get<bool>());
  EXPECT_EQ(m["positions"].size(), 9u);
  EXPECT_EQ(m["indices"], json::array({0, 1, 2}));
  EXPECT_EQ(m["normals"].size(), 9u);
  // Row-major: scale on the diagonal, translation in the last column.
  const std::vector<double> matrix = m["matrix"];
  const std::vector<double> expected{2, 0, 0, 1, 0, 2, 0, 2, 0, 0, 2, 3, 0, 0, 0, 1};
  EXPECT_EQ(matrix, expected);

  const json& c = j["shapes"][1];
  EXPECT_EQ(c["type"], "unsupported");
  EXPECT_EQ(c["kind"], "cylinder");
  EXPECT_EQ(c["source_index"], 7);
}

}  // namespace
}  // namespace tessera::bench
