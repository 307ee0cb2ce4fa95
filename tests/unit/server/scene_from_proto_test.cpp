#include "convert/scene_proto.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::set_vec3;
using testing::tiny_scene;
using testing::tiny_settings;

std::string issues_text(const SceneConversion& conversion) {
  return describe_issues(conversion.issues);
}

// Expects exactly one issue, at `field`, whose message contains `message`.
void expect_single_issue(const v1::Scene& scene, const v1::RenderSettings& settings,
                         const std::string& field, const std::string& message) {
  const SceneConversion conversion = scene_from_proto(scene, settings);
  EXPECT_FALSE(conversion.ok());
  ASSERT_EQ(conversion.issues.size(), 1u) << issues_text(conversion);
  EXPECT_EQ(conversion.issues[0].field, field) << issues_text(conversion);
  EXPECT_NE(conversion.issues[0].message.find(message), std::string::npos)
      << "message was: " << conversion.issues[0].message;
}

void expect_single_issue(const v1::Scene& scene, const std::string& field,
                         const std::string& message) {
  expect_single_issue(scene, tiny_settings(), field, message);
}

TEST(SceneFromProto, ConvertsEveryShapeWithItsMaterialAndSourceIndex) {
  v1::Scene scene = tiny_scene();
  v1::Geometry* triangle = scene.add_geometry();  // geometry[2]
  triangle->set_material("grey");
  triangle->set_visible(false);
  set_vec3(triangle->mutable_triangle()->mutable_v0(), 0, 0, 0);
  set_vec3(triangle->mutable_triangle()->mutable_v1(), 1, 0, 0);
  set_vec3(triangle->mutable_triangle()->mutable_v2(), 0, 1, 0);
  v1::Geometry* mesh = scene.add_geometry();  // geometry[3]
  mesh->set_material("lamp");
  for (double p : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0})
    mesh->mutable_mesh()->add_positions(p);
  for (unsigned i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh->mutable_mesh()->add_indices(i);

  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_TRUE(conversion.ok()) << issues_text(conversion);
  const SceneDescription& d = *conversion.scene;

  EXPECT_EQ(d.camera.position, glm::dvec3(0, 0, 5));
  EXPECT_EQ(d.camera.up, glm::dvec3(0, 1, 0));  // unset: default
  EXPECT_DOUBLE_EQ(d.camera.fov_degrees, 40.0);
  EXPECT_EQ(d.background.color, glm::dvec3(0.1, 0.1, 0.1));
  EXPECT_DOUBLE_EQ(d.background.intensity, 1.0);  // unset optional: default

  ASSERT_EQ(d.materials.size(), 2u);
  EXPECT_EQ(d.materials[0].name, "grey");
  EXPECT_EQ(d.materials[0].type, MaterialType::kLambertian);
  EXPECT_EQ(d.materials[0].albedo, glm::dvec3(0.8));
  EXPECT_DOUBLE_EQ(d.materials[0].refractive_index, 1.5);
  EXPECT_DOUBLE_EQ(d.materials[0].film_ior, 1.33);
  EXPECT_EQ(d.materials[1].type, MaterialType::kLight);
  EXPECT_EQ(d.materials[1].albedo, glm::dvec3(1.0));  // lights default to white
  EXPECT_EQ(d.materials[1].emission, glm::dvec3(4.0));

  ASSERT_EQ(d.spheres.size(), 1u);
  EXPECT_EQ(d.spheres[0].source_index, 0u);
  EXPECT_EQ(d.spheres[0].material, 0u);
  EXPECT_DOUBLE_EQ(d.spheres[0].radius, 1.0);
  EXPECT_TRUE(d.spheres[0].visible);

  ASSERT_EQ(d.quads.size(), 1u);
  EXPECT_EQ(d.quads[0].source_index, 1u);
  EXPECT_EQ(d.quads[0].material, 1u);
  EXPECT_EQ(d.quads[0].corner, glm::dvec3(-1, 2, -1));
  EXPECT_EQ(d.quads[0].v, glm::dvec3(0, 0, 2));

  ASSERT_EQ(d.meshes.size(), 2u);
  EXPECT_EQ(d.meshes[0].source_index, 2u);
  EXPECT_FALSE(d.meshes[0].visible);
  EXPECT_EQ(d.meshes[0].positions[1], glm::dvec3(1, 0, 0));
  EXPECT_EQ(d.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(d.meshes[1].source_index, 3u);
  EXPECT_EQ(d.meshes[1].material, 1u);
  ASSERT_EQ(d.meshes[1].positions.size(), 4u);
  EXPECT_EQ(d.meshes[1].positions[2], glm::dvec3(1, 1, 0));
  EXPECT_EQ(d.meshes[1].indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));

  EXPECT_EQ(d.render.width, 16u);
  EXPECT_EQ(d.render.samples_per_pixel, 1u);
}

