// The renderer draws B-spline/NURBS patches and trimmed faces end to end (description ->
// pools and flat arrays -> BVH -> dispatch -> depth integrator). Each image is compared
// pixel by pixel with an independent answer for the same camera rays: the plane or
// cylinder the patch equals, solved analytically in double, a point-in-polygon test of
// our own for trimming holes, or the same patch with its control points moved by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

#include "first_hit_scene.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/scene_error.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kWidth = 48;
constexpr std::uint32_t kHeight = 36;

SceneDescription base_scene() {
  CameraDesc camera;
  camera.position = {1.5, 3.0, 6.0};
  camera.look_at = {0.0, 0.3, 0.0};
  camera.fov_degrees = 45.0;
  return test::first_hit_scene(camera, kWidth, kHeight, IntegratorKind::kDepth, 5);
}

Ray camera_ray(const SceneDescription& scene, std::uint32_t x, std::uint32_t y) {
  return test::first_sample_camera_ray(scene, x, y);
}

std::vector<float> render_depth(const SceneDescription& scene) {
  EXPECT_TRUE(validate_scene(scene).empty());
  const auto prepared = PreparedScene::build(scene);
  EXPECT_TRUE(prepared->variant().features.covers(prepared->required_features()));
  return render_image(*prepared);
}

using DepthReference = std::function<std::optional<double>(const dvec3& origin, const dvec3& d)>;

struct Comparison {
  int hits = 0;
  int mismatches = 0;
};

// Every pixel's depth against `reference` (distance along the unit ray; nullopt: a miss).
Comparison compare_depth(const SceneDescription& scene, const DepthReference& reference,
                         double relative_tolerance, int allowed_mismatches) {
  const std::vector<float> image = render_depth(scene);
  Comparison result;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const Ray ray = camera_ray(scene, x, y);
      const dvec3 d = glm::normalize(dvec3(ray.direction));
      const std::optional<double> expected = reference(dvec3(ray.origin), d);
      const float depth = image[(y * kWidth + x) * 4];
      if (expected) ++result.hits;
      const bool ok = expected
                          ? std::fabs(depth - *expected) <= relative_tolerance * *expected + 1e-6
                          : depth == 0.0f;
      if (!ok && ++result.mismatches > allowed_mismatches)
        ADD_FAILURE() << "pixel (" << x << ", " << y << "): rendered " << depth << ", expected "
                      << (expected ? std::to_string(*expected) : std::string("a miss"));
    }
  return result;
}

// A 4 x 4 grid spanning corner + s u + t v, s, t in [0, 1], evenly spaced: with clamped
// knots a bicubic patch with collinear, evenly spaced control rows is exactly that
// parallelogram.
SplinePatchDesc planar_patch(const dvec3& corner, const dvec3& u, const dvec3& v) {
  SplinePatchDesc p;
  p.count_u = 4;
  p.count_v = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) p.control_points.push_back(corner + (i / 3.0) * u + (j / 3.0) * v);
  return p;
}

// Distance to the plane y = height along the ray, if ahead.
std::optional<double> plane_y(const dvec3& o, const dvec3& d, double height) {
  if (d.y == 0.0) return std::nullopt;
  const double t = (height - o.y) / d.y;
  return t > 0.0 ? std::optional<double>(t) : std::nullopt;
}

TEST(PatchesRender, PlanarPatchEqualsTheSquareItSpans) {
  SceneDescription scene = base_scene();
  scene.patches.push_back(planar_patch({-2, 0, -2}, {4, 0, 0}, {0, 0, 4}));
  const Comparison c = compare_depth(
      scene,
      [](const dvec3& o, const dvec3& d) -> std::optional<double> {
        const auto t = plane_y(o, d, 0.0);
        if (!t) return std::nullopt;
        const dvec3 p = o + *t * d;
        if (std::fabs(p.x) > 2.0 || std::fabs(p.z) > 2.0) return std::nullopt;
        return t;
      },
      1e-5, 0);
  EXPECT_GT(c.hits, 300);
}

