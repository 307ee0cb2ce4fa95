// Two-level structure: instances of one mesh under rotations, non-uniform scales and
// translations against brute force over triangles transformed into world space.
#include "tessera/accel/instance_accel.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "accel_test_scenes.hpp"

namespace tessera {
namespace {

TEST(InstanceAccel, MatchesTransformedTrianglesByBruteForce) {
  const std::vector<Triangle> mesh = accel_test::closed_sphere(3);
  const TriangleAccel accel = TriangleAccel::build(mesh);
  const glm::mat4 transforms[] = {
      glm::translate(glm::mat4(1.0f), vec3(3.0f, 0.0f, 0.0f)),
      glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), vec3(-2.0f, 1.0f, 0.0f)), 0.5f,
                             vec3(0, 0, 1)),
                 vec3(0.5f)),
      glm::scale(glm::translate(glm::mat4(1.0f), vec3(0.0f, 0.0f, 3.0f)), vec3(1.0f, 2.0f, 0.5f)),
  };
  std::vector<MeshInstance> instances;
  std::vector<Triangle> world;
  for (const glm::mat4& m : transforms) {
    instances.push_back(MeshInstance{&accel, m});
    for (const Triangle& t : mesh)
      world.push_back(Triangle{vec3(m * vec4(t.p0, 1.0f)), vec3(m * vec4(t.p1, 1.0f)),
                               vec3(m * vec4(t.p2, 1.0f)), 0});
  }
  const InstanceAccel instanced(instances);

  std::mt19937 rng(5);
  std::size_t hits = 0, disagreements = 0, rays = 0;
  for (int i = 0; i < 3000; ++i) {
    const vec3 origin = accel_test::random_point(rng, -6.0f, 6.0f);
    const vec3 target = vec3(transforms[i % 3][3]) + accel_test::random_point(rng, -1.0f, 1.0f);
    const Ray ray{origin, glm::normalize(target - origin)};
    ++rays;
    const accel_test::ReferenceHit expected = accel_test::reference_closest(world, ray);
    InstanceHit got;
    const bool hit = instanced.closest(ray, got);
    EXPECT_EQ(instanced.occluded(ray), hit);
    if (hit != expected.hit) {
      ++disagreements;  // grazing rays: object and world space round differently
      continue;
    }
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(got.hit.t, expected.record.t, 1e-4f * expected.record.t);
    EXPECT_EQ(got.instance, expected.record.primitive / mesh.size());
  }
  EXPECT_GT(hits, rays / 3);
  EXPECT_LE(disagreements, rays / 200);
}

TEST(InstanceAccel, EmptyAndInvalid) {
  const InstanceAccel none(std::vector<MeshInstance>{});
  InstanceHit hit;
  EXPECT_FALSE(none.closest(Ray{vec3(0.0f), vec3(0, 0, 1)}, hit));
  EXPECT_FALSE(none.occluded(Ray{vec3(0.0f), vec3(0, 0, 1)}));
  const TriangleAccel accel = TriangleAccel::build(accel_test::closed_sphere(1));
  EXPECT_THROW(InstanceAccel({MeshInstance{&accel, glm::mat4(0.0f)}}), std::invalid_argument);
  EXPECT_THROW(InstanceAccel({MeshInstance{nullptr, glm::mat4(1.0f)}}), std::invalid_argument);
}

}  // namespace
}  // namespace tessera
