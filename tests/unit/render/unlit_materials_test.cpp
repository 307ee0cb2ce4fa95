// RayON's mirror, constant and show_normals materials in the path tracer, against exact
// answers: a constant surface shows its albedo and nothing else (lights do not shade it),
// show_normals shows 0.5 (n + 1) for the normal facing the camera, and a mirror shows the
// background tinted by its albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kSize = 8;

// A 20 x 20 square in the plane z = 0 with normal +z, filling the view of a camera on the
// z axis at `camera_z` (looking at the origin), a grey background, and a sphere light
// behind the camera that would light the square if anything sampled it.
SceneDescription square_scene(const MaterialDesc& material, double camera_z) {
  SceneDescription scene;
  scene.camera.position = glm::dvec3(0.0, 0.0, camera_z);
  scene.camera.look_at = glm::dvec3(0.0);
  scene.camera.fov_degrees = 30.0;
  scene.materials.push_back(material);
  MaterialDesc lamp;
  lamp.name = "lamp";
  lamp.type = MaterialType::kLight;
  lamp.emission = glm::dvec3(5.0);
  scene.materials.push_back(lamp);
  QuadDesc square;
  square.corner = glm::dvec3(-10.0, -10.0, 0.0);
  square.u = glm::dvec3(20.0, 0.0, 0.0);
  square.v = glm::dvec3(0.0, 20.0, 0.0);
  square.material = 0;
  scene.quads.push_back(square);
  SphereDesc light;
  light.center = glm::dvec3(0.0, 0.0, camera_z * 1.6);
  light.radius = 0.5;
  light.material = 1;
  light.source_index = 1;
  scene.spheres.push_back(light);
  scene.background.color = glm::dvec3(0.4);
  scene.render.width = kSize;
  scene.render.height = kSize;
  scene.render.samples_per_pixel = 4;
  scene.render.max_depth = 8;
  scene.render.tile_size = 8;
  return scene;
}

void expect_every_pixel(const SceneDescription& scene, const glm::vec3& expected, float tolerance) {
  const std::vector<float> image = render_image(*PreparedScene::build(scene));
  ASSERT_EQ(image.size(), kSize * kSize * 4u);
  for (std::size_t p = 0; p < kSize * kSize; ++p)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(image[4 * p + c], expected[c], tolerance) << "pixel " << p << " channel " << c;
}

MaterialDesc material(MaterialType type, const glm::dvec3& albedo) {
  MaterialDesc m;
  m.name = "surface";
  m.type = type;
  m.albedo = albedo;
  return m;
}

TEST(UnlitMaterials, ConstantRendersExactlyItsAlbedo) {
  const glm::dvec3 albedo(0.2, 0.6, 0.9);
  expect_every_pixel(square_scene(material(MaterialType::kConstant, albedo), 5.0),
                     glm::vec3(albedo), 1e-6f);
}

TEST(UnlitMaterials, ShowNormalsRendersTheNormalFacingTheCamera) {
  const MaterialDesc normals = material(MaterialType::kShowNormals, glm::dvec3(0.8));
  // From the front the normal is +z; from behind the square the facing normal is -z.
  expect_every_pixel(square_scene(normals, 5.0), glm::vec3(0.5f, 0.5f, 1.0f), 1e-6f);
  expect_every_pixel(square_scene(normals, -5.0), glm::vec3(0.5f, 0.5f, 0.0f), 1e-6f);
}

TEST(UnlitMaterials, MirrorReflectsTheBackgroundTintedByAlbedo) {
  // Every camera ray reflects away from the square, past the light behind the camera
  // (which covers less than the view's angle only around the axis: keep it out of the way).
  SceneDescription scene = square_scene(material(MaterialType::kMirror, {0.5, 0.25, 1.0}), 5.0);
  scene.spheres.clear();
  scene.materials.pop_back();
  expect_every_pixel(scene, glm::vec3(0.2f, 0.1f, 0.4f), 1e-5f);
}

TEST(UnlitMaterials, ConstantSeenInAMirrorIsTintedByTheMirror) {
  // A mirror square at z = 0 and a constant square behind the camera facing it: the path
  // ends at the constant surface with the mirror's throughput.
  SceneDescription scene = square_scene(material(MaterialType::kMirror, {0.5, 0.5, 0.5}), 5.0);
  scene.spheres.clear();
  scene.materials[1] = material(MaterialType::kConstant, {0.2, 0.4, 0.8});
  QuadDesc back = scene.quads[0];
  back.corner = glm::dvec3(-100.0, -100.0, 10.0);
  back.u = glm::dvec3(200.0, 0.0, 0.0);
  back.v = glm::dvec3(0.0, 200.0, 0.0);
  back.material = 1;
  back.source_index = 1;
  scene.quads.push_back(back);
  expect_every_pixel(scene, glm::vec3(0.1f, 0.2f, 0.4f), 1e-5f);
}

// A furnace lit by a constant surface alone: a Lambertian sphere of albedo 0.5 inside a
// constant sphere of albedo 1. Nothing light-samples the constant surface (it is not a
// light), so its colour arrives only through the BSDF-sampled hit, counted once with full
// weight whatever the light strategy: every sample that sees the inner sphere returns
// exactly 0.5 (cosine sampling's weight is the albedo), every other exactly 1.
TEST(UnlitMaterials, ConstantEnclosureLightsThroughHitsUnderEveryStrategy) {
  for (LightStrategy strategy :
       {LightStrategy::kMis, LightStrategy::kLight, LightStrategy::kBsdf}) {
    SceneDescription scene;
    scene.camera.position = glm::dvec3(0.0, 0.0, 3.0);
    scene.camera.look_at = glm::dvec3(0.0);
    scene.camera.fov_degrees = 50.0;
    scene.materials.push_back(material(MaterialType::kLambertian, glm::dvec3(0.5)));
    scene.materials.push_back(material(MaterialType::kConstant, glm::dvec3(1.0)));
    SphereDesc inner;
    inner.radius = 1.0;
    SphereDesc enclosure;
    enclosure.radius = 20.0;
    enclosure.material = 1;
    enclosure.source_index = 1;
    scene.spheres = {inner, enclosure};
    scene.render.width = kSize;
    scene.render.height = kSize;
    scene.render.samples_per_pixel = 8;
    scene.render.tile_size = 8;
    scene.render.light_strategy = strategy;
    const std::vector<float> image = render_image(*PreparedScene::build(scene));
    int inside = 0;
    for (std::size_t p = 0; p < kSize * kSize; ++p) {
      const float v = image[4 * p];
      // Edge pixels mix both; the rest are exactly one or the other.
      ASSERT_TRUE(v >= 0.5f - 1e-5f && v <= 1.0f + 1e-5f) << "pixel " << p << ": " << v;
      if (std::fabs(v - 0.5f) < 1e-5f) ++inside;
    }
    EXPECT_GT(inside, 4) << static_cast<int>(strategy);
  }
}

}  // namespace
}  // namespace tessera
