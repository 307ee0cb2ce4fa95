// SceneDescription -> proto -> SceneDescription through the one conversion library: every
// field survives, geometry keeps the order it was written in and nothing is left to the
// server's defaults. (schema_proto_test checks the mapping itself against the .proto.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "convert/proto_fields.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

// Fields the client must always send are present (nothing is left to the server's
// defaults), and the library's own reverse conversion gives the scene back.
SceneDescription desc_from_proto(const v1::Scene& scene, const v1::RenderSettings& settings) {
  EXPECT_TRUE(scene.has_camera() && scene.camera().has_up());
  EXPECT_TRUE(scene.background().has_intensity());
  for (const v1::Material& m : scene.materials())
    EXPECT_TRUE(m.has_albedo() && m.has_refractive_index() && m.has_film_ior()) << m.name();
  for (const v1::Geometry& g : scene.geometry()) EXPECT_TRUE(g.has_visible());
  SceneConversion conversion = scene_from_proto(scene, settings);
  EXPECT_TRUE(conversion.ok()) << describe_issues(conversion.issues);
  return conversion.ok() ? std::move(*conversion.scene) : SceneDescription{};
}

void expect_same_scene(const SceneDescription& a, const SceneDescription& b) {
  EXPECT_EQ(a.camera.position, b.camera.position);
  EXPECT_EQ(a.camera.look_at, b.camera.look_at);
  EXPECT_EQ(a.camera.up, b.camera.up);
  EXPECT_EQ(a.camera.fov_degrees, b.camera.fov_degrees);
  EXPECT_EQ(a.background.color, b.background.color);
  EXPECT_EQ(a.background.intensity, b.background.intensity);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    SCOPED_TRACE("material " + a.materials[i].name);
    const MaterialDesc &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.albedo, y.albedo);
    EXPECT_EQ(x.emission, y.emission);
    EXPECT_EQ(x.roughness, y.roughness);
    EXPECT_EQ(x.refractive_index, y.refractive_index);
    EXPECT_EQ(x.metallic, y.metallic);
    EXPECT_EQ(x.transmission, y.transmission);
    EXPECT_EQ(x.anisotropy, y.anisotropy);
    EXPECT_EQ(x.preset, y.preset);
    EXPECT_EQ(x.film_thickness, y.film_thickness);
    EXPECT_EQ(x.film_ior, y.film_ior);
    EXPECT_EQ(x.color, y.color);
    EXPECT_EQ(x.emission_intensity, y.emission_intensity);
    EXPECT_EQ(x.pattern, y.pattern);
    EXPECT_EQ(x, y);  // and every field added later
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    EXPECT_EQ(a.spheres[i].center, b.spheres[i].center);
    EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius);
    EXPECT_EQ(a.spheres[i].material, b.spheres[i].material);
    EXPECT_EQ(a.spheres[i].visible, b.spheres[i].visible);
    EXPECT_EQ(a.spheres[i].source_index, b.spheres[i].source_index);
  }
  ASSERT_EQ(a.quads.size(), b.quads.size());
  for (std::size_t i = 0; i < a.quads.size(); ++i) {
    EXPECT_EQ(a.quads[i].corner, b.quads[i].corner);
    EXPECT_EQ(a.quads[i].u, b.quads[i].u);
    EXPECT_EQ(a.quads[i].v, b.quads[i].v);
    EXPECT_EQ(a.quads[i].material, b.quads[i].material);
    EXPECT_EQ(a.quads[i].visible, b.quads[i].visible);
    EXPECT_EQ(a.quads[i].source_index, b.quads[i].source_index);
  }
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t i = 0; i < a.meshes.size(); ++i) {
    EXPECT_EQ(a.meshes[i].positions, b.meshes[i].positions);
    EXPECT_EQ(a.meshes[i].indices, b.meshes[i].indices);
    EXPECT_EQ(a.meshes[i].material, b.meshes[i].material);
    EXPECT_EQ(a.meshes[i].visible, b.meshes[i].visible);
    EXPECT_EQ(a.meshes[i].source_index, b.meshes[i].source_index);
  }
  EXPECT_EQ(a.render.width, b.render.width);
  EXPECT_EQ(a.render.height, b.render.height);
  EXPECT_EQ(a.render.samples_per_pixel, b.render.samples_per_pixel);
  EXPECT_EQ(a.render.max_depth, b.render.max_depth);
  EXPECT_EQ(a.render.tile_size, b.render.tile_size);
  EXPECT_EQ(a.render.seed, b.render.seed);
  // And everything else: the descriptions are equal but for the file a mesh came from,
  // which does not travel.
  SceneDescription x = a, y = b;
  for (auto& mesh : x.meshes) mesh.source_file.clear();
  for (auto& mesh : y.meshes) mesh.source_file.clear();
  EXPECT_TRUE(x == y);
}