// The cubic rational Bézier of a quarter circle (degree-elevated from the quadratic one):
// homogeneous points H0, (H0 + 2 H1) / 3, (2 H1 + H2) / 3, H2 with H1 = w (1, 1) and
// w = sqrt(2) / 2.
void quarter_circle(double radius, std::vector<glm::dvec2>& points, std::vector<double>& weights) {
  const double w = std::sqrt(0.5);
  const glm::dvec3 h0(radius, 0, 1), h1(w * radius, w * radius, w), h2(0, radius, 1);
  const glm::dvec3 h[4] = {h0, (h0 + 2.0 * h1) / 3.0, (2.0 * h1 + h2) / 3.0, h2};
  for (const auto& p : h) {
    points.emplace_back(p.x / p.z, p.y / p.z);
    weights.push_back(p.z);
  }
}

TEST(PatchesRender, NurbsQuarterCylinderMatchesTheAnalyticCylinder) {
  constexpr double kRadius = 1.5, kHeight = 1.6;
  SceneDescription scene = base_scene();
  std::vector<glm::dvec2> circle;
  std::vector<double> circle_weights;
  quarter_circle(kRadius, circle, circle_weights);
  SplinePatchDesc p;
  p.count_u = 4;
  p.count_v = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      p.control_points.emplace_back(circle[i].x, kHeight * j / 3.0, circle[i].y);
      p.weights.push_back(circle_weights[i]);
    }
  scene.patches.push_back(p);
  const Comparison c = compare_depth(
      scene,
      [](const dvec3& o, const dvec3& d) -> std::optional<double> {
        // x^2 + z^2 = R^2, nearest root with x, z >= 0 and 0 <= y <= h.
        const double a = d.x * d.x + d.z * d.z;
        const double b = o.x * d.x + o.z * d.z;
        const double cc = o.x * o.x + o.z * o.z - kRadius * kRadius;
        const double disc = b * b - a * cc;
        if (a == 0.0 || disc < 0.0) return std::nullopt;
        const double q = -(b + std::copysign(std::sqrt(disc), b));
        double roots[2] = {q / a, cc / q};
        if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
        for (double t : roots) {
          const dvec3 x = o + t * d;
          if (t > 0.0 && x.x >= 0.0 && x.z >= 0.0 && x.y >= 0.0 && x.y <= kHeight) return t;
        }
        return std::nullopt;
      },
      1e-4, 3);
  EXPECT_GT(c.hits, 100);
}

// Crossing-number point-in-polygon, independent of the geometry module's winding test.
bool inside_polygon(const std::vector<glm::dvec2>& polygon, const glm::dvec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const glm::dvec2 &a = polygon[i], &b = polygon[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
      inside = !inside;
  }
  return inside;
}

TEST(PatchesRender, RaysThroughATrimmingHoleSeeWhatIsBehind) {
  SceneDescription scene = base_scene();
  // A 4 x 4 square at y = 0 trimmed to a pentagon-like outer loop with a hexagonal hole,
  // above a larger floor rectangle at y = -1.
  QuadDesc square;
  square.corner = {-2, 0, -2};
  square.u = {4, 0, 0};
  square.v = {0, 0, 4};
  TrimmedFaceDesc face;
  face.surface = square;
  const std::vector<glm::dvec2> outer = {
      {0.05, 0.05}, {0.95, 0.1}, {0.9, 0.95}, {0.5, 0.8}, {0.08, 0.92}};
  std::vector<glm::dvec2> hole;
  for (int k = 0; k < 6; ++k) {
    const double a = 2.0 * 3.14159265358979 * k / 6.0;
    hole.emplace_back(0.5 + 0.25 * std::cos(a), 0.45 + 0.25 * std::sin(a));
  }
  face.loops = {outer, hole};
  face.source_index = 0;
  scene.trimmed_faces.push_back(face);
  QuadDesc floor;
  floor.corner = {-4, -1, -4};
  floor.u = {8, 0, 0};
  floor.v = {0, 0, 8};
  floor.source_index = 1;
  scene.quads.push_back(floor);

  int through_hole = 0;
  const Comparison c = compare_depth(
      scene,
      [&](const dvec3& o, const dvec3& d) -> std::optional<double> {
        if (const auto t = plane_y(o, d, 0.0)) {
          const dvec3 p = o + *t * d;
          // The quad's uv: (s, t) along u and v.
          const glm::dvec2 uv((p.x + 2.0) / 4.0, (p.z + 2.0) / 4.0);
          if (inside_polygon(outer, uv) && !inside_polygon(hole, uv)) return t;
          if (inside_polygon(hole, uv)) ++through_hole;
        }
        if (const auto t = plane_y(o, d, -1.0)) {
          const dvec3 p = o + *t * d;
          if (std::fabs(p.x) <= 4.0 && std::fabs(p.z) <= 4.0) return t;
        }
        return std::nullopt;
      },
      1e-5, 3);  // rays within float rounding of a loop edge may go either way
  EXPECT_GT(c.hits, 500);
  EXPECT_GT(through_hole, 30);
}

