// RayON's remaining material types and its emission shorthand, as the YAML loader and
// validation read them: the types map onto the renderer's BSDF families, color +
// emission_intensity is the emission, and conflicting or incomplete input names its field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene_error_of.hpp"
#include "tessera/render/material_mapping.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "scene.yaml", ".");
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

std::string with_material(const std::string& material) {
  return "materials:\n  - " + material +
         "\ngeometry:\n  - { type: sphere, material: m, center: [0, 0, 0], radius: 1 }\n";
}

TEST(RayonMaterials, MirrorConstantAndShowNormalsLoadAndMap) {
  const LoadedScene loaded = load(
      "materials:\n"
      "  - { name: chrome, type: mirror, albedo: [0.9, 0.8, 0.7], roughness: 0.5 }\n"
      "  - { name: flat, type: constant, albedo: [1, 0, 0.5] }\n"
      "  - { name: normals, type: show_normals }\n"
      "geometry: []\n");
  EXPECT_TRUE(loaded.warnings.empty());
  const auto& m = loaded.scene.materials;
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].type, MaterialType::kMirror);
  EXPECT_EQ(m[1].type, MaterialType::kConstant);
  EXPECT_EQ(m[2].type, MaterialType::kShowNormals);

  // A mirror is a perfect reflector tinted by albedo: roughness does not blur it.
  const Material mirror = make_material(m[0]);
  EXPECT_EQ(mirror.kind, BsdfKind::kConductor);
  EXPECT_EQ(mirror.roughness, 0.0f);
  EXPECT_EQ(mirror.albedo, vec3(0.9f, 0.8f, 0.7f));

  const Material flat = make_material(m[1]);
  EXPECT_EQ(flat.kind, BsdfKind::kConstant);
  EXPECT_TRUE(flat.unlit());
  EXPECT_FALSE(flat.emissive());  // not a light: nothing samples it
  EXPECT_EQ(flat.unlit_color(flat.albedo, vec3(0.0f, 0.0f, 1.0f)), vec3(1.0f, 0.0f, 0.5f));

  const Material normals = make_material(m[2]);
  EXPECT_EQ(normals.kind, BsdfKind::kShowNormals);
  EXPECT_TRUE(normals.unlit());
  EXPECT_FALSE(normals.emissive());
  EXPECT_EQ(normals.unlit_color(normals.albedo, vec3(0.0f, -1.0f, 0.0f)), vec3(0.5f, 0.0f, 0.5f));
  EXPECT_EQ(normals.unlit_color(normals.albedo, vec3(0.6f, 0.0f, 0.8f)), vec3(0.8f, 0.5f, 0.9f));
}

TEST(RayonMaterials, ColorAndEmissionIntensityAreTheEmission) {
  const LoadedScene loaded = load(
      with_material("{ name: m, type: light, color: [1.0, 0.875, 0.75], emission_intensity: 8 }"));
  EXPECT_TRUE(loaded.warnings.empty());
  const MaterialDesc& m = loaded.scene.materials.at(0);
  EXPECT_EQ(m.emitted_radiance(), glm::dvec3(8.0, 7.0, 6.0));
  EXPECT_EQ(make_material(m).emission, vec3(8.0f, 7.0f, 6.0f));
  // color alone (RayON reads it only with an intensity) emits nothing.
  const LoadedScene plain = load(with_material("{ name: m, type: lambertian, color: [1, 0, 0] }"));
  EXPECT_EQ(plain.scene.materials.at(0).emitted_radiance(), glm::dvec3(0.0));
}

TEST(RayonMaterials, EmissionShorthandErrorsNameTheField) {
  SceneIssue issue = load_error(with_material(
      "{ name: m, type: light, emission: [1, 1, 1], color: [1, 1, 1], emission_intensity: 2 }"));
  EXPECT_EQ(issue.field, "materials[0].emission_intensity");
  EXPECT_NE(issue.message.find("cannot be combined with emission"), std::string::npos)
      << issue.message;

  issue = load_error(with_material("{ name: m, type: light, color: [1, 1, 1] }"));
  EXPECT_EQ(issue.field, "materials[0].emission");
  EXPECT_NE(issue.message.find("required for a light"), std::string::npos) << issue.message;

  issue = load_error(with_material("{ name: m, type: light, emission_intensity: -1 }"));
  EXPECT_EQ(issue.field, "materials[0].emission_intensity");

  issue = load_error(
      with_material("{ name: m, type: light, color: [1, -1, 1], emission_intensity: 1 }"));
  EXPECT_EQ(issue.field, "materials[0].color");
}

