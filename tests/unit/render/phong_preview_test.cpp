// The Phong preview integrator: every pixel of a lambertian and of a metal sphere against
// Blinn-Phong evaluated by hand on that pixel's exact camera ray and the sphere's exact
// normal, in double precision.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "first_hit_scene.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kSize = 40;

SceneDescription sphere_scene(const MaterialDesc& material, std::uint64_t seed) {
  CameraDesc camera;
  camera.position = glm::dvec3(0.3, 0.4, 4.0);
  camera.look_at = glm::dvec3(0.0, 0.0, 0.0);
  camera.fov_degrees = 35.0;
  SceneDescription scene =
      test::first_hit_scene(camera, kSize, kSize, IntegratorKind::kPhong, seed);
  scene.materials = {material};
  SphereDesc sphere;
  sphere.radius = 1.0;
  scene.spheres.push_back(sphere);
  return scene;
}

// The unit sphere at the origin: the outward normal where the ray first meets it.
std::optional<glm::dvec3> sphere_normal(const glm::dvec3& origin, const glm::dvec3& direction) {
  const double b = glm::dot(origin, direction);
  const double c = glm::dot(origin, origin) - 1.0;
  const double disc = b * b - c;
  if (disc < 0.0) return std::nullopt;
  const double t = -b - std::sqrt(disc);
  return glm::normalize(origin + t * direction);
}

void expect_phong_image(const MaterialDesc& material,
                        double (*expected)(double facing, int channel, const glm::dvec3& albedo)) {
  const SceneDescription scene = sphere_scene(material, 3);
  const std::vector<float> image = render_image(*PreparedScene::build(scene));
  int hits = 0;
  for (std::uint32_t y = 0; y < kSize; ++y)
    for (std::uint32_t x = 0; x < kSize; ++x) {
      const Ray ray = test::first_sample_camera_ray(scene, x, y);
      const glm::dvec3 d = glm::normalize(glm::dvec3(ray.direction));
      const std::optional<glm::dvec3> n = sphere_normal(glm::dvec3(ray.origin), d);
      const std::size_t at = (std::size_t{y} * kSize + x) * 4;
      if (!n) {
        ASSERT_EQ(image[at + 3], 0.0f) << x << ", " << y;
        continue;
      }
      // Grazing pixels: float and double may disagree on whether the ray hits at all.
      const double facing = glm::dot(*n, -d);
      if (facing < 0.05) continue;
      ++hits;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(image[at + c], expected(facing, c, material.albedo), 2e-3)
            << "pixel " << x << ", " << y << " channel " << c;
    }
  EXPECT_GT(hits, 400);
}

TEST(PhongPreview, LambertianIsAlbedoTimesAmbientPlusCosine) {
  MaterialDesc m;
  m.name = "clay";
  m.albedo = glm::dvec3(0.7, 0.4, 0.2);
  expect_phong_image(m, [](double facing, int c, const glm::dvec3& albedo) {
    return albedo[c] * (0.15 + 0.85 * facing);
  });
}

TEST(PhongPreview, MetalHighlightFollowsItsGgxAlpha) {
  MaterialDesc m;
  m.name = "steel";
  m.type = MaterialType::kMetal;
  m.albedo = glm::dvec3(0.9, 0.8, 0.6);
  m.roughness = 0.6;  // GGX alpha 0.3: Blinn-Phong exponent 2 / 0.09 - 2
  expect_phong_image(m, [](double facing, int c, const glm::dvec3& albedo) {
    return albedo[c] * (0.15 + 0.85 * std::pow(facing, 2.0 / 0.09 - 2.0));
  });
}

}  // namespace
}  // namespace tessera
