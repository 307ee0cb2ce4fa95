// Textures in YAML and protobuf: image files decoded to linear RGB as their colour space
// says (an 8-bit PNG's 128 is sRGB 0.2158, not 0.502), read only where scene files may be,
// references from materials checked with suggestions, budgets enforced, and every field
// surviving YAML -> description -> protobuf -> description.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "../scene/scene_error_of.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

// A 2 x 2 grey PNG whose bytes are all 128: write_image sRGB-encodes linear 0.21586 to it.
void write_png(const std::filesystem::path& path) {
  RgbaImage image{2, 2, std::vector<float>(16, 0.21586f)};
  for (std::size_t i = 3; i < image.pixels.size(); i += 4) image.pixels[i] = 1.0f;
  write_image(path, image);
}

class YamlTextures : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test and process: CTest runs the tests of this file side by side.
    dir_ = std::filesystem::temp_directory_path() /
           ("tessera_yaml_textures_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "inside");
    write_png(dir_ / "inside" / "grey.png");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  SceneIssue error_of(const std::string& text, const SceneLoadOptions& options = {}) {
    return test::scene_error_of([&] { load_scene_yaml(text, "scene.yaml", dir_, options); }, text);
  }

  std::filesystem::path dir_;
};

TEST_F(YamlTextures, ImagesAreDecodedAsTheirColourSpaceSays) {
  const LoadedScene loaded = load_scene_yaml(R"(
textures:
  - { name: auto, type: image, file: inside/grey.png }
  - { name: raw, type: image, file: inside/grey.png, color_space: linear, wrap: clamp,
      filter: bilinear, scale: 4 }
  - { name: checks, type: checker, color_a: [1, 0, 0], color_b: 0.25, scale: 8 }
materials:
  - { name: floor, type: lambertian, albedo_texture: checks }
  - { name: metal, type: metal, albedo: 0.9, roughness_texture: raw }
)",
                                             "scene.yaml", dir_);
  const auto& textures = loaded.scene.textures;
  ASSERT_EQ(textures.size(), 3u);
  EXPECT_EQ(textures[0].image_width, 2u);
  ASSERT_EQ(textures[0].image_pixels.size(), 12u);
  // 128/255 = 0.50196 encoded; sRGB decodes it to 0.21586.
  EXPECT_NEAR(textures[0].image_pixels[0], 0.21586f, 1e-4f);
  EXPECT_NEAR(textures[1].image_pixels[0], 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(textures[1].wrap, "clamp");
  EXPECT_EQ(textures[1].filter, "bilinear");
  EXPECT_DOUBLE_EQ(textures[1].scale, 4.0);
  EXPECT_EQ(textures[2].color_b, glm::dvec3(0.25));
  EXPECT_EQ(loaded.scene.materials[0].albedo_texture, "checks");
  EXPECT_EQ(loaded.scene.materials[1].roughness_texture, "raw");

  // Everything survives protobuf, pixels included.
  SceneConversion back =
      scene_from_proto(scene_to_proto(loaded.scene), settings_to_proto(loaded.scene.render));
  ASSERT_TRUE(back.ok()) << describe_issues(back.issues);
  for (std::size_t i = 0; i < textures.size(); ++i) {
    TextureDesc expected = textures[i];
    expected.file.clear();  // YAML-only: the pixels travel instead
    EXPECT_EQ(back.scene->textures[i], expected) << i;
  }
  EXPECT_EQ(back.scene->materials, loaded.scene.materials);
}

TEST_F(YamlTextures, MistakesNameTheFieldAndTheReason) {
  const SceneIssue unknown = error_of(R"(
textures: [ { name: wood, type: checker } ]
materials: [ { name: m, type: lambertian, albedo_texture: wod } ]
)");
  EXPECT_EQ(unknown.field, "materials[0].albedo_texture");
  EXPECT_NE(unknown.message.find("unknown texture 'wod'"), std::string::npos) << unknown.message;
  EXPECT_NE(unknown.message.find("did you mean 'wood'"), std::string::npos) << unknown.message;

  const SceneIssue duplicate =
      error_of("textures: [ { name: a, type: checker }, { name: a, type: checker } ]\n");
  EXPECT_EQ(duplicate.field, "textures[1].name");

  const SceneIssue wrap = error_of("textures: [ { name: a, type: checker, wrap: tile } ]\n");
  EXPECT_EQ(wrap.field, "textures[0].wrap");

  const SceneIssue missing =
      error_of("textures: [ { name: a, type: image, file: inside/no.png } ]\n");
  EXPECT_EQ(missing.field, "textures[0].file");
  EXPECT_NE(missing.message.find("no such file"), std::string::npos) << missing.message;

  EXPECT_EQ(error_of("textures: [ { name: a, type: image } ]\n").field, "textures[0].file");

  SceneLoadOptions confined;
  confined.allowed_roots = {dir_ / "elsewhere"};
  const std::string image = "textures: [ { name: a, type: image, file: inside/grey.png } ]\n";
  const SceneIssue outside = error_of(image, confined);
  EXPECT_EQ(outside.field, "textures[0].file");
  EXPECT_NE(outside.message.find("outside the directories"), std::string::npos) << outside.message;

  // The budget counts every texture of the scene together: two 4-pixel images with 6 allowed.
  SceneLoadOptions small;
  small.limits.max_texture_pixels = 6;
  const SceneIssue large = error_of(
      "textures: [ { name: a, type: image, file: inside/grey.png },\n"
      "            { name: b, type: image, file: inside/grey.png } ]\n",
      small);
  EXPECT_EQ(large.field, "textures[1].file");
  EXPECT_NE(large.message.find("allowed"), std::string::npos) << large.message;
}

TEST_F(YamlTextures, ProtobufPixelsAreChecked) {
  SceneDescription scene;
  scene.textures.push_back(TextureDesc{.name = "t",
                                       .type = "image",
                                       .image_width = 2,
                                       .image_height = 1,
                                       .image_pixels = {1, 2, 3}});
  SceneConversion short_pixels =
      scene_from_proto(scene_to_proto(scene), settings_to_proto(scene.render));
  ASSERT_FALSE(short_pixels.ok());
  EXPECT_EQ(short_pixels.issues[0].field, "textures[0].image_pixels");
  scene.textures[0].image_pixels = {1, 2, 3, 4, -5, 6};
  SceneConversion negative =
      scene_from_proto(scene_to_proto(scene), settings_to_proto(scene.render));
  ASSERT_FALSE(negative.ok());
  EXPECT_NE(negative.issues[0].message.find(">= 0"), std::string::npos);
}

}  // namespace
}  // namespace tessera