// p -> translate + R(axis, degrees) (scale * p), by Rodrigues' formula.
dvec3 place_by_hand(const TransformDesc& t, const dvec3& p) {
  const dvec3 s = t.scale * p;
  const dvec3 k = glm::normalize(t.rotate_axis);
  const double a = glm::radians(t.rotate_degrees);
  const dvec3 r =
      s * std::cos(a) + glm::cross(k, s) * std::sin(a) + k * glm::dot(k, s) * (1.0 - std::cos(a));
  return t.translate + r;
}

TEST(PatchesRender, TransformedPatchEqualsItsHandPlacedControlGrid) {
  // A wavy 5 x 4 NURBS patch (non-uniform clamped knots) placed by a rotation, a
  // non-uniform scale and a translation.
  SplinePatchDesc wavy;
  wavy.count_u = 5;
  wavy.count_v = 4;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) {
      wavy.control_points.emplace_back(-1.0 + 0.5 * i, 0.4 * std::sin(1.3 * i + 2.1 * j),
                                       -1.0 + 2.0 * j / 3.0);
      wavy.weights.push_back(1.0 + 0.3 * ((i + j) % 3));
    }
  wavy.knots_u = {0, 0, 0, 0, 0.3, 1, 1, 1, 1};
  TransformDesc t;
  t.translate = {0.2, 0.5, -0.3};
  t.rotate_axis = {1, 1, 0};
  t.rotate_degrees = 35.0;
  t.scale = {1.2, 0.8, 1.5};

  SceneDescription placed = base_scene();
  wavy.transform = t;
  placed.patches.push_back(wavy);
  SceneDescription by_hand = base_scene();
  wavy.transform = std::nullopt;
  for (auto& p : wavy.control_points) p = place_by_hand(t, p);
  by_hand.patches.push_back(wavy);

  const std::vector<float> a = render_depth(placed), b = render_depth(by_hand);
  int hits = 0, mismatches = 0;
  for (std::size_t i = 0; i < a.size(); i += 4) {
    if (b[i] > 0.0f) ++hits;
    if (std::fabs(a[i] - b[i]) > 1e-4f * b[i]) ++mismatches;
  }
  EXPECT_GT(hits, 150);
  EXPECT_LE(mismatches, 2);  // silhouette pixels may flip on last-bit differences
}

TEST(PatchesRender, TrimmedSphereUnderATransformKeepsItsUvRegion) {
  // The upper half of a sphere's u range (u in [0, 0.5]: the half with z <= 0 in object
  // space, from u = (atan2(-z, x) + pi) / 2 pi) for v in [0.3, 1] (above y = -r cos(0.3 pi)),
  // then rotated 90 degrees around y and moved.
  SceneDescription scene = base_scene();
  SphereDesc sphere;
  sphere.radius = 1.2;
  TrimmedFaceDesc face;
  face.surface = sphere;
  face.loops = {{{0.0, 0.3}, {0.25, 0.3}, {0.5, 0.3}, {0.5, 1.0}, {0.25, 1.0}, {0.0, 1.0}}};
  TransformDesc t;
  t.rotate_axis = {0, 1, 0};
  t.rotate_degrees = 90.0;
  t.translate = {0.3, 0.2, 0.0};
  face.transform = t;
  scene.trimmed_faces.push_back(face);
  const double r = 1.2;
  const dvec3 center(0.3, 0.2, 0.0);
  const Comparison c = compare_depth(
      scene,
      [&](const dvec3& o, const dvec3& d) -> std::optional<double> {
        const dvec3 oc = o - center;
        const double b = glm::dot(oc, d), cc = glm::dot(oc, oc) - r * r;
        const double disc = b * b - cc;
        if (disc < 0.0) return std::nullopt;
        const double q = -(b + std::copysign(std::sqrt(disc), b));
        double roots[2] = {q, cc / q};
        if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
        for (double root : roots) {
          if (!(root > 0.0)) continue;
          // World -> object: undo the translation and the 90 degree turn about y
          // (object (x, y, z) went to world (z, y, -x)).
          const dvec3 w = o + root * d - center;
          const dvec3 p(-w.z, w.y, w.x);
          const double u = (std::atan2(-p.z, p.x) + 3.14159265358979) / (2 * 3.14159265358979);
          const double v = std::acos(glm::clamp(-p.y / r, -1.0, 1.0)) / 3.14159265358979;
          if (u >= 0.0 && u <= 0.5 && v >= 0.3) return root;
        }
        return std::nullopt;
      },
      1e-4, 4);
  EXPECT_GT(c.hits, 100);
}

