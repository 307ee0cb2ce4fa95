// How next-event estimation shares its picks between lights at infinity and bounded ones.
#include <gtest/gtest.h>

#include "scene_materials.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

using glm::dvec3;

// RayON's 01_bvh_test_scene in small: a dim sky, a panel light, and a ground that is a
// sphere of radius 1000. Weighed over the bounds of all the geometry, the sky had 13,000
// times the panel's power and the panel was picked once in 13,000; over the region of the
// lights and the camera, and with either side kept within [0.1, 0.9], both are sampled.
TEST(LightShare, AHugeShapeDoesNotStarveTheBoundedLights) {
  SceneDescription scene;
  scene.camera.position = {-10.0, 5.0, 8.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  scene.materials = {test::lambertian_material("ground", dvec3(0.45)),
                     test::light_material("panel", dvec3(4.0))};
  scene.spheres.push_back(SphereDesc{.center = {0, -1000, 0}, .radius = 1000, .material = 0});
  scene.quads.push_back(QuadDesc{
      .corner = {-4, 6, -4}, .u = {8, 0, 0}, .v = {0, 0, 8}, .material = 1, .visible = false});
  scene.environment = EnvironmentDesc{.type = "gradient", .intensity = 0.18};
  const auto prepared = PreparedScene::build(scene);
  const SceneView view = prepared->view();
  ASSERT_EQ(view.light_count, 2u);
  ASSERT_EQ(view.first_infinite_light, 1u);
  const float panel = view.lights[0].pmf, sky = view.lights[1].pmf;
  EXPECT_NEAR(panel + sky, 1.0f, 1e-6f);
  EXPECT_GE(panel, 0.1f - 1e-6f);
  EXPECT_GE(sky, 0.1f - 1e-6f);
  // The sky's power over the lit region: 4 pi^2 R^2 L with R about 9.8 (the panel and the
  // camera), L = 0.18 (0.75, 0.85, 1) in luminance, against the panel's 2 pi 4 * 64: the
  // panel takes about 0.7 of the picks.
  EXPECT_GT(panel, 0.5f);
}

// With only lights at infinity the share does not apply: a sun (with an extent, so it is
// picked) and the sky keep their power ratio whatever the radius.
TEST(LightShare, LightsAtInfinityAloneKeepTheirPowerRatio) {
  SceneDescription scene;
  scene.materials = {test::lambertian_material("ground", dvec3(0.5))};
  scene.spheres.push_back(SphereDesc{.center = {0, -1000, 0}, .radius = 1000, .material = 0});
  scene.environment = EnvironmentDesc{.type = "constant", .color = dvec3(1.0), .intensity = 1.0};
  scene.lights.push_back(LightDesc{
      .type = "sun", .direction = {0, -1, 0}, .irradiance = 4.0, .angular_radius_degrees = 0.5});
  const auto prepared = PreparedScene::build(scene);
  const SceneView view = prepared->view();
  ASSERT_EQ(view.light_count, 2u);
  // Sun E pi R^2 against sky 4 pi^2 R^2 L: 4 / (4 pi) of the sky's.
  const float sun = view.lights[0].pmf, sky = view.lights[1].pmf;
  EXPECT_NEAR(sun / sky, 1.0f / 3.14159265f, 1e-4f);
}

// Up to four delta lights are sampled at every vertex and never picked; the other lights
// share the picks. Five or more are picked among the rest as before.
TEST(LightShare, AFewDeltaLightsAreSampledAtEveryVertex) {
  SceneDescription scene;
  scene.materials = {test::lambertian_material("ground", dvec3(0.5))};
  scene.quads.push_back(
      QuadDesc{.corner = {-5, 0, -5}, .u = {10, 0, 0}, .v = {0, 0, 10}, .material = 0});
  scene.environment = EnvironmentDesc{.type = "gradient", .intensity = 0.3};
  scene.lights.push_back(LightDesc{.type = "point", .position = {0, 2, 0}, .intensity = 5.0});
  scene.lights.push_back(LightDesc{.type = "sun", .direction = {-1, -2, 0}, .irradiance = 2.0});
  {
    const auto prepared = PreparedScene::build(scene);
    const SceneView view = prepared->view();
    ASSERT_EQ(view.light_count, 3u);
    EXPECT_EQ(view.every_vertex_count, 2u);
    EXPECT_TRUE(view.pick_lights);
    float picked = 0.0f;
    for (std::uint32_t i = 0; i < view.light_count; ++i) {
      const LightSource& light = view.lights[i];
      EXPECT_EQ(light.every_vertex, !light.hit_by_rays) << i;
      if (light.every_vertex) {
        EXPECT_EQ(light.pmf, 0.0f) << i;
      }
      picked += light.pmf;
    }
    EXPECT_NEAR(picked, 1.0f, 1e-6f);  // the sky alone
  }
  scene.environment.reset();
  scene.background.intensity = 0.0;
  {
    const SceneView view = PreparedScene::build(scene)->view();
    EXPECT_EQ(view.every_vertex_count, 2u);
    EXPECT_FALSE(view.pick_lights);  // nothing left to pick
  }
  for (int i = 0; i < 3; ++i)
    scene.lights.push_back(
        LightDesc{.type = "point", .position = {double(i), 3, 0}, .intensity = 1.0});
  const SceneView view = PreparedScene::build(scene)->view();
  EXPECT_EQ(view.every_vertex_count, 0u);
  EXPECT_TRUE(view.pick_lights);
}

}  // namespace
}  // namespace tessera
