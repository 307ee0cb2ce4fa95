// RayON's fibonacci_dots pattern: the spiral's points by hand, the dot test against RayON's
// own construction (arc-cosine form, nearest point by angle) in double precision, and
// rendered albedo images against the pattern evaluated on each pixel's exact camera ray,
// measured from a sphere's centre and from the world origin on a rectangle, as RayON does.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "first_hit_scene.hpp"
#include "tessera/render/pattern.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"

namespace tessera {
namespace {

TEST(Pattern, FibonacciPointsFollowTheSpiral) {
  // By hand: z = 1 - (2i + 1) / n, longitude = 2.39996323 (i + 0.5).
  const struct {
    std::uint32_t i, n;
    vec3 expected;
  } cases[] = {{0, 4, {0.2396885f, 0.6164815f, 0.75f}},
               {3, 4, {-0.3434044f, 0.5653082f, -0.75f}},
               {0, 1, {0.3623749f, 0.9320324f, 0.0f}}};
  for (const auto& c : cases) {
    const vec3 p = spherical_fibonacci_point(c.i, c.n);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], c.expected[k], 2e-6f) << c.i << "/" << c.n;
  }
  for (std::uint32_t i = 0; i < 50; ++i)
    EXPECT_NEAR(glm::length(spherical_fibonacci_point(i, 50)), 1.0f, 1e-6f);
}

// RayON's construction: polar angle acos(1 - 2 v), the nearest point by the largest dot
// product, inside when its arc cosine is below the radius. Returns nothing within 1e-4
// radians of the edge, where float and double may disagree.
std::optional<bool> rayon_in_dot(const glm::dvec3& direction, int n, double radius) {
  double best = -1.0;
  for (int i = 0; i < n; ++i) {
    const double k = i + 0.5;
    const double polar = std::acos(1.0 - 2.0 * k / n);
    const double longitude = 2.39996323 * k;
    const glm::dvec3 c(std::cos(longitude) * std::sin(polar), std::sin(longitude) * std::sin(polar),
                       std::cos(polar));
    best = std::max(best, glm::dot(direction, c));
  }
  const double angle = std::acos(std::clamp(best, -1.0, 1.0));
  if (std::fabs(angle - radius) < 1e-4) return std::nullopt;
  return angle < radius;
}

MaterialPattern dots(std::uint32_t count, float radius) {
  MaterialPattern p;
  p.type = PatternType::kFibonacciDots;
  p.color = vec3(0.02f, 0.03f, 0.04f);
  p.dot_count = count;
  p.cos_dot_radius = std::cos(radius);
  return p;
}

TEST(Pattern, DotsMatchRayonsConstruction) {
  const MaterialPattern pattern = dots(12, 0.33f);
  const vec3 base(0.9f, 0.1f, 0.1f);
  std::uint64_t state = 12345;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  int inside = 0, outside = 0;
  for (int i = 0; i < 4000; ++i) {
    const double z = 1.0 - 2.0 * uniform(), phi = 2.0 * 3.141592653589793 * uniform();
    const double r = std::sqrt(1.0 - z * z);
    const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
    const std::optional<bool> expected = rayon_in_dot(d, 12, 0.33);
    if (!expected) continue;
    // Any length: the pattern normalises the offset from the centre.
    const vec3 albedo = patterned_albedo(pattern, base, vec3(d * 2.5));
    EXPECT_EQ(albedo, *expected ? pattern.color : base) << d.x << " " << d.y << " " << d.z;
    ++(*expected ? inside : outside);
  }
  // 12 caps of 0.33 rad cover 12 (1 - cos 0.33) / 2 = 32% of the sphere.
  EXPECT_NEAR(inside / 4000.0, 0.324, 0.03);
  EXPECT_GT(outside, 2000);
}

TEST(Pattern, EdgesAndOtherTypes) {
  // One dot, at (cos 1.2, sin 1.2, 0) (longitude 2.39996323 / 2): inside up to 0.33 rad.
  const MaterialPattern one = dots(1, 0.33f);
  const vec3 base(0.5f);
  const float centre = 2.39996323f * 0.5f;
  const auto at = [&](float longitude) {
    return patterned_albedo(one, base, vec3(std::cos(longitude), std::sin(longitude), 0.0f));
  };
  EXPECT_EQ(at(centre), one.color);
  EXPECT_EQ(at(centre + 0.32f), one.color);
  EXPECT_EQ(at(centre - 0.34f), base);
  EXPECT_EQ(at(centre + 3.14159f), base);
  EXPECT_EQ(patterned_albedo(one, base, vec3(0.0f)), base);  // no direction at the centre
  // RayON parses checkerboard and stripes but draws the plain albedo.
  for (PatternType type : {PatternType::kCheckerboard, PatternType::kStripes, PatternType::kNone}) {
    MaterialPattern p = one;
    p.type = type;
    EXPECT_EQ(patterned_albedo(p, base, vec3(std::cos(centre), std::sin(centre), 0.0f)), base);
  }
}

