// The YAML side of the kind declarations: unknown keys are errors with a suggestion, RayON's
// unused keys are warnings, --lenient downgrades, and the README's tables are the ones the
// declarations make.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scene_error_of.hpp"
#include "tessera/scene/schema/docs.hpp"
#include "tessera/scene/schema/suggest.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text, bool lenient = false) {
  SceneLoadOptions options;
  options.lenient = lenient;
  return load_scene_yaml(text, "scene.yaml", ".", options);
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

const std::string kMaterials = "materials:\n  - { name: white, type: lambertian }\n";

TEST(SchemaYaml, MisspelledRequiredKeyIsNamedWithTheKeyItMeant) {
  const SceneIssue issue =
      load_error(kMaterials +
                 "geometry:\n  - { type: sphere, material: white, center: [0, 0, 0], "
                 "raduis: 1 }\n");
  EXPECT_EQ(issue.to_string(),
            "scene.yaml:4: geometry[0].raduis: unknown key 'raduis' (did you mean 'radius'?)");
}

TEST(SchemaYaml, RenderPassesAreReadAndCheckedAgainstSppAndAdaptiveSampling) {
  EXPECT_EQ(load("render: { spp: 8, passes: 4 }\n").scene.render.passes, 4u);
  EXPECT_EQ(load("render: { spp: 8 }\n").scene.render.pass_count(), 1u);
  const SceneIssue over = load_error("render: { spp: 4, passes: 8 }\n");
  EXPECT_EQ(over.field, "render.passes");
  EXPECT_EQ(over.message, "must not exceed samples_per_pixel (4), got 8");
  const SceneIssue adaptive = load_error("render: { spp: 64, passes: 4, target_error: 0.05 }\n");
  EXPECT_EQ(adaptive.field, "render.passes");
  EXPECT_NE(adaptive.message.find("adaptive sampling"), std::string::npos);
}

TEST(SchemaYaml, UnknownKeysInEverySectionAreErrorsWithTheirLine) {
  EXPECT_EQ(load_error("camera:\n  position: [0, 0, 5]\n  fvo: 30\n").to_string(),
            "scene.yaml:3: camera.fvo: unknown key 'fvo' (did you mean 'fov'?)");
  EXPECT_EQ(load_error("materials:\n  - { name: a, type: metal, roughnes: 0.2 }\n").field,
            "materials[0].roughnes");
  EXPECT_NE(load_error("materials:\n  - { name: a, type: metal, roughnes: 0.2 }\n")
                .message.find("did you mean 'roughness'"),
            std::string::npos);
  EXPECT_EQ(load_error("render: { sp: 4 }\n").message, "unknown key 'sp' (did you mean 'spp'?)");
  // Far from every key: no guess.
  EXPECT_EQ(load_error("render: { wibble: 4 }\n").message, "unknown key 'wibble'");
  const SceneIssue transform = load_error(
      kMaterials +
      "geometry:\n  - { type: sphere, material: white, center: [0, 0, 0], radius: 1,\n"
      "      transform: { translate: [1, 0, 0], rotat: { axis: [0, 1, 0], degrees: 9 } } }\n");
  EXPECT_EQ(transform.field, "geometry[0].transform.rotat");
  EXPECT_EQ(transform.line, 5);
  EXPECT_NE(transform.message.find("did you mean 'rotate'"), std::string::npos);
  // A key of another shape type is unknown here (caps is a cylinder's).
  EXPECT_EQ(
      load_error(kMaterials + "geometry:\n  - { type: sphere, material: white, center: [0, 0, 0], "
                              "radius: 1, caps: true }\n")
          .field,
      "geometry[0].caps");
}

TEST(SchemaYaml, MisspelledTypesSuggestTheNearestKind) {
  const SceneIssue shape =
      load_error(kMaterials +
                 "geometry:\n  - { type: spere, material: white, center: [0, 0, 0], radius: 1 }\n");
  EXPECT_EQ(shape.field, "geometry[0].type");
  EXPECT_NE(shape.message.find("unknown geometry type 'spere' (did you mean 'sphere'?)"),
            std::string::npos);
  const SceneIssue material = load_error("materials:\n  - { name: a, type: lambertain }\n");
  EXPECT_NE(material.message.find("did you mean 'lambertian'"), std::string::npos);
  const SceneIssue reference =
      load_error(kMaterials +
                 "geometry:\n  - { type: sphere, material: whte, center: [0, 0, 0], radius: 1 }\n");
  EXPECT_EQ(reference.message, "unknown material 'whte' (did you mean 'white'?)");
}