TEST(SceneFromProto, ZeroRenderSettingsGetServerDefaults) {
  v1::RenderSettings settings;
  settings.set_seed(7);
  const SceneConversion conversion = scene_from_proto(tiny_scene(), settings);
  ASSERT_TRUE(conversion.ok()) << issues_text(conversion);
  const RenderSettings& r = conversion.scene->render;
  EXPECT_EQ(r.width, 320u);
  EXPECT_EQ(r.height, 240u);
  EXPECT_EQ(r.samples_per_pixel, 16u);
  EXPECT_EQ(r.max_depth, 16u);
  EXPECT_EQ(r.tile_size, 32u);
  EXPECT_EQ(r.seed, 7u);
  EXPECT_EQ(r.sampler, SamplerKind::kSobol);
  EXPECT_EQ(r.light_strategy, LightStrategy::kMis);

  const v1::RenderSettings back = settings_to_proto(r);
  EXPECT_EQ(back.width(), 320u);
  EXPECT_EQ(back.tile_size(), 32u);
  EXPECT_EQ(back.seed(), 7u);
  // Written explicitly, so the job record says what the server chose.
  EXPECT_EQ(back.sampler(), v1::SAMPLER_SOBOL);
  EXPECT_EQ(back.light_strategy(), v1::LIGHT_STRATEGY_MIS);
}

TEST(SceneFromProto, SamplerAndLightStrategyConvertBothWays) {
  v1::RenderSettings in = tiny_settings();
  in.set_sampler(v1::SAMPLER_INDEPENDENT);
  in.set_light_strategy(v1::LIGHT_STRATEGY_BSDF);
  RenderSettings core = settings_from_proto(in);
  EXPECT_EQ(core.sampler, SamplerKind::kIndependent);
  EXPECT_EQ(core.light_strategy, LightStrategy::kBsdf);
  v1::RenderSettings back = settings_to_proto(core);
  EXPECT_EQ(back.sampler(), v1::SAMPLER_INDEPENDENT);
  EXPECT_EQ(back.light_strategy(), v1::LIGHT_STRATEGY_BSDF);

  in.set_sampler(v1::SAMPLER_SOBOL);
  in.set_light_strategy(v1::LIGHT_STRATEGY_LIGHT);
  core = settings_from_proto(in);
  EXPECT_EQ(core.sampler, SamplerKind::kSobol);
  EXPECT_EQ(core.light_strategy, LightStrategy::kLight);
  back = settings_to_proto(core);
  EXPECT_EQ(back.sampler(), v1::SAMPLER_SOBOL);
  EXPECT_EQ(back.light_strategy(), v1::LIGHT_STRATEGY_LIGHT);
}

