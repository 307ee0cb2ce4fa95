// The scene export the Cycles peer reads (bench/peers/cycles_render.py): parsed back here,
// so the format is checked without Blender.
#include "scene_export.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tessera/image/exr.hpp"
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
  scene.cylinders.push_back(CylinderDesc{.radius = 0.5, .height = 2.0, .caps = true});
  scene.tori.push_back(TorusDesc{.major_radius = 1.5, .minor_radius = 0.2});
  scene.sdf_boxes.push_back(SdfBoxDesc{.source_index = 7});
  const json j = exported(scene);

  ASSERT_EQ(j["shapes"].size(), 4u);
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

  const json& cylinder = j["shapes"][1];
  EXPECT_EQ(cylinder["type"], "cylinder");
  EXPECT_DOUBLE_EQ(cylinder["radius"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(cylinder["height"].get<double>(), 2.0);
  EXPECT_TRUE(cylinder["caps"].get<bool>());
  const json& torus = j["shapes"][2];
  EXPECT_EQ(torus["type"], "torus");
  EXPECT_DOUBLE_EQ(torus["minor_radius"].get<double>(), 0.2);
  const json& box = j["shapes"][3];
  EXPECT_EQ(box["type"], "unsupported");
  EXPECT_EQ(box["kind"], "sdf_box");
  EXPECT_EQ(box["source_index"], 7);
}

// RayON's golf balls are exported as their spheres, and what the peer cannot draw (dimples,
// textures, patterns) is named so it can warn: before, a golf ball was left out of the
// peer's image without a word.
TEST(SceneExport, GolfBallsTexturesAndPatternsAreNamed) {
  SceneDescription scene;
  MaterialDesc& plain = scene.materials.emplace_back();
  plain.name = "plain";
  MaterialDesc& textured = scene.materials.emplace_back();
  textured.name = "textured";
  textured.albedo_texture = "checks";
  textured.pattern = PatternDesc{.type = "fibonacci_dots", .dot_count = 40, .dot_radius = 0.1};
  scene.displaced_spheres.push_back(DisplacedSphereDesc{
      .center = {1, 2, 3}, .radius = 0.5, .displacement_scale = 0.3, .material = 1});
  const json j = exported(scene);

  ASSERT_EQ(j["shapes"].size(), 1u);
  const json& ball = j["shapes"][0];
  EXPECT_EQ(ball["type"], "sphere");
  EXPECT_DOUBLE_EQ(ball["radius"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(ball["center"][2].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(ball["dimples"].get<double>(), 0.3);
  EXPECT_EQ(ball["material"], 1);

  EXPECT_EQ(j["materials"][0]["albedo_texture"], "");
  EXPECT_TRUE(j["materials"][0]["pattern"].is_null());
  EXPECT_EQ(j["materials"][1]["albedo_texture"], "checks");
  EXPECT_EQ(j["materials"][1]["roughness_texture"], "");
  EXPECT_EQ(j["materials"][1]["pattern"], "fibonacci_dots");
}

// Textures travel with their fields, an image's pixels go into an EXR beside the JSON
// named by it, and a mesh's uv go with its positions: what the peer needs to draw them.
TEST(SceneExport, TexturesAndMeshUvs) {
  SceneDescription scene;
  scene.materials.emplace_back().name = "m";
  TextureDesc checks;
  checks.name = "checks";
  checks.type = "checker";
  checks.scale = 6.0;
  checks.color_a = {0.75, 0.75, 0.75};
  TextureDesc image;
  image.name = "picture";
  image.type = "image";
  image.wrap = "clamp";
  image.image_width = 2;
  image.image_height = 1;
  image.image_pixels = {0.25f, 0.5f, 1.0f, 2.0f, 0.0f, 0.125f};
  scene.textures = {checks, image};
  TriangleMeshDesc mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.uvs = {{0, 0}, {2, 0}, {0, 0.5}};
  scene.meshes.push_back(mesh);

  const json j = exported(scene);
  ASSERT_EQ(j["textures"].size(), 2u);
  EXPECT_EQ(j["textures"][0]["type"], "checker");
  EXPECT_DOUBLE_EQ(j["textures"][0]["scale"].get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(j["textures"][0]["color_a"][0].get<double>(), 0.75);
  EXPECT_TRUE(j["textures"][0]["image"].is_null());
  EXPECT_EQ(j["textures"][1]["wrap"], "clamp");
  EXPECT_EQ(j["textures"][1]["image"], texture_image_name(1));
  const std::vector<double> uvs = j["shapes"][0]["uvs"];
  EXPECT_EQ(uvs, (std::vector<double>{0, 0, 2, 0, 0, 0.5}));

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "tessera_scene_export_textures";
  std::filesystem::create_directories(dir);
  write_scene_json(scene, dir / "scene.json");
  const RgbaImage written = read_image(dir / texture_image_name(1));
  ASSERT_EQ(written.width, 2u);
  ASSERT_EQ(written.height, 1u);
  EXPECT_FLOAT_EQ(written.pixels[1], 0.5f);  // first pixel's green, as read
  EXPECT_FLOAT_EQ(written.pixels[4], 2.0f);  // second pixel's red: float, not clamped
  EXPECT_FALSE(std::filesystem::exists(dir / texture_image_name(0)));
  std::filesystem::remove_all(dir);
}

// Lights that are not shapes and the environment travel with their fields; without an
// environment the background colour is the constant one.
TEST(SceneExport, LightsAndEnvironment) {
  SceneDescription scene;
  scene.background.color = {0.1, 0.2, 0.3};
  scene.background.intensity = 2.0;
  scene.lights.push_back(LightDesc{.type = "point", .position = {1, 2, 3}, .intensity = 5.0});
  scene.lights.push_back(LightDesc{.type = "sun", .direction = {0, -1, 0}, .irradiance = 3.0});
  scene.lights.push_back(LightDesc{.type = "spot", .cone_angle_degrees = 20.0});
  json j = exported(scene);
  EXPECT_EQ(j["environment"]["type"], "constant");
  EXPECT_DOUBLE_EQ(j["environment"]["color"][2].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(j["environment"]["intensity"].get<double>(), 2.0);
  ASSERT_EQ(j["lights"].size(), 3u);
  EXPECT_EQ(j["lights"][0]["type"], "point");
  EXPECT_DOUBLE_EQ(j["lights"][0]["position"][1].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["lights"][0]["intensity"].get<double>(), 5.0);
  EXPECT_EQ(j["lights"][1]["type"], "directional");
  EXPECT_DOUBLE_EQ(j["lights"][1]["irradiance"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["lights"][2]["cone_angle_degrees"].get<double>(), 20.0);

  scene.environment = EnvironmentDesc{.type = "image", .intensity = 0.5, .rotation_degrees = 90.0};
  j = exported(scene);
  EXPECT_EQ(j["environment"]["type"], "image");
  EXPECT_EQ(j["environment"]["image"], kEnvironmentImageName);
  EXPECT_DOUBLE_EQ(j["environment"]["rotation_degrees"].get<double>(), 90.0);
}

}  // namespace
}  // namespace tessera::bench