TEST(PatchesRender, ManyPatchesAndATrimmedPatchShareTheirPools) {
  // Several patches, so the piece pool grows (and moves) while the scene is built, then a
  // planar patch trimmed to a diamond in its knot domain [0, 1]^2, above them.
  SceneDescription scene = base_scene();
  for (int k = 0; k < 5; ++k) {
    SplinePatchDesc p = planar_patch({-3.0 + 1.2 * k, -0.5, -2}, {1.0, 0, 0}, {0, 0, 4});
    p.source_index = static_cast<std::uint32_t>(k);
    scene.patches.push_back(p);
  }
  TrimmedFaceDesc face;
  face.surface = planar_patch({-2, 0.5, -2}, {4, 0, 0}, {0, 0, 4});
  const std::vector<glm::dvec2> diamond = {{0.5, 0.0}, {1.0, 0.5}, {0.5, 1.0}, {0.0, 0.5}};
  face.loops = {diamond};
  face.source_index = 5;
  scene.trimmed_faces.push_back(face);
  const Comparison c = compare_depth(
      scene,
      [&](const dvec3& o, const dvec3& d) -> std::optional<double> {
        if (const auto t = plane_y(o, d, 0.5)) {
          const dvec3 p = o + *t * d;
          // The patch's (u, v) is ((x + 2) / 4, (z + 2) / 4).
          if (inside_polygon(diamond, glm::dvec2((p.x + 2.0) / 4.0, (p.z + 2.0) / 4.0))) return t;
        }
        if (const auto t = plane_y(o, d, -0.5)) {
          const dvec3 p = o + *t * d;
          for (int k = 0; k < 5; ++k) {
            const double x0 = -3.0 + 1.2 * k;
            if (p.x >= x0 && p.x <= x0 + 1.0 && std::fabs(p.z) <= 2.0) return t;
          }
        }
        return std::nullopt;
      },
      1e-5, 3);  // rays within rounding of an edge may go either way
  EXPECT_GT(c.hits, 400);
}

TEST(PatchesRender, TrimmedCylinderBandAcrossTheSeam) {
  // A cylinder (axis +y, so u = atan2(-z, x) / 2 pi wrapped to [0, 1), v = y / height)
  // trimmed to u in [0.7, 1.25] (across the seam at +x; steps over half a turn need a
  // point between) and v in [0.1, 0.9].
  constexpr double kRadius = 1.0, kHeight = 1.5;
  SceneDescription scene = base_scene();
  CylinderDesc cylinder;
  cylinder.radius = kRadius;
  cylinder.height = kHeight;
  TrimmedFaceDesc face;
  face.surface = cylinder;
  face.loops = {{{0.7, 0.1}, {1.0, 0.1}, {0.25, 0.1}, {0.25, 0.9}, {0.0, 0.9}, {0.7, 0.9}}};
  scene.trimmed_faces.push_back(face);
  int inside_of_band = 0;
  const Comparison c = compare_depth(
      scene,
      [&](const dvec3& o, const dvec3& d) -> std::optional<double> {
        const double a = d.x * d.x + d.z * d.z;
        const double b = o.x * d.x + o.z * d.z;
        const double cc = o.x * o.x + o.z * o.z - kRadius * kRadius;
        const double disc = b * b - a * cc;
        if (a == 0.0 || disc < 0.0) return std::nullopt;
        const double q = -(b + std::copysign(std::sqrt(disc), b));
        double roots[2] = {q / a, cc / q};
        if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
        for (int k = 0; k < 2; ++k) {
          const dvec3 p = o + roots[k] * d;
          double u = std::atan2(-p.z, p.x) / (2.0 * 3.14159265358979);
          if (u < 0.0) u += 1.0;
          const double v = p.y / kHeight;
          if (roots[k] > 0.0 && (u >= 0.7 || u <= 0.25) && v >= 0.1 && v <= 0.9) {
            inside_of_band += k;  // the far crossing: seen through the open side
            return roots[k];
          }
        }
        return std::nullopt;
      },
      1e-4, 4);
  EXPECT_GT(c.hits, 60);
  EXPECT_GT(inside_of_band, 10);
}

