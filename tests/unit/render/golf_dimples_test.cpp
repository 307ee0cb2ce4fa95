// RayON's displaced_sphere: the dimple height field against its definition (deepest at the
// spiral's points, shallower towards the rim), the normal tilting towards a dimple's centre
// on its wall and not at all at its centre or with strength 0, and rendered images: the same
// silhouette as a plain sphere, with normals that differ across the ball.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tessera/render/golf_dimples.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

// A unit direction at angle `angle` from `centre`, turned towards `towards`.
vec3 tilted(const vec3& centre, const vec3& towards, float angle) {
  const vec3 side = glm::normalize(towards - glm::dot(towards, centre) * centre);
  return std::cos(angle) * centre + std::sin(angle) * side;
}

TEST(GolfDimples, HeightIsDeepestAtTheSpiralPoints) {
  for (std::uint32_t i : {0u, 17u, 75u, 149u}) {
    const vec3 c = spherical_fibonacci_point(i, kGolfDimpleCount);
    EXPECT_NEAR(golf_dimple_height(c), -kGolfDimpleDepth, 1e-3f) << i;
    // 0.05 rad out, towards any direction: the nearest point is still c (neighbours are
    // about 0.29 rad apart), so the profile is 0.35 cos(pi/2 0.05 / 0.24).
    const vec3 off = tilted(c, vec3(0.3f, 0.8f, -0.5f), 0.05f);
    EXPECT_NEAR(golf_dimple_height(off),
                -kGolfDimpleDepth * std::cos(0.05f / kGolfDimpleRadius * kPi * 0.5f), 2e-3f)
        << i;
  }
}

TEST(GolfDimples, NormalTiltsTowardsTheDimpleCentreOnItsWall) {
  const vec3 c = spherical_fibonacci_point(40, kGolfDimpleCount);
  const vec3 eye = c;  // looking straight at the dimple
  // At the centre the slope is 0; RayON's one-sided differences 0.015 apart read
  // 0.35 (pi / 0.48)^2 0.015 / 2 = 0.11 there, a tilt of about 0.2 * 0.11 * sqrt(2) = 0.03.
  EXPECT_LT(glm::length(golf_dimpled_normal(c, eye, 0.2f) - c), 0.04f);
  const vec3 wall = tilted(c, vec3(0.0f, 0.0f, 1.0f), 0.1f);
  EXPECT_EQ(golf_dimpled_normal(wall, eye, 0.0f), wall);
  const vec3 n = golf_dimpled_normal(wall, eye, 0.2f);
  EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  EXPECT_GT(glm::dot(n - wall, c - wall), 0.0f);
  EXPECT_GT(glm::length(n - wall), 0.05f);
  EXPECT_LE(glm::length(n - wall), 0.41f);  // the tilt is capped at 0.4 before normalising
  // Seen edge-on the dimples fade out (RayON's smoothstep on n . v).
  const vec3 grazing = glm::normalize(glm::cross(wall, vec3(0.3f, 0.2f, 0.9f)));
  EXPECT_EQ(golf_dimpled_normal(wall, grazing, 0.2f), wall);
}

std::vector<float> render_ball(const std::string& type) {
  const std::string text = R"(
camera: { position: [0, 0, 4], look_at: [0, 0, 0], fov: 35 }
materials: [ { name: white, type: lambertian } ]
geometry:
  - { type: )" + type + R"(, material: white, center: [0, 0, 0], radius: 1 }
render: { width: 48, height: 48, spp: 1, integrator: normals }
)";
  return render_image(*PreparedScene::build(load_scene_yaml(text, type, ".").scene));
}

TEST(GolfDimples, RenderedBallKeepsTheSphereSilhouetteWithDimpledNormals) {
  const std::vector<float> plain = render_ball("sphere");
  const std::vector<float> golf = render_ball("displaced_sphere");
  ASSERT_EQ(plain.size(), golf.size());
  int covered = 0, dimpled = 0;
  for (std::size_t p = 0; p < plain.size(); p += 4) {
    ASSERT_EQ(plain[p + 3], golf[p + 3]) << "coverage differs at " << p / 4;
    if (plain[p + 3] == 0.0f) continue;
    ++covered;
    const float d = std::fabs(plain[p] - golf[p]) + std::fabs(plain[p + 1] - golf[p + 1]) +
                    std::fabs(plain[p + 2] - golf[p + 2]);
    dimpled += d > 0.01f;
  }
  EXPECT_GT(covered, 1000);
  EXPECT_GT(dimpled, covered / 3);
}

}  // namespace
}  // namespace tessera
