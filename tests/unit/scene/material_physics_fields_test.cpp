// The fields and spellings the physically based materials add to the scene format: a
// conductor's complex index (`eta`, `k`) or `preset`, RayON's `dielectric` for glass, and the
// type defaults that keep glass and anisotropic metals lossless unless tinted.
#include <gtest/gtest.h>

#include <string>

#include "scene_error_of.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "scene.yaml", ".", SceneLoadOptions{});
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

TEST(MaterialPhysicsFields, ConductorIndexIsReadPerChannel) {
  const LoadedScene loaded = load(
      "materials:\n  - { name: m, type: anisotropic_metal, roughness: 0.15, anisotropy: 0.5,\n"
      "      eta: [0.18, 0.42, 1.37], k: [3.42, 2.35, 1.77] }\n");
  ASSERT_EQ(loaded.scene.materials.size(), 1u);
  const MaterialDesc& m = loaded.scene.materials[0];
  EXPECT_EQ(m.eta, glm::dvec3(0.18, 0.42, 1.37));
  EXPECT_EQ(m.k, glm::dvec3(3.42, 2.35, 1.77));
  EXPECT_TRUE(loaded.warnings.empty());
}

TEST(MaterialPhysicsFields, ConductorIndexIsValidated) {
  EXPECT_EQ(load_error("materials:\n  - { name: m, type: metal, k: [3, 2, 1] }\n").field,
            "materials[0].eta");
  EXPECT_EQ(
      load_error("materials:\n  - { name: m, type: metal, eta: [1, 0, 1], k: [2, 2, 2] }\n").field,
      "materials[0].eta");
  EXPECT_EQ(load_error("materials:\n  - { name: m, type: metal, eta: [1, -1, 1] }\n").field,
            "materials[0].eta");
  const SceneIssue both = load_error(
      "materials:\n  - { name: m, type: metal, preset: gold, eta: [1, 1, 1], k: [2, 2, 2] }\n");
  EXPECT_EQ(both.field, "materials[0].preset");
  EXPECT_NE(both.message.find("cannot be combined with eta"), std::string::npos) << both.message;
  // Chromium is a preset too.
  EXPECT_EQ(load("materials:\n  - { name: m, type: anisotropic_metal, preset: chromium }\n")
                .scene.materials[0]
                .preset,
            "chromium");
}

TEST(MaterialPhysicsFields, TransmittanceIsValidated) {
  const LoadedScene loaded = load(
      "materials:\n  - { name: g, type: glass, transmittance: [0.9, 0.5, 0.2], "
      "transmittance_distance: 2 }\n");
  EXPECT_EQ(loaded.scene.materials[0].transmittance, glm::dvec3(0.9, 0.5, 0.2));
  EXPECT_EQ(loaded.scene.materials[0].transmittance_distance, 2.0);
  EXPECT_EQ(load_error("materials:\n  - { name: g, type: glass, transmittance: 0 }\n").field,
            "materials[0].transmittance");
  EXPECT_EQ(
      load_error("materials:\n  - { name: g, type: glass, transmittance: [1, 1.5, 1] }\n").field,
      "materials[0].transmittance");
  EXPECT_EQ(
      load_error("materials:\n  - { name: g, type: glass, transmittance_distance: 0 }\n").field,
      "materials[0].transmittance_distance");
}

TEST(MaterialPhysicsFields, DielectricIsGlass) {
  const LoadedScene loaded =
      load("materials:\n  - { name: g, type: dielectric, refractive_index: 1.33 }\n");
  EXPECT_EQ(loaded.scene.materials[0].type, MaterialType::kGlass);
  EXPECT_EQ(loaded.scene.materials[0].refractive_index, 1.33);
}

// Glass and anisotropic metals without an albedo are untinted (RayON's glass renders
// lossless, its anisotropic metals take their colour from the index); other types keep the
// 0.8 default, and a given albedo wins.
TEST(MaterialPhysicsFields, GlassAndAnisotropicMetalDefaultToWhite) {
  const LoadedScene loaded = load(
      "materials:\n  - { name: g, type: glass }\n  - { name: a, type: anisotropic_metal }\n"
      "  - { name: m, type: metal }\n  - { name: t, type: glass, albedo: [1, 0.5, 0.5] }\n");
  EXPECT_EQ(loaded.scene.materials[0].albedo, glm::dvec3(1.0));
  EXPECT_EQ(loaded.scene.materials[1].albedo, glm::dvec3(1.0));
  EXPECT_EQ(loaded.scene.materials[2].albedo, glm::dvec3(0.8));
  EXPECT_EQ(loaded.scene.materials[3].albedo, glm::dvec3(1.0, 0.5, 0.5));
}

}  // namespace
}  // namespace tessera