TEST(SceneToProto, CornellBoxRoundTripsExactly) {
  const LoadedScene loaded =
      load_scene_file(std::filesystem::path(TESSERA_SOURCE_DIR) / "examples/scenes/cornell.yaml");
  const v1::SubmitJobRequest request = make_submit_request(loaded.scene, "cornell", 7);
  EXPECT_EQ(request.name(), "cornell");
  EXPECT_EQ(request.priority(), 7);
  EXPECT_EQ(request.scene().geometry_size(), 8);
  EXPECT_EQ(request.settings().width(), 320u);
  EXPECT_EQ(request.settings().samples_per_pixel(), 32u);
  EXPECT_EQ(request.settings().seed(), 1u);
  expect_same_scene(loaded.scene, desc_from_proto(request.scene(), request.settings()));
}

// Every material type, mixed geometry kinds in an interleaved order, a hidden light, a
// standalone triangle and an OBJ mesh loaded from a file.
TEST(SceneToProto, MixedSceneKeepsInputOrderAndEveryField) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "tessera_scene_to_proto_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\nf 1 2 3 4\n";
  const std::string yaml = R"(
camera: { position: [1, 2, 3], look_at: [0, 0.5, 0], up: [0, 0, 1], fov: 33.3 }
settings: { background_color: [0.1, 0.2, 0.3], background_intensity: 0.7 }
materials:
  - { name: diffuse, type: lambertian, albedo: [0.1, 0.2, 0.3] }
  - { name: lamp, type: light, emission: [5, 6, 7] }
  - { name: steel, type: metal, albedo: 0.9, roughness: 0.25 }
  - { name: blur, type: rough_mirror, roughness: 0.5, metallic: 1 }
  - { name: glass, type: glass, refractive_index: 1.7, transmission: 1 }
  - { name: brushed, type: anisotropic_metal, roughness: 0.3, anisotropy: -0.4, preset: gold }
  - { name: coat, type: clear_coat, albedo: [0.8, 0.1, 0.1], refractive_index: 1.45 }
  - { name: bubble, type: thin_film, film_thickness: 420, film_ior: 1.4 }
  - { name: dots, type: lambertian, pattern: { type: fibonacci_dots, color: [0.1, 0.2, 0.3], dot_count: 12, dot_radius: 0.33 } }
  - { name: chrome, type: mirror, albedo: 0.95 }
  - { name: flat, type: constant, albedo: [1, 0, 0.5] }
  - { name: normals, type: show_normals }
  - { name: warm, type: light, color: [1.0, 0.875, 0.75], emission_intensity: 12 }
geometry:
  - { type: triangle, material: coat, v0: [0, 0, 0], v1: [1, 0, 0], v2: [0, 1, 0] }
  - { type: sphere, material: glass, center: [0.1, 0.2, 0.3], radius: 0.123456789 }
  - { type: rectangle, material: lamp, corner: [0, 2, 0], u: [1, 0, 0], v: [0, 0, 1], visible: false }
  - { type: obj, material: steel, file: quad.obj, position: [1, 0, 0], scale: 2 }
  - { type: sphere, material: bubble, center: [-1, 0, 0], radius: 0.5 }
  - { type: quad, material: diffuse, corner: [0, 0, 0], u: [4, 0, 0], v: [0, 0, 4] }
  - { type: sphere, material: brushed, center: [2, 0, 0], radius: 0.25 }
  - { type: sphere, material: blur, center: [3, 0, 0], radius: 0.25, visible: false }
render: { width: 17, height: 9, spp: 3, max_depth: 5, tile_size: 8, seed: 12345678901 }
)";
  const LoadedScene loaded = load_scene_yaml(yaml, "mixed.yaml", dir);
  const v1::SubmitJobRequest request = make_submit_request(loaded.scene, "mixed", -3);
  std::filesystem::remove_all(dir);

  const v1::Scene& scene = request.scene();
  ASSERT_EQ(scene.geometry_size(), 8);
  const v1::Geometry::ShapeCase expected_kinds[] = {
      v1::Geometry::kTriangle, v1::Geometry::kSphere, v1::Geometry::kRectangle,
      v1::Geometry::kMesh,     v1::Geometry::kSphere, v1::Geometry::kRectangle,
      v1::Geometry::kSphere,   v1::Geometry::kSphere};
  for (int i = 0; i < 8; ++i)
    EXPECT_EQ(scene.geometry(i).shape_case(), expected_kinds[i]) << "geometry[" << i << "]";
  EXPECT_EQ(scene.geometry(1).material(), "glass");
  EXPECT_FALSE(scene.geometry(2).visible());
  EXPECT_TRUE(scene.geometry(5).visible());
  // The OBJ quad arrives triangulated, already placed and scaled by the loader.
  EXPECT_EQ(scene.geometry(3).mesh().indices_size(), 6);
  EXPECT_EQ(request.settings().seed(), 12345678901u);
  EXPECT_EQ(request.priority(), -3);

  expect_same_scene(loaded.scene, desc_from_proto(scene, request.settings()));
}