TEST(SceneFromProto, DeviceConvertsBothWaysAndAnUnknownOneIsNamed) {
  v1::RenderSettings in = tiny_settings();
  EXPECT_EQ(settings_from_proto(in).device, RenderDevice::kAny);  // unspecified
  EXPECT_EQ(settings_to_proto(settings_from_proto(in)).device(), v1::RENDER_DEVICE_ANY);
  in.set_device(v1::RENDER_DEVICE_GPU);
  EXPECT_EQ(settings_from_proto(in).device, RenderDevice::kGpu);
  EXPECT_EQ(settings_to_proto(settings_from_proto(in)).device(), v1::RENDER_DEVICE_GPU);
  in.set_device(v1::RENDER_DEVICE_CPU);
  EXPECT_EQ(settings_from_proto(in).device, RenderDevice::kCpu);
  EXPECT_EQ(settings_to_proto(settings_from_proto(in)).device(), v1::RENDER_DEVICE_CPU);
  v1::RenderSettings settings = tiny_settings();
  settings.set_device(static_cast<v1::RenderDevice>(9));
  expect_single_issue(tiny_scene(), settings, "settings.device",
                      "unknown device value 9 (expected RENDER_DEVICE_ANY, RENDER_DEVICE_CPU or "
                      "RENDER_DEVICE_GPU)");
}

TEST(SceneFromProto, UnknownSamplerAndLightStrategyNameTheFieldAndTheValues) {
  v1::RenderSettings settings = tiny_settings();
  settings.set_sampler(static_cast<v1::Sampler>(7));
  expect_single_issue(tiny_scene(), settings, "settings.sampler",
                      "unknown sampler value 7 (expected SAMPLER_INDEPENDENT or SAMPLER_SOBOL)");
  settings = tiny_settings();
  settings.set_light_strategy(static_cast<v1::LightStrategy>(-1));
  expect_single_issue(
      tiny_scene(), settings, "settings.light_strategy",
      "unknown light strategy value -1 (expected LIGHT_STRATEGY_MIS, LIGHT_STRATEGY_LIGHT or "
      "LIGHT_STRATEGY_BSDF)");
}

// Progressive passes split spp into sample ranges, so the same two rules as YAML's
// render.passes apply, named in protobuf's path style.
TEST(SceneFromProto, PassesAreCheckedAgainstSppAndAdaptiveSampling) {
  v1::RenderSettings settings = tiny_settings();
  settings.set_samples_per_pixel(8);
  settings.set_passes(4);
  const SceneConversion ok = scene_from_proto(tiny_scene(), settings);
  ASSERT_TRUE(ok.ok()) << issues_text(ok);
  EXPECT_EQ(ok.scene->render.passes, 4u);
  EXPECT_EQ(settings_to_proto(ok.scene->render).passes(), 4u);
  settings.set_passes(9);
  expect_single_issue(tiny_scene(), settings, "settings.passes",
                      "must not exceed samples_per_pixel (8), got 9");
  settings.set_passes(2);
  settings.set_target_error(0.05);
  settings.set_min_samples_per_pixel(4);
  expect_single_issue(tiny_scene(), settings, "settings.passes", "adaptive sampling");
  settings.set_passes(0);  // one pass
  EXPECT_TRUE(scene_from_proto(tiny_scene(), settings).ok());
}

TEST(SceneFromProto, MissingShapeIsNamed) {
  v1::Scene scene = tiny_scene();
  scene.add_geometry()->set_material("grey");
  expect_single_issue(scene, "geometry[2].shape",
                      "set one of sphere, displaced_sphere, rectangle, triangle, mesh, plane");
}

TEST(SceneFromProto, UnknownMaterialNameIsNamed) {
  v1::Scene scene = tiny_scene();
  scene.mutable_geometry(1)->set_material("nope");
  expect_single_issue(scene, "geometry[1].material", "unknown material 'nope'");
}

TEST(SceneFromProto, MissingMaterialReferenceIsNamed) {
  v1::Scene scene = tiny_scene();
  scene.mutable_geometry(0)->clear_material();
  expect_single_issue(scene, "geometry[0].material", "is required");
}

TEST(SceneFromProto, UnspecifiedMaterialTypeIsRejected) {
  v1::Scene scene = tiny_scene();
  scene.mutable_materials(1)->set_type(v1::MATERIAL_TYPE_UNSPECIFIED);
  expect_single_issue(scene, "materials[1].type", "MATERIAL_TYPE_UNSPECIFIED");
}

