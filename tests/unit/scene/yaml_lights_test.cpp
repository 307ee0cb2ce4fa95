// The top-level `lights` list and `environment` in YAML: every field read, `sun` as an alias
// of `directional`, errors that name the field, and RayON's `settings` mapped onto RayON's
// gradient sky unless the scene gives an environment.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scene_error_of.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "scene.yaml", ".", {});
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

TEST(YamlLights, EveryLightTypeAndFieldIsRead) {
  const LoadedScene loaded = load(R"(
lights:
  - { type: point, position: [1, 2, 3], color: [1, 0.5, 0.25], intensity: 40 }
  - type: spot
    position: [0, 4, 0]
    direction: [0, -1, 0]
    intensity: 100
    cone_angle_degrees: 35
    cone_falloff_degrees: 8
  - { type: sun, direction: [-1, -2, -1], irradiance: 3, angular_radius_degrees: 0.27 }
  - { type: directional, direction: [0, -1, 0], color: 0.5 }
)");
  const auto& lights = loaded.scene.lights;
  ASSERT_EQ(lights.size(), 4u);
  EXPECT_EQ(lights[0].type, "point");
  EXPECT_EQ(lights[0].position, glm::dvec3(1, 2, 3));
  EXPECT_EQ(lights[0].color, glm::dvec3(1, 0.5, 0.25));
  EXPECT_DOUBLE_EQ(lights[0].intensity, 40.0);
  EXPECT_EQ(lights[1].type, "spot");
  EXPECT_DOUBLE_EQ(lights[1].cone_angle_degrees, 35.0);
  EXPECT_DOUBLE_EQ(lights[1].cone_falloff_degrees, 8.0);
  EXPECT_EQ(lights[2].type, "sun");
  EXPECT_DOUBLE_EQ(lights[2].irradiance, 3.0);
  EXPECT_DOUBLE_EQ(lights[2].angular_radius_degrees, 0.27);
  EXPECT_EQ(lights[3].color, glm::dvec3(0.5));
  EXPECT_DOUBLE_EQ(lights[3].irradiance, 1.0);         // the declared default
  EXPECT_FALSE(loaded.scene.environment.has_value());  // no settings, no environment
}

TEST(YamlLights, ErrorsNameTheField) {
  EXPECT_EQ(load_error("lights:\n  - { type: laser, position: [0, 1, 0] }\n").to_string(),
            "scene.yaml:2: lights[0].type: unknown type 'laser' (expected one of "
            "point,spot,directional,sun)");
  EXPECT_EQ(load_error("lights:\n  - { position: [0, 1, 0] }\n").field, "lights[0].type");
  const SceneIssue negative =
      load_error("lights:\n  - { type: point }\n  - { type: point, intensity: -2 }\n");
  EXPECT_EQ(negative.field, "lights[1].intensity");
  EXPECT_NE(negative.message.find("got -2"), std::string::npos) << negative.message;
  const SceneIssue falloff =
      load_error("lights:\n  - { type: spot, cone_angle_degrees: 10, cone_falloff_degrees: 20 }\n");
  EXPECT_EQ(falloff.field, "lights[0].cone_falloff_degrees");
  EXPECT_EQ(falloff.message, "must not exceed cone_angle_degrees (10), got 20");
  EXPECT_EQ(load_error("lights:\n  - { type: sun, direction: [0, 0, 0] }\n").field,
            "lights[0].direction");
  EXPECT_EQ(load_error("lights:\n  - { type: sun, angular_radius_degrees: 95 }\n").field,
            "lights[0].angular_radius_degrees");
  EXPECT_EQ(load_error("lights:\n  - { type: point, postion: [0, 1, 0] }\n").message,
            "unknown key 'postion' (did you mean 'position'?)");
  EXPECT_EQ(load_error("lights: { type: point }\n").field, "lights");
  EXPECT_EQ(load_error("environment: { type: hdri }\n").field, "environment.type");
  EXPECT_EQ(load_error("environment: { type: constant, intensity: -1 }\n").field,
            "environment.intensity");
}