TEST(SceneToProto, MaterialTypesMapOneToOne) {
  for (const MaterialType type :
       {MaterialType::kLambertian, MaterialType::kLight, MaterialType::kMetal,
        MaterialType::kRoughMirror, MaterialType::kGlass, MaterialType::kAnisotropicMetal,
        MaterialType::kClearCoat, MaterialType::kThinFilm, MaterialType::kMirror,
        MaterialType::kConstant, MaterialType::kShowNormals}) {
    const v1::MaterialType proto = material_type_to_proto(type);
    EXPECT_NE(proto, v1::MATERIAL_TYPE_UNSPECIFIED) << to_string(type);
    // Names agree: MATERIAL_TYPE_<UPPER-CASE YAML NAME>.
    std::string upper = to_string(type);
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(v1::MaterialType_Name(proto), "MATERIAL_TYPE_" + upper);
  }
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

TEST(SceneToProto, SamplerAndLightStrategyTravel) {
  SceneDescription scene =
      load_scene_yaml("render: { sampler: independent, light_strategy: light }\n", "s.yaml", ".")
          .scene;
  v1::RenderSettings settings = settings_to_proto(scene.render);
  EXPECT_EQ(settings.sampler(), v1::SAMPLER_INDEPENDENT);
  EXPECT_EQ(settings.light_strategy(), v1::LIGHT_STRATEGY_LIGHT);
  EXPECT_EQ(settings_from_proto(settings), scene.render);
  for (std::size_t i = 0; i < sampler_names().size(); ++i) {
    scene.render.sampler = static_cast<SamplerKind>(i);
    const v1::RenderSettings out = settings_to_proto(scene.render);
    EXPECT_EQ(v1::Sampler_Name(out.sampler()),
              proto_fields::enum_value_name("SAMPLER_", to_string(scene.render.sampler)));
    EXPECT_EQ(settings_from_proto(out).sampler, scene.render.sampler);
  }
  for (std::size_t i = 0; i < light_strategy_names().size(); ++i) {
    scene.render.light_strategy = static_cast<LightStrategy>(i);
    const v1::RenderSettings out = settings_to_proto(scene.render);
    EXPECT_EQ(
        v1::LightStrategy_Name(out.light_strategy()),
        proto_fields::enum_value_name("LIGHT_STRATEGY_", to_string(scene.render.light_strategy)));
    EXPECT_EQ(settings_from_proto(out).light_strategy, scene.render.light_strategy);
  }
}

TEST(SceneToProto, IntegratorAndAovsTravel) {
  SceneDescription scene =
      load_scene_file(std::filesystem::path(TESSERA_SOURCE_DIR) / "examples/scenes/cornell.yaml")
          .scene;
  EXPECT_EQ(settings_to_proto(scene.render).integrator(), v1::INTEGRATOR_PATH);
  scene.render.aovs = kAovDepth | kAovNormal;
  v1::RenderSettings settings = settings_to_proto(scene.render);
  ASSERT_EQ(settings.aovs_size(), 2);
  EXPECT_EQ(settings.aovs(0), v1::AOV_NORMAL);
  EXPECT_EQ(settings.aovs(1), v1::AOV_DEPTH);
  EXPECT_EQ(aov_mask_from_proto(settings), kAovDepth | kAovNormal);
  for (IntegratorKind kind :
       {IntegratorKind::kNormals, IntegratorKind::kShadow, IntegratorKind::kTransparency,
        IntegratorKind::kAlbedo, IntegratorKind::kDepth, IntegratorKind::kPhong}) {
    scene.render.integrator = kind;
    std::string upper = to_string(kind);
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(v1::Integrator_Name(settings_to_proto(scene.render).integrator()),
              "INTEGRATOR_" + upper);
  }
}

}  // namespace
}  // namespace tessera