TEST(PatchesRender, PatchesAndTrimmedFacesUseTheirOwnShapeBits) {
  SceneDescription scene = base_scene();
  scene.patches.push_back(planar_patch({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}));
  SceneFeatures f = SceneFeatures::of(scene);
  EXPECT_EQ(f.shapes, static_cast<unsigned>(kShapePatch));
  TrimmedFaceDesc face;
  face.loops = {{{0, 0.2}, {0.5, 0.2}, {0.5, 0.8}}};
  scene.trimmed_faces.push_back(face);
  f = SceneFeatures::of(scene);
  EXPECT_EQ(f.shapes, static_cast<unsigned>(kShapePatch | kShapeTrimmed));
  EXPECT_EQ(f.light_count, 0u);
}

TEST(PatchesRender, EmittingPatchIsCountedWhenHitAndHiddenOneOnlyOffCamera) {
  SceneDescription scene = base_scene();
  MaterialDesc lamp;
  lamp.name = "lamp";
  lamp.type = MaterialType::kLight;
  lamp.emission = {2.0, 2.0, 2.0};
  scene.materials.push_back(lamp);
  SplinePatchDesc p = planar_patch({-2, 0, -2}, {4, 0, 0}, {0, 0, 4});
  p.material = 1;
  scene.patches.push_back(p);
  scene.render.integrator = IntegratorKind::kPath;
  scene.render.samples_per_pixel = 2;
  const auto prepared = PreparedScene::build(scene);
  EXPECT_EQ(prepared->features().light_count, 0u);  // no sampler: counted when hit
  const std::vector<float> image = render_image(*prepared);
  // Hidden, it is left out of camera rays alone (other rays hit it, so even an emitter
  // without a light sampler may be hidden): its pixels are those of the scene without it.
  scene.patches[0].visible = false;
  EXPECT_TRUE(validate_scene(scene).empty());
  const std::vector<float> hidden = render_image(*PreparedScene::build(scene));
  scene.patches.clear();
  const std::vector<float> without = render_image(*PreparedScene::build(scene));
  // Every camera ray of a pixel whose four corners see the emitting square (so every
  // sample hits it) sees its emission directly.
  const Camera camera = Camera::from_description(scene.camera, kWidth, kHeight);
  const auto on_square = [&](float px, float py) {
    const Ray ray = camera.generate(px, py);
    const dvec3 o(ray.origin), d = glm::normalize(dvec3(ray.direction));
    const auto t = plane_y(o, d, 0.0);
    if (!t) return false;
    const dvec3 q = o + *t * d;
    return std::fabs(q.x) < 1.99 && std::fabs(q.z) < 1.99;
  };
  int lit = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      if (on_square(fx, fy) && on_square(fx + 1, fy) && on_square(fx, fy + 1) &&
          on_square(fx + 1, fy + 1)) {
        ++lit;
        const std::size_t red = (std::size_t{y} * kWidth + x) * 4;
        EXPECT_NEAR(image[red], 2.0f, 1e-5f) << x << ", " << y;
        EXPECT_NE(hidden[red], image[red]) << x << ", " << y;
        EXPECT_EQ(hidden[red], without[red]) << x << ", " << y;
      }
    }
  EXPECT_GT(lit, 200);
}

}  // namespace
}  // namespace tessera
