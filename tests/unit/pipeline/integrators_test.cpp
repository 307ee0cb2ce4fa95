#include <gtest/gtest.h>

#include <cmath>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

MaterialDesc material(const std::string& name, MaterialType type, glm::dvec3 albedo) {
  MaterialDesc m;
  m.name = name;
  m.type = type;
  m.albedo = albedo;
  return m;
}

// Camera at the origin looking down -z at a 1x1-pixel image (narrow field of view), so
// every sample hits near the image centre.
SceneDescription single_pixel(IntegratorKind integrator) {
  SceneDescription scene;
  scene.camera.position = {0, 0, 0};
  scene.camera.look_at = {0, 0, -1};
  scene.camera.fov_degrees = 0.01;
  scene.render.width = 1;
  scene.render.height = 1;
  scene.render.samples_per_pixel = 4;
  scene.render.tile_size = 8;
  scene.render.integrator = integrator;
  return scene;
}

std::vector<float> render(const SceneDescription& scene) {
  return render_image(*PreparedScene::build(scene));
}

TEST(Integrators, NormalsDepthAndAlbedoOfASphereFacingTheCamera) {
  SceneDescription scene = single_pixel(IntegratorKind::kNormals);
  scene.materials.push_back(material("m", MaterialType::kLambertian, {0.2, 0.4, 0.6}));
  scene.spheres.push_back(SphereDesc{{0, 0, -10}, 2.0, 0, true, 0});
  auto pixel = render(scene);
  EXPECT_NEAR(pixel[0], 0.5f, 1e-3f);  // normal (0, 0, 1) -> (0.5, 0.5, 1)
  EXPECT_NEAR(pixel[1], 0.5f, 1e-3f);
  EXPECT_NEAR(pixel[2], 1.0f, 1e-3f);

  scene.render.integrator = IntegratorKind::kDepth;
  pixel = render(scene);
  EXPECT_NEAR(pixel[0], 8.0f, 1e-4f);

  scene.render.integrator = IntegratorKind::kAlbedo;
  pixel = render(scene);
  EXPECT_NEAR(pixel[0], 0.2f, 1e-6f);
  EXPECT_NEAR(pixel[1], 0.4f, 1e-6f);
  EXPECT_NEAR(pixel[2], 0.6f, 1e-6f);
}

TEST(Integrators, TransparencyCompositesEveryHitFrontToBack) {
  // Two glass panes (opacity 1 - transmission = 0.25 each) in front of an opaque red wall,
  // all facing the camera. Headlight shading at normal incidence is exactly albedo.
  SceneDescription scene = single_pixel(IntegratorKind::kTransparency);
  MaterialDesc pane = material("pane", MaterialType::kLambertian, {1, 1, 1});
  pane.transmission = 0.75;
  scene.materials.push_back(pane);
  scene.materials.push_back(material("red", MaterialType::kLambertian, {1, 0, 0}));
  for (double z : {-2.0, -3.0})
    scene.quads.push_back(QuadDesc{{-1, -1, z}, {2, 0, 0}, {0, 2, 0}, 0, true, 0});
  scene.quads.push_back(QuadDesc{{-1, -1, -5}, {2, 0, 0}, {0, 2, 0}, 1, true, 0});
  const auto pixel = render(scene);
  // C = 0.25 + 0.75 * 0.25 + 0.75 * 0.75 * red
  EXPECT_NEAR(pixel[0], 0.25f + 0.1875f + 0.5625f, 1e-5f);
  EXPECT_NEAR(pixel[1], 0.25f + 0.1875f, 1e-5f);
}

TEST(Integrators, ShadowIntegratorIsDarkBehindABlocker) {
  // A floor lit by a small lamp straight above, with a blocker between them: the spot
  // under the blocker gets no direct light; a spot beside it does.
  SceneDescription scene = single_pixel(IntegratorKind::kShadow);
  scene.camera.position = {0, 1, 0.001};
  scene.camera.look_at = {0, 0, 0};
  scene.materials.push_back(material("floor", MaterialType::kLambertian, {0.5, 0.5, 0.5}));
  MaterialDesc lamp = material("lamp", MaterialType::kLight, {1, 1, 1});
  lamp.emission = {10, 10, 10};
  scene.materials.push_back(lamp);
  scene.quads.push_back(QuadDesc{{-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 0, true, 0});
  scene.quads.push_back(QuadDesc{{-0.1, 4, -0.1}, {0.2, 0, 0}, {0, 0, 0.2}, 1, false, 1});
  const float lit = render(scene)[0];
  EXPECT_GT(lit, 0.0f);
  scene.quads.push_back(
      QuadDesc{{-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, 0, true, 2});  // above the camera
  const float shadowed = render(scene)[0];
  EXPECT_EQ(shadowed, 0.0f);
  // Unshadowed: L = albedo/pi * Le * cos*cos * A / d^2 for a small lamp straight above.
  const float expected = 0.5f / kPi * 10.0f * 0.04f / 16.0f;
  EXPECT_NEAR(lit, expected, expected * 0.01f);
}

}  // namespace
}  // namespace tessera