TEST(SchemaYaml, LenientTurnsUnknownKeysIntoWarningsAndStillNeedsRequiredOnes) {
  const std::string text =
      kMaterials +
      "geometry:\n  - { type: sphere, material: white, center: [0, 0, 0], raduis: 1 }\n";
  const SceneIssue issue = test::scene_error_of([&] { load(text, true); }, text);
  EXPECT_EQ(issue.field, "geometry[0].radius");
  EXPECT_EQ(issue.message, "is required but missing (is 'raduis' a misspelling of it?)");

  const LoadedScene loaded = load("camera: { fov: 30, zoom: 2 }\n", true);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_EQ(loaded.warnings[0].to_string(),
            "scene.yaml:1: camera.zoom: unknown key 'zoom', ignored");
}

TEST(SchemaYaml, RayonKeysTesseraDoesNotUseAreWarningsThatSaySo) {
  const LoadedScene loaded = load(
      "settings: { background_color: 0.5, use_bvh: true, ambient_light: 0.1 }\n"
      "materials:\n  - { name: m, type: lambertian, pattern: { type: stripes } }\n");
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_EQ(loaded.warnings[0].field, "settings.use_bvh");
  EXPECT_NE(loaded.warnings[0].message.find("RayON key read but not used"), std::string::npos);
  EXPECT_EQ(loaded.warnings[1].field, "settings.ambient_light");
  EXPECT_EQ(loaded.scene.background.color, glm::dvec3(0.5));
  // A pattern is read (stripes draw the plain albedo, as in RayON), so it does not warn.
  ASSERT_TRUE(loaded.scene.materials.at(0).pattern.has_value());
  EXPECT_EQ(loaded.scene.materials[0].pattern->type, "stripes");
}

TEST(SchemaYaml, DefaultsAndRulesComeFromTheDeclaration) {
  // cylinder axis defaults to +y; sdf_box accepts rounding, sdf_rounded_box requires it.
  const LoadedScene loaded = load(
      kMaterials +
      "geometry:\n  - { type: cylinder, material: white, base: [0, 0, 0], radius: 1, height: 2 }\n"
      "  - { type: sdf_box, material: white, half_extent: [1, 1, 1], rounding: 0.5 }\n");
  ASSERT_EQ(loaded.scene.cylinders.size(), 1u);
  EXPECT_EQ(loaded.scene.cylinders[0].axis, glm::dvec3(0, 1, 0));
  EXPECT_DOUBLE_EQ(loaded.scene.sdf_boxes[0].rounding, 0.5);
  EXPECT_EQ(load_error(kMaterials + "geometry:\n  - { type: sdf_rounded_box, material: white, "
                                    "half_extent: [1, 1, 1] }\n")
                .field,
            "geometry[0].rounding");
  EXPECT_EQ(load_error(kMaterials + "geometry:\n  - { type: cone, material: white, base: [0, 0, "
                                    "0], base_radius: -1, height: 1 }\n")
                .message,
            "must be >= 0, got -1");
  EXPECT_EQ(
      load_error("materials:\n  - { name: a, type: anisotropic_metal, preset: bronze }\n").message,
      "unknown preset 'bronze' (expected one of silver,gold,copper,aluminium,aluminum,chromium)");
}

TEST(SchemaYaml, ClosestMatchNeedsAPlausibleTypo) {
  constexpr std::string_view kKeys[] = {"radius", "center", "major_radius", "minor_radius"};
  EXPECT_EQ(schema::closest_match("raidus", kKeys), "radius");  // swapped letters: 1 edit
  EXPECT_EQ(schema::closest_match("centre", kKeys), "center");
  EXPECT_EQ(schema::closest_match("minor_raduis", kKeys), "minor_radius");
  EXPECT_EQ(schema::closest_match("colour", kKeys), "");
  EXPECT_EQ(schema::closest_match("", kKeys), "");
}

// The README's tables are the declarations' own: change a field and this test prints the
// table to paste.
std::string readme_block(const std::string& name) {
  std::ifstream in(std::filesystem::path(TESSERA_SOURCE_DIR) / "README.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const std::string open = "<!-- fields:" + name + " -->\n";
  const std::string close = "<!-- /fields:" + name + " -->";
  const std::size_t begin = all.find(open);
  const std::size_t end = all.find(close);
  if (begin == std::string::npos || end == std::string::npos) return "(no block " + name + ")";
  return all.substr(begin + open.size(), end - begin - open.size());
}

TEST(SchemaDocs, ReadmeTablesAreTheDeclarations) {
  EXPECT_EQ(readme_block("shapes"), schema::shape_table_markdown());
  EXPECT_EQ(readme_block("materials"), schema::material_table_markdown());
  EXPECT_EQ(readme_block("sections"), schema::section_table_markdown());
}

}  // namespace
}  // namespace tessera