TEST(SceneFromProto, OutOfRangeMaterialTypeIsRejected) {
  v1::Scene scene = tiny_scene();
  scene.mutable_materials(0)->set_type(static_cast<v1::MaterialType>(42));
  expect_single_issue(scene, "materials[0].type", "unknown material type 42");
}

TEST(SceneFromProto, LightWithoutEmissionIsRejected) {
  v1::Scene scene = tiny_scene();
  scene.mutable_materials(1)->clear_emission();
  expect_single_issue(scene, "materials[1].emission", "required for a light material");
}

TEST(SceneFromProto, UnknownMetalPresetIsRejected) {
  v1::Scene scene = tiny_scene();
  scene.mutable_materials(0)->set_type(v1::MATERIAL_TYPE_ANISOTROPIC_METAL);
  scene.mutable_materials(0)->set_preset("unobtainium");
  expect_single_issue(scene, "materials[0].preset", "unknown preset 'unobtainium'");
}

TEST(SceneFromProto, NegativeRadiusGivesTheExactMessage) {
  v1::Scene scene = tiny_scene();
  for (int i = 0; i < 2; ++i) {
    v1::Geometry* g = scene.add_geometry();
    g->set_material("grey");
    g->mutable_sphere()->set_radius(0.5);
  }
  scene.mutable_geometry(3)->mutable_sphere()->set_radius(-1);
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_EQ(conversion.issues.size(), 1u);
  EXPECT_EQ(describe_issues(conversion.issues), "geometry[3].sphere.radius: must be > 0, got -1");
}

TEST(SceneFromProto, ZeroRadiusIsRejected) {
  v1::Scene scene = tiny_scene();
  scene.mutable_geometry(0)->mutable_sphere()->clear_radius();
  expect_single_issue(scene, "geometry[0].sphere.radius", "must be > 0, got 0");
}

TEST(SceneFromProto, NonFiniteNumbersNameTheComponent) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_geometry(0)->mutable_sphere()->mutable_center()->set_y(nan);
    expect_single_issue(scene, "geometry[0].sphere.center.y", "must be a finite number, got nan");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_geometry(0)->mutable_sphere()->set_radius(inf);
    expect_single_issue(scene, "geometry[0].sphere.radius", "must be a finite number, got inf");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_camera()->set_fov_degrees(-inf);
    expect_single_issue(scene, "camera.fov_degrees", "must be a finite number, got -inf");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_geometry(1)->mutable_rectangle()->mutable_u()->set_z(nan);
    expect_single_issue(scene, "geometry[1].rectangle.u.z", "finite");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_materials(0)->set_roughness(nan);
    expect_single_issue(scene, "materials[0].roughness", "finite");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_background()->set_intensity(inf);
    expect_single_issue(scene, "background.intensity", "finite");
  }
}

v1::Geometry* add_mesh(v1::Scene& scene, std::initializer_list<double> positions,
                       std::initializer_list<unsigned> indices) {
  v1::Geometry* g = scene.add_geometry();
  g->set_material("grey");
  v1::TriangleMesh* mesh = g->mutable_mesh();
  for (double p : positions) mesh->add_positions(p);
  for (unsigned i : indices) mesh->add_indices(i);
  return g;
}

TEST(SceneFromProto, MeshLayoutErrorsAreNamed) {
  {
    v1::Scene scene = tiny_scene();
    add_mesh(scene, {0, 0, 0, 1, 0, 0, 0, 1}, {0, 1, 2});
    expect_single_issue(scene, "geometry[2].mesh.positions",
                        "count must be a multiple of 3 (x, y, z per vertex), got 8");
  }
  {
    v1::Scene scene = tiny_scene();
    add_mesh(scene, {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 2, 1, 3});
    expect_single_issue(scene, "geometry[2].mesh.indices[5]",
                        "vertex index 3 out of range (3 vertices)");
  }
  {
    v1::Scene scene = tiny_scene();
    add_mesh(scene, {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0});
    expect_single_issue(scene, "geometry[2].mesh.indices", "multiple of 3");
  }
  {
    v1::Scene scene = tiny_scene();
    add_mesh(scene, {0, 0, 0, 1, 0, 0, 0, 1, 0}, {});
    expect_single_issue(scene, "geometry[2].mesh.indices", "at least one triangle");
  }
  {
    v1::Scene scene = tiny_scene();
    add_mesh(scene, {0, 0, 0, 1, std::nan(""), 0, 0, 1, 0}, {0, 1, 2});
    expect_single_issue(scene, "geometry[2].mesh.positions[4]", "finite");
  }
}