// The albedo integrator's image of `scene` against the pattern on each pixel's exact
// camera ray; `hit` gives the hit point's offset from the pattern's centre, or nothing.
template <typename Hit>
void expect_pattern_image(const SceneDescription& scene, const PatternDesc& p,
                          const glm::dvec3& base, Hit&& hit) {
  const std::vector<float> image = render_image(*PreparedScene::build(scene));
  const std::uint32_t w = scene.render.width, h = scene.render.height;
  ASSERT_EQ(image.size(), std::size_t{w} * h * 4);
  int dotted = 0, plain = 0;
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      const Ray ray = test::first_sample_camera_ray(scene, x, y);
      const std::optional<glm::dvec3> offset =
          hit(glm::dvec3(ray.origin), glm::normalize(glm::dvec3(ray.direction)));
      if (!offset) continue;
      const std::optional<bool> in_dot =
          rayon_in_dot(glm::normalize(*offset), static_cast<int>(p.dot_count), p.dot_radius);
      if (!in_dot) continue;
      const glm::dvec3 expected = *in_dot ? p.color : base;
      const std::size_t at = (std::size_t{y} * w + x) * 4;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(image[at + c], expected[c], 1e-6) << "pixel " << x << ", " << y;
      ++(*in_dot ? dotted : plain);
    }
  }
  EXPECT_GT(dotted, 20);
  EXPECT_GT(plain, 20);
}

MaterialDesc dotted_material(const PatternDesc& pattern, const glm::dvec3& albedo) {
  MaterialDesc m;
  m.name = "dotted";
  m.albedo = albedo;
  m.pattern = pattern;
  return m;
}

PatternDesc golf_dots() {
  PatternDesc p;
  p.type = "fibonacci_dots";
  p.color = glm::dvec3(0.02, 0.5, 0.9);
  p.dot_count = 40;
  p.dot_radius = 0.2;
  return p;
}

TEST(Pattern, SphereDotsAreMeasuredFromItsCentre) {
  CameraDesc camera;
  camera.position = glm::dvec3(1.0, 2.0, 4.0);
  camera.look_at = glm::dvec3(1.0, 2.0, 0.0);
  camera.fov_degrees = 35.0;
  SceneDescription scene = test::first_hit_scene(camera, 48, 48, IntegratorKind::kAlbedo, 3);
  const glm::dvec3 base(0.9, 0.1, 0.1);
  scene.materials[0] = dotted_material(golf_dots(), base);
  SphereDesc sphere;
  sphere.center = glm::dvec3(1.0, 2.0, 0.0);
  sphere.radius = 1.0;
  scene.spheres.push_back(sphere);
  expect_pattern_image(scene, golf_dots(), base,
                       [&](const glm::dvec3& o, const glm::dvec3& d) -> std::optional<glm::dvec3> {
                         const glm::dvec3 oc = o - sphere.center;
                         const double b = glm::dot(oc, d);
                         const double disc = b * b - (glm::dot(oc, oc) - 1.0);
                         if (disc < 1e-3) return std::nullopt;  // grazing: skip
                         return oc + (-b - std::sqrt(disc)) * d;
                       });
}

TEST(Pattern, OtherShapesMeasureFromTheWorldOrigin) {
  CameraDesc camera;
  camera.position = glm::dvec3(0.3, -0.2, 3.0);
  camera.look_at = glm::dvec3(0.3, -0.2, 0.0);
  camera.fov_degrees = 60.0;
  SceneDescription scene = test::first_hit_scene(camera, 48, 48, IntegratorKind::kAlbedo, 5);
  const glm::dvec3 base(0.2, 0.7, 0.3);
  scene.materials[0] = dotted_material(golf_dots(), base);
  QuadDesc quad;  // the plane z = 1, in front of the origin
  quad.corner = glm::dvec3(-10.0, -10.0, 1.0);
  quad.u = glm::dvec3(20.0, 0.0, 0.0);
  quad.v = glm::dvec3(0.0, 20.0, 0.0);
  scene.quads.push_back(quad);
  expect_pattern_image(scene, golf_dots(), base,
                       [](const glm::dvec3& o, const glm::dvec3& d) -> std::optional<glm::dvec3> {
                         return o + ((1.0 - o.z) / d.z) * d;
                       });
}

}  // namespace
}  // namespace tessera
