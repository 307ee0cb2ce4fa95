// Finite but absurd numbers (a camera at 1e308, an emission of 1e308, a radius of 1e300)
// and NURBS weights far apart are refused with the field named, by the scene model's own
// rules, so every loader gets them.
#include <gtest/gtest.h>

#include <string>

#include "scene_error_of.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/scene/schema/field.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

LoadedScene load(const std::string& text) {
  return load_scene_yaml(text, "scene.yaml", ".");
}

SceneIssue load_error(const std::string& text) {
  return test::scene_error_of([&] { load(text); }, text);
}

std::string with_geometry(const std::string& entry) {
  return "materials:\n"
         "  - { name: white, type: lambertian }\n"
         "  - { name: lamp, type: light, emission: [4, 4, 4] }\n"
         "geometry:\n"
         "  - { type: sphere, material: white, center: [0, 0, -9], radius: 1 }\n" +
         entry + "\n";
}

TEST(Magnitude, AbsurdFiniteValuesAreRefusedWithTheFieldNamed) {
  const SceneIssue camera = load_error("camera: { position: [0, 0, 1e308] }\n");
  EXPECT_EQ(camera.field, "camera.position");
  EXPECT_NE(camera.message.find("within +-1e+12"), std::string::npos) << camera.message;
  EXPECT_EQ(
      load_error("materials:\n  - { name: hot, type: light, emission: [1e308, 1, 1] }\n").field,
      "materials[0].emission");
  EXPECT_EQ(load_error(with_geometry("  - { type: sphere, material: white, center: [0, 0, 0], "
                                     "radius: 1e300 }"))
                .field,
            "geometry[1].radius");
  EXPECT_EQ(load_error(with_geometry("  - { type: triangle, material: white, v0: [0, 0, 0], "
                                     "v1: [1, 0, 0], v2: [0, -1e200, 0] }"))
                .field,
            "geometry[1].v2");
  EXPECT_EQ(load_error(with_geometry("  - { type: sphere, material: white, center: [0, 0, 0], "
                                     "radius: 1, transform: { translate: [1e13, 0, 0] } }"))
                .field,
            "geometry[1].transform.translate");
}

TEST(Magnitude, LargeButPhysicalValuesStillLoad) {
  EXPECT_NO_THROW(load(
      with_geometry("  - { type: sphere, material: white, center: [0, 0, -1e9], radius: 6.4e6 }\n"
                    "  - { type: sphere, material: lamp, center: [1e11, 0, 0], radius: 7e8 }")));
  EXPECT_EQ(schema::kMaxMagnitude, 1e12);
}

// A 4 x 4 planar grid over [0, 3]^2 in z = 0, written row by row (rows along u).
const char* kGrid =
    "[[[0,0,0],[0,1,0],[0,2,0],[0,3,0]],[[1,0,0],[1,1,0],[1,2,0],[1,3,0]],\n"
    "                     [[2,0,0],[2,1,0],[2,2,0],[2,3,0]],[[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]";

std::string patch_with_weights(const std::string& weights) {
  return with_geometry(std::string("  - type: bspline_patch\n"
                                   "    material: white\n"
                                   "    control_points: ") +
                       kGrid + "\n    weights: " + weights);
}

TEST(Magnitude, NurbsWeightsFarApartAreRefused) {
  const SceneIssue extreme =
      load_error(patch_with_weights("[[1,1,1,1],[1,1e-300,1e300,1],[1,1,1,1],[1,1,1,1]]"));
  EXPECT_EQ(extreme.field, "geometry[1].weights[6]");  // 1e300: beyond the magnitude bound
  const SceneIssue spread =
      load_error(patch_with_weights("[[1,1,1,1],[1,1e-4,1e3,1],[1,1,1,1],[1,1,1,1]]"));
  EXPECT_EQ(spread.field, "geometry[1].weights");
  EXPECT_NE(spread.message.find("at most 1000000"), std::string::npos) << spread.message;
  EXPECT_NO_THROW(load(patch_with_weights("[[1,1,1,1],[1,1e-3,1e3,1],[1,1,1,1],[1,1,1,1]]")));
  EXPECT_EQ(kMaxWeightRatio, 1e6);
}

TEST(Magnitude, ControlPointsBeyondTheBoundAreRefused) {
  const std::string far =
      with_geometry(std::string("  - type: bspline_patch\n"
                                "    material: white\n"
                                "    control_points: ") +
                    "[[[0,0,0],[0,1,0],[0,2,0],[0,3,0]],[[1,0,0],[1,1,1e15],[1,2,0],[1,3,0]],\n"
                    "     [[2,0,0],[2,1,0],[2,2,0],[2,3,0]],[[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]");
  EXPECT_EQ(load_error(far).field, "geometry[1].control_points[5]");
}

}  // namespace
}  // namespace tessera