TEST(YamlLights, RayonSettingsBecomeItsGradientSkyUnlessAnEnvironmentIsGiven) {
  const LoadedScene rayon =
      load("settings: { background_color: [0.4, 0.6, 0.9], background_intensity: 0.18 }\n");
  ASSERT_TRUE(rayon.scene.environment.has_value());
  EXPECT_EQ(rayon.scene.environment->type, "gradient");
  EXPECT_DOUBLE_EQ(rayon.scene.environment->intensity, 0.18);
  EXPECT_EQ(rayon.scene.background.color, glm::dvec3(0.4, 0.6, 0.9));  // kept, as read

  const LoadedScene own = load(
      "settings: { background_color: 0.3 }\n"
      "environment: { type: constant, color: [0.2, 0.3, 0.4], intensity: 2 }\n");
  ASSERT_TRUE(own.scene.environment.has_value());
  EXPECT_EQ(own.scene.environment->type, "constant");
  EXPECT_EQ(own.scene.environment->color, glm::dvec3(0.2, 0.3, 0.4));
  EXPECT_DOUBLE_EQ(own.scene.environment->intensity, 2.0);
}

// An image environment is read when the scene loads, from a path relative to the scene and
// under the same allowed-directory rule as mesh files; errors name environment.file.
TEST(YamlLights, ImageEnvironmentIsReadIntoTheDescription) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "tessera_yaml_environment_test";
  std::filesystem::create_directories(dir / "inside");
  RgbaImage sky{4, 2, {}};
  for (int i = 0; i < 8; ++i) sky.pixels.insert(sky.pixels.end(), {float(i), 0.5f, 0.25f, 1.0f});
  write_image(dir / "inside" / "sky.exr", sky);
  std::ofstream(dir / "inside" / "broken.exr") << "not an image";

  const std::string scene =
      "environment: { type: image, file: inside/sky.exr, intensity: 2, rotation_degrees: 30 }\n";
  const LoadedScene loaded = load_scene_yaml(scene, "scene.yaml", dir);
  ASSERT_TRUE(loaded.scene.environment.has_value());
  const EnvironmentDesc& env = *loaded.scene.environment;
  EXPECT_EQ(env.image_width, 4u);
  EXPECT_EQ(env.image_height, 2u);
  ASSERT_EQ(env.image_pixels.size(), 24u);
  EXPECT_EQ(env.image_pixels[3 * 5], 5.0f);
  EXPECT_EQ(env.image_pixels[3 * 5 + 1], 0.5f);
  EXPECT_DOUBLE_EQ(env.rotation_degrees, 30.0);

  const auto error_of = [&](const std::string& text, const SceneLoadOptions& options) {
    return test::scene_error_of([&] { load_scene_yaml(text, "scene.yaml", dir, options); }, text);
  };
  const SceneIssue missing = error_of("environment: { type: image, file: inside/none.exr }\n", {});
  EXPECT_EQ(missing.field, "environment.file");
  EXPECT_NE(missing.message.find("no such file"), std::string::npos) << missing.message;
  const SceneIssue unreadable =
      error_of("environment: { type: image, file: inside/broken.exr }\n", {});
  EXPECT_EQ(unreadable.field, "environment.file");
  EXPECT_NE(unreadable.message.find("cannot read"), std::string::npos) << unreadable.message;
  SceneLoadOptions small;
  small.limits.max_environment_pixels = 4;
  const SceneIssue large = error_of(scene, small);
  EXPECT_EQ(large.field, "environment.file");
  EXPECT_NE(large.message.find("more than the 4 allowed"), std::string::npos) << large.message;
  SceneLoadOptions confined;
  confined.allowed_roots = {dir / "elsewhere"};
  const SceneIssue outside = error_of(scene, confined);
  EXPECT_EQ(outside.field, "environment.file");
  EXPECT_NE(outside.message.find("outside the directories"), std::string::npos) << outside.message;
  confined.allowed_roots = {dir / "inside"};
  EXPECT_EQ(load_scene_yaml(scene, "scene.yaml", dir, confined).scene.environment->image_width, 4u);
  EXPECT_EQ(error_of("environment: { type: image }\n", {}).field, "environment.file");
  std::filesystem::remove_all(dir);
}

// RayON's BVH test scene: its sky is RayON's gradient at background_intensity 0.18, not the
// flat blue of its (unused) background_color.
TEST(YamlLights, RayonBvhTestSceneGetsTheGradientSky) {
  const std::filesystem::path file = "/work/shared/rayon-scenes/01_bvh_test_scene.yaml";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is not here";
  const LoadedScene loaded = load_scene_file(file.string());
  ASSERT_TRUE(loaded.scene.environment.has_value());
  EXPECT_EQ(loaded.scene.environment->type, "gradient");
  EXPECT_DOUBLE_EQ(loaded.scene.environment->intensity, 0.18);
}

}  // namespace
}  // namespace tessera