// Checks validate_scene() makes, reported under the protobuf paths.
TEST(SceneFromProto, SemanticErrorsUseProtobufFieldPaths) {
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_materials(0)->set_roughness(2.5);
    expect_single_issue(scene, "materials[0].roughness", "got 2.5");
  }
  {
    v1::Scene scene = tiny_scene();
    set_vec3(scene.mutable_geometry(1)->mutable_rectangle()->mutable_v(), 4, 0, 0);
    expect_single_issue(scene, "geometry[1].rectangle.v", "parallel");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_camera()->set_fov_degrees(200);
    expect_single_issue(scene, "camera.fov_degrees", "got 200");
  }
  {
    v1::Scene scene = tiny_scene();
    set_vec3(scene.mutable_camera()->mutable_look_at(), 0, 0, 5);
    expect_single_issue(scene, "camera.look_at", "must differ");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_background()->set_intensity(-1);
    expect_single_issue(scene, "background.intensity", "got -1");
  }
  {
    v1::Scene scene = tiny_scene();
    scene.mutable_materials(1)->set_name("grey");
    scene.mutable_geometry(1)->set_material("grey");  // refers to the first "grey"
    expect_single_issue(scene, "materials[1].name", "duplicate material name 'grey'");
  }
  {
    v1::RenderSettings settings = tiny_settings();
    settings.set_tile_size(4);
    expect_single_issue(tiny_scene(), settings, "settings.tile_size", "got 4");
  }
  {
    v1::RenderSettings settings = tiny_settings();
    settings.set_samples_per_pixel(1'000'000);
    expect_single_issue(tiny_scene(), settings, "settings.samples_per_pixel", "got 1000000");
  }
  {
    v1::RenderSettings settings = tiny_settings();
    settings.set_width(100'000);
    expect_single_issue(tiny_scene(), settings, "settings.width", "got 100000");
  }
}

TEST(SceneFromProto, ReportsEveryStructuralIssue) {
  v1::Scene scene = tiny_scene();
  scene.mutable_geometry(0)->mutable_sphere()->set_radius(-2);
  scene.mutable_geometry(1)->set_material("missing");
  scene.mutable_materials(0)->set_type(v1::MATERIAL_TYPE_UNSPECIFIED);
  const SceneConversion conversion = scene_from_proto(scene, tiny_settings());
  ASSERT_EQ(conversion.issues.size(), 3u) << issues_text(conversion);
  EXPECT_EQ(conversion.issues[0].field, "materials[0].type");
  EXPECT_EQ(conversion.issues[1].field, "geometry[0].sphere.radius");
  EXPECT_EQ(conversion.issues[2].field, "geometry[1].material");
  EXPECT_EQ(issues_text(conversion),
            "materials[0].type: must be set (got MATERIAL_TYPE_UNSPECIFIED); "
            "geometry[0].sphere.radius: must be > 0, got -2; "
            "geometry[1].material: unknown material 'missing'");
}

TEST(SceneFromProto, AnEmptySceneUsesTheYamlDefaults) {
  const SceneConversion conversion = scene_from_proto(v1::Scene(), tiny_settings());
  ASSERT_TRUE(conversion.ok()) << issues_text(conversion);
  EXPECT_EQ(conversion.scene->camera.position, CameraDesc{}.position);
  EXPECT_TRUE(conversion.scene->spheres.empty());
}

}  // namespace
}  // namespace tessera::server