TEST(RayonMaterials, PatternLoadsAndMaps) {
  const LoadedScene loaded = load(with_material(
      "{ name: m, type: lambertian, albedo: [0.9, 0.1, 0.1], pattern: { type: fibonacci_dots, "
      "color: [0.02, 0.02, 0.02], dot_count: 12, dot_radius: 0.33 } }"));
  EXPECT_TRUE(loaded.warnings.empty());
  const MaterialDesc& m = loaded.scene.materials.at(0);
  ASSERT_TRUE(m.pattern.has_value());
  EXPECT_EQ(m.pattern->type, "fibonacci_dots");
  EXPECT_EQ(m.pattern->color, glm::dvec3(0.02));
  EXPECT_EQ(m.pattern->dot_count, 12u);
  EXPECT_EQ(m.pattern->dot_radius, 0.33);
  const Material mapped = make_material(m);
  EXPECT_EQ(mapped.pattern.type, PatternType::kFibonacciDots);
  EXPECT_EQ(mapped.pattern.dot_count, 12u);
  EXPECT_FLOAT_EQ(mapped.pattern.cos_dot_radius, std::cos(0.33f));
  EXPECT_EQ(mapped.pattern.color, vec3(0.02f));

  // checkerboard needs nothing but its type (RayON reads the same keys for every type).
  const LoadedScene checker = load(with_material(
      "{ name: m, type: lambertian, pattern: { type: checkerboard, color: [0.05, 0.05, 0.05] } "
      "}"));
  EXPECT_EQ(make_material(checker.scene.materials.at(0)).pattern.type, PatternType::kCheckerboard);
}

TEST(RayonMaterials, PatternErrorsNameTheField) {
  const auto error_for = [](const std::string& pattern) {
    return load_error(with_material("{ name: m, type: lambertian, pattern: " + pattern + " }"));
  };
  SceneIssue issue = error_for("{ type: polka }");
  EXPECT_EQ(issue.field, "materials[0].pattern.type");
  EXPECT_NE(issue.message.find("fibonacci_dots"), std::string::npos) << issue.message;

  issue = error_for("{ color: [1, 1, 1] }");
  EXPECT_EQ(issue.field, "materials[0].pattern.type");
  EXPECT_NE(issue.message.find("required"), std::string::npos) << issue.message;

  issue = error_for("{ type: fibonacci_dots, dot_radius: 0.3 }");
  EXPECT_EQ(issue.field, "materials[0].pattern.dot_count");
  EXPECT_NE(issue.message.find("[1, 10000]"), std::string::npos) << issue.message;

  issue = error_for("{ type: fibonacci_dots, dot_count: 20000, dot_radius: 0.3 }");
  EXPECT_EQ(issue.field, "materials[0].pattern.dot_count");

  issue = error_for("{ type: fibonacci_dots, dot_count: 12, dot_radius: 4 }");
  EXPECT_EQ(issue.field, "materials[0].pattern.dot_radius");

  issue = error_for("{ type: fibonacci_dots, dot_count: 12, dot_radius: 0.3, colour: 1 }");
  EXPECT_EQ(issue.field, "materials[0].pattern.colour");
  EXPECT_NE(issue.message.find("did you mean 'color'"), std::string::npos) << issue.message;

  issue = error_for("{ type: fibonacci_dots, dot_count: 12, color: [0, -1, 0] }");
  EXPECT_EQ(issue.field, "materials[0].pattern.color");

  issue = error_for("[1, 2]");
  EXPECT_EQ(issue.field, "materials[0].pattern");
}

}  // namespace
}  // namespace tessera
