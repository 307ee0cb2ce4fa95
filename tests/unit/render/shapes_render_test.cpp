// The renderer draws every shape type end to end (description -> flat arrays -> BVH or
// plane list -> dispatch -> integrator). Each image is compared pixel by pixel with an
// independent answer for the same camera rays: the geometry module's intersector called
// directly, an analytic formula, or the same geometry placed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

#include "first_hit_scene.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {
namespace {

constexpr std::uint32_t kWidth = 40;
constexpr std::uint32_t kHeight = 30;

SceneDescription base_scene(IntegratorKind integrator = IntegratorKind::kDepth) {
  CameraDesc camera;
  camera.position = {0.3, 2.0, 6.0};
  camera.look_at = {0.0, 0.5, 0.0};
  camera.fov_degrees = 45.0;
  return test::first_hit_scene(camera, kWidth, kHeight, integrator, 11);
}

Ray camera_ray(const SceneDescription& scene, std::uint32_t x, std::uint32_t y) {
  return test::first_sample_camera_ray(scene, x, y);
}

using DepthReference = std::function<std::optional<double>(const Ray&)>;

// Renders `scene` with the depth integrator and checks every pixel against `reference`
// (distance along the unit camera ray, nullopt for a miss). Returns the pixels hit.
int expect_depth_matches(const SceneDescription& scene, const DepthReference& reference,
                         double relative_tolerance = 1e-5, int allowed_mismatches = 0) {
  const auto prepared = PreparedScene::build(scene);
  EXPECT_TRUE(prepared->variant().features.covers(prepared->required_features()));
  const std::vector<float> image = render_image(*prepared);
  int hits = 0, mismatches = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const Ray ray = camera_ray(scene, x, y);
      const std::optional<double> expected = reference(ray);
      const float depth = image[(y * kWidth + x) * 4];
      if (expected) ++hits;
      const bool ok = expected
                          ? std::fabs(depth - *expected) <= relative_tolerance * *expected + 1e-6
                          : depth == 0.0f;
      if (!ok && ++mismatches > allowed_mismatches)
        ADD_FAILURE() << "pixel (" << x << ", " << y << "): rendered " << depth << ", expected "
                      << (expected ? std::to_string(*expected) : std::string("a miss"));
    }
  return hits;
}

// The geometry module's own intersector on the float camera ray (direction has unit length).
template <typename Shape>
DepthReference core_reference(const Shape& shape) {
  return [shape](const Ray& ray) -> std::optional<double> {
    HitRecord hit;
    if (!intersect(shape, make_precise_ray(ray), kInfinity, hit, 0)) return std::nullopt;
    return static_cast<double>(hit.t) * glm::length(dvec3(ray.direction));
  };
}
template <typename Shape>
DepthReference instance_reference(const Shape& shape, const TransformDesc& transform) {
  const glm::dmat4 m = transform.matrix();
  Instance<Shape> instance;
  EXPECT_TRUE(
      Instance<Shape>::make(shape, AffineTransform{glm::dmat3(m), glm::dvec3(m[3])}, instance));
  return [instance](const Ray& ray) -> std::optional<double> {
    HitRecord hit;
    if (!intersect(instance, ray, kInfinity, hit, 0)) return std::nullopt;
    return static_cast<double>(hit.t) * glm::length(dvec3(ray.direction));
  };
}

TEST(ShapesRender, PlaneMatchesTheAnalyticDistance) {
  SceneDescription scene = base_scene();
  scene.planes.push_back(PlaneDesc{{0, -0.5, 0}, {0.2, 1, 0.1}, 0, true, 0});
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, 1, 0.1));
  const int hits = expect_depth_matches(scene, [&](const Ray& ray) -> std::optional<double> {
    const glm::dvec3 o(ray.origin), d(ray.direction);
    const double t = glm::dot(glm::dvec3(0, -0.5, 0) - o, n) / glm::dot(d, n);
    if (!(t > 0.0)) return std::nullopt;
    return t;
  });
  EXPECT_GT(hits, 100);
  EXPECT_LT(hits, static_cast<int>(kWidth * kHeight));  // the horizon is in view
  EXPECT_TRUE((PreparedScene::build(scene)->features().shapes & kShapePlane) != 0);
}

TEST(ShapesRender, AnnulusMatchesTheAnalyticDistance) {
  SceneDescription scene = base_scene();
  scene.disks.push_back(DiskDesc{{0, 0.2, 0}, {0, 1, 0.3}, 1.5, 0.6, 0, true, 0});
  const glm::dvec3 n = glm::normalize(glm::dvec3(0, 1, 0.3));
  const int hits = expect_depth_matches(scene, [&](const Ray& ray) -> std::optional<double> {
    const glm::dvec3 o(ray.origin), d(ray.direction), c(0, 0.2, 0);
    const double t = glm::dot(c - o, n) / glm::dot(d, n);
    if (!(t > 0.0)) return std::nullopt;
    const double rho = glm::length(o + t * d - c);
    if (rho > 1.5 || rho < 0.6) return std::nullopt;
    return t;
  });
  EXPECT_GT(hits, 50);
}

TEST(ShapesRender, CylinderConeAndTorusMatchTheCoreIntersectors) {
  {
    SceneDescription scene = base_scene();
    scene.cylinders.push_back(CylinderDesc{{0, 0, 0}, {0.3, 1, 0}, 0.7, 1.2, true, 0, true, 0});
    EXPECT_GT(
        expect_depth_matches(scene, core_reference(Cylinder::make(vec3(0, 0, 0), vec3(0.3, 1, 0),
                                                                  0.7f, 1.2f, true, 0))),
        50);
  }
  {
    SceneDescription scene = base_scene();
    scene.cones.push_back(ConeDesc{{0, -0.5, 0}, {0, 1, 0}, 1.0, 0.3, 1.5, false, 0, true, 0});
    EXPECT_GT(expect_depth_matches(scene, core_reference(Cone::make(vec3(0, -0.5, 0), vec3(0, 1, 0),
                                                                    1.0f, 0.3f, 1.5f, false, 0))),
              50);
  }
  {
    SceneDescription scene = base_scene();
    scene.tori.push_back(TorusDesc{{0, 0.5, 0}, {0, 1, 0.5}, 1.2, 0.35, 0, true, 0});
    EXPECT_GT(expect_depth_matches(scene, core_reference(Torus::make(
                                              vec3(0, 0.5, 0), vec3(0, 1, 0.5), 1.2f, 0.35f, 0))),
              50);
  }
}

TEST(ShapesRender, SignedDistanceShapesMatchTheSphereTracer) {
  {
    SceneDescription scene = base_scene();
    scene.sdf_boxes.push_back(SdfBoxDesc{{0, 0.5, 0}, {1, 0.5, 0.7}, 0.0, 0, true, 0});
    EXPECT_GT(expect_depth_matches(
                  scene, core_reference(SdfBox{vec3(0, 0.5, 0), vec3(1, 0.5, 0.7), 0.0f, 0})),
              50);
  }
  {
    SceneDescription scene = base_scene();
    scene.sdf_boxes.push_back(SdfBoxDesc{{0, 0.5, 0}, {1, 0.5, 0.7}, 0.3, 0, true, 0});
    EXPECT_GT(expect_depth_matches(
                  scene, core_reference(SdfBox{vec3(0, 0.5, 0), vec3(1, 0.5, 0.7), 0.3f, 0})),
              50);
  }
  {
    SceneDescription scene = base_scene();
    scene.sdf_tori.push_back(SdfTorusDesc{{0, 0.5, 0}, {0, 1, 0}, 1.2, 0.4, 0, true, 0});
    EXPECT_GT(expect_depth_matches(
                  scene, core_reference(SdfTorus{vec3(0, 0.5, 0), vec3(0, 1, 0), 1.2f, 0.4f, 0})),
              50);
  }
  {
    SceneDescription scene = base_scene();
    scene.sdf_capsules.push_back(SdfCapsuleDesc{{-1, 0, 0}, {1, 1, 0}, 0.4, 0, true, 0});
    EXPECT_GT(expect_depth_matches(
                  scene, core_reference(SdfCapsule{vec3(-1, 0, 0), vec3(1, 1, 0), 0.4f, 0})),
              50);
  }
}

// Rotation + uniform scale is baked into a cylinder; the reference is the unbaked
// cylinder placed by an Instance, a different code path.
TEST(ShapesRender, BakedSimilarityEqualsTheInstancedShape) {
  SceneDescription scene = base_scene();
  const TransformDesc transform{{0.2, 0.1, 0}, {1, 0, 1}, 50.0, glm::dvec3(1.3)};
  scene.cylinders.push_back(
      CylinderDesc{{0, 0, 0}, {0, 1, 0}, 0.5, 1.0, true, 0, true, 0, transform});
  scene.tori.push_back(TorusDesc{{1.5, 0, 0}, {0, 1, 0}, 0.5, 0.2, 0, true, 1, transform});
  EXPECT_EQ(PreparedScene::build(scene)->features().shapes & kShapeInstance, 0u);
  const auto cylinder = instance_reference(
      Cylinder::make(vec3(0, 0, 0), vec3(0, 1, 0), 0.5f, 1.0f, true, 0), transform);
  const auto torus =
      instance_reference(Torus::make(vec3(1.5, 0, 0), vec3(0, 1, 0), 0.5f, 0.2f, 0), transform);
  // A mirroring uniform scale (negative) still bakes: lengths scale by |s|, the axis flips.
  const TransformDesc mirror{{-1.5, 0.5, 0}, {0, 0, 1}, 30.0, glm::dvec3(-0.8)};
  scene.cones.push_back(ConeDesc{{0, 0, 0}, {0, 1, 0}, 0.6, 0.1, 1.0, true, 0, true, 2, mirror});
  const auto cone = instance_reference(
      Cone::make(vec3(0, 0, 0), vec3(0, 1, 0), 0.6f, 0.1f, 1.0f, true, 0), mirror);
  const int hits = expect_depth_matches(
      scene,
      [&](const Ray& ray) -> std::optional<double> {
        std::optional<double> nearest;
        for (const auto& candidate : {cylinder(ray), torus(ray), cone(ray)})
          if (candidate && (!nearest || *candidate < *nearest)) nearest = candidate;
        return nearest;
      },
      1e-4, 3);
  EXPECT_GT(hits, 80);
}

// Non-uniform scale turns a sphere into an ellipsoid, which only an Instance can draw; the
// reference solves the ellipsoid's quadratic in double.
TEST(ShapesRender, NonUniformlyScaledSphereIsTheAnalyticEllipsoid) {
  SceneDescription scene = base_scene(IntegratorKind::kNormals);
  const glm::dvec3 radii(2.0, 0.6, 1.0);
  scene.spheres.push_back(
      SphereDesc{{0, 0, 0}, 1.0, 0, true, 0, TransformDesc{{0, 0.5, 0}, {0, 0, 1}, 0.0, radii}});
  const auto prepared = PreparedScene::build(scene);
  EXPECT_NE(prepared->features().shapes & kShapeInstance, 0u);
  const std::vector<float> normals = render_image(*prepared);
  scene.render.integrator = IntegratorKind::kDepth;
  int checked = 0;
  const int hits = expect_depth_matches(
      scene,
      [&](const Ray& ray) -> std::optional<double> {
        const glm::dvec3 o = (glm::dvec3(ray.origin) - glm::dvec3(0, 0.5, 0)) / radii;
        const glm::dvec3 d = glm::dvec3(ray.direction) / radii;
        const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
        const double disc = b * b - a * c;
        if (disc < 0.0) return std::nullopt;
        const double t = (-b - std::sqrt(disc)) / a;
        if (!(t > 0.0)) return std::nullopt;
        return t;
      },
      1e-4, 2);
  EXPECT_GT(hits, 100);
  // Shading normals: the gradient of the implicit function (x/a)^2 + ... at the hit.
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const Ray ray = camera_ray(scene, x, y);
      const glm::dvec3 o(ray.origin), dir(ray.direction);
      const glm::dvec3 lo = (o - glm::dvec3(0, 0.5, 0)) / radii, ld = dir / radii;
      const double a = glm::dot(ld, ld), b = glm::dot(lo, ld), c = glm::dot(lo, lo) - 1.0;
      const double disc = b * b - a * c;
      if (disc < 1e-3 * a) continue;  // skip silhouettes
      const double t = (-b - std::sqrt(disc)) / a;
      const glm::dvec3 p = o + t * dir - glm::dvec3(0, 0.5, 0);
      const glm::dvec3 n = glm::normalize(p / (radii * radii));
      const float* pixel = &normals[(y * kWidth + x) * 4];
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(pixel[k], 0.5 * n[k] + 0.5, 2e-3);
      ++checked;
    }
  EXPECT_GT(checked, 100);
}

// A rotated signed-distance capsule (an Instance) equals the capsule whose endpoints were
// rotated by hand.
TEST(ShapesRender, TransformedDistanceFieldEqualsTheShapePlacedByHand) {
  SceneDescription scene = base_scene();
  const TransformDesc transform{{0.5, 0.2, 0}, {0, 0, 1}, 90.0, glm::dvec3(1.0)};
  scene.sdf_capsules.push_back(SdfCapsuleDesc{{0, 0, 0}, {1, 0, 0}, 0.4, 0, true, 0, transform});
  // Rotating (1, 0, 0) by 90 degrees about z gives (0, 1, 0); then translate.
  const SdfCapsule by_hand{vec3(0.5, 0.2, 0), vec3(0.5, 1.2, 0), 0.4f, 0};
  EXPECT_GT(expect_depth_matches(scene, core_reference(by_hand), 1e-4, 2), 30);
}

// A mesh transform is baked into the vertices; the same triangle written pre-transformed
// renders the same image.
TEST(ShapesRender, TransformedMeshEqualsTheMeshPlacedByHand) {
  SceneDescription moved = base_scene();
  TriangleMeshDesc mesh;
  mesh.positions = {{-1, 0, 0}, {1, 0, 0}, {0, 1.5, 0}};
  mesh.indices = {0, 1, 2};
  mesh.transform = TransformDesc{{0, 0.2, 0.5}, {0, 1, 0}, 30.0, {1.5, 1.0, 1.0}};
  moved.meshes.push_back(mesh);
  SceneDescription by_hand = base_scene();
  TriangleMeshDesc placed = mesh;
  placed.transform.reset();
  const glm::dmat4 m = mesh.transform->matrix();
  for (auto& p : placed.positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  by_hand.meshes.push_back(placed);
  const auto a = render_image(*PreparedScene::build(moved));
  const auto b = render_image(*PreparedScene::build(by_hand));
  ASSERT_EQ(a.size(), b.size());
  int covered = 0;
  for (std::size_t i = 0; i < a.size(); i += 4) {
    EXPECT_NEAR(a[i], b[i], 1e-5 * b[i]) << "pixel " << i / 4;
    covered += b[i] > 0.0f;
  }
  EXPECT_GT(covered, 50);
}

// Per-vertex normals shade meshes (normals integrator): each pixel shows the normal
// interpolated at its hit, here of a mesh scaled non-uniformly, whose normals must have
// followed the inverse transpose. The reference interpolates in double from the hit point.
TEST(ShapesRender, MeshNormalsAreInterpolatedAfterTheirTransform) {
  SceneDescription scene = base_scene(IntegratorKind::kNormals);
  scene.camera.position = {0, 0, 4};
  scene.camera.look_at = {0, 0, 0};
  TriangleMeshDesc mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.normals = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.transform = TransformDesc{{0, 0, 0}, {0, 0, 1}, 0.0, {1.5, 0.8, 1.0}};
  scene.meshes.push_back(mesh);
  const auto image = render_image(*PreparedScene::build(scene));
  const glm::dvec3 scale(1.5, 0.8, 1.0);
  glm::dvec3 p[3], n[3];
  for (int k = 0; k < 3; ++k) {
    p[k] = mesh.positions[k] * scale;
    n[k] = glm::normalize(mesh.normals[k] / scale);  // inverse transpose of a diagonal map
  }
  int checked = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const Ray ray = camera_ray(scene, x, y);
      const glm::dvec3 o(ray.origin), d(ray.direction);
      const glm::dvec3 q = o + (-o.z / d.z) * d;
      // Barycentrics of q in the (planar, z = 0) triangle.
      const double area =
          (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
      const double b1 =
          ((q.x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (q.y - p[0].y)) / area;
      const double b2 =
          ((p[1].x - p[0].x) * (q.y - p[0].y) - (q.x - p[0].x) * (p[1].y - p[0].y)) / area;
      const double b0 = 1.0 - b1 - b2;
      const float* pixel = &image[(y * kWidth + x) * 4];
      if (std::min(b0, std::min(b1, b2)) < -1e-3) {
        EXPECT_EQ(pixel[0] + pixel[1] + pixel[2], 0.0f) << x << ", " << y;
        continue;
      }
      if (std::min(b0, std::min(b1, b2)) < 1e-3) continue;  // on an edge
      const glm::dvec3 expected = glm::normalize(b0 * n[0] + b1 * n[1] + b2 * n[2]);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(pixel[k], 0.5 * expected[k] + 0.5, 1e-4);
      ++checked;
    }
  EXPECT_GT(checked, 100);
}

TEST(ShapesRender, SceneWithEveryShapeUsesTheAllVariant) {
  SceneDescription scene = base_scene(IntegratorKind::kPath);
  scene.planes.push_back(PlaneDesc{{0, -1, 0}, {0, 1, 0}, 0, true, 0});
  scene.sdf_boxes.push_back(SdfBoxDesc{{0, 0, 0}, {0.5, 0.5, 0.5}, 0.0, 0, true, 1});
  const auto prepared = PreparedScene::build(scene);
  EXPECT_EQ(prepared->variant().features.shapes, kAllShapes);
  SceneDescription analytic = base_scene(IntegratorKind::kPath);
  analytic.spheres.push_back(SphereDesc{
      {0, 0, 0}, 1.0, 0, true, 0, TransformDesc{{1, 0, 0}, {0, 1, 0}, 20.0, glm::dvec3(2)}});
  EXPECT_EQ(PreparedScene::build(analytic)->variant().features.shapes, kShapeSphere | kShapeQuad);
}

// Planes live outside the BVH; shadow rays must still find them. A floor lit by a hidden
// lamp, then a plane between them: the floor goes dark (shadow and path integrators).
TEST(ShapesRender, PlaneOutsideTheBvhOccludesShadowRays) {
  for (IntegratorKind integrator : {IntegratorKind::kShadow, IntegratorKind::kPath}) {
    SceneDescription scene = base_scene(integrator);
    scene.render.width = kWidth;
    scene.camera.position = {0, 1, 0.001};
    scene.camera.look_at = {0, 0, 0};
    scene.camera.fov_degrees = 20.0;
    scene.render.max_depth = 2;
    MaterialDesc lamp;
    lamp.name = "lamp";
    lamp.type = MaterialType::kLight;
    lamp.emission = glm::dvec3(10.0);
    scene.materials.push_back(lamp);
    scene.quads.push_back(QuadDesc{{-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 0, true, 0});
    scene.quads.push_back(QuadDesc{{-0.2, 4, -0.2}, {0.4, 0, 0}, {0, 0, 0.4}, 1, false, 1});
    const auto lit = render_image(*PreparedScene::build(scene));
    double lit_sum = 0.0;
    for (std::size_t i = 0; i < lit.size(); i += 4) lit_sum += lit[i];
    EXPECT_GT(lit_sum, 0.0) << to_string(integrator);
    // Above the camera, facing it from behind: camera rays looking down never reach it.
    scene.planes.push_back(PlaneDesc{{0, 2, 0}, {0, 1, 0}, 0, true, 2});
    const auto shadowed = render_image(*PreparedScene::build(scene));
    for (std::size_t i = 0; i < shadowed.size(); i += 4)
      ASSERT_EQ(shadowed[i], 0.0f) << to_string(integrator) << " pixel " << i / 4;
  }
}

// Transparency composites every hit, planes included: a half-transparent plane in front of
// an opaque one gives a mix of both albedos, not only the nearer.
TEST(ShapesRender, TransparencySeesPlanesOutsideTheBvh) {
  SceneDescription scene = base_scene(IntegratorKind::kTransparency);
  scene.camera.position = {0, 0, 5};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.fov_degrees = 5.0;
  MaterialDesc veil;
  veil.name = "veil";
  veil.albedo = {1, 0, 0};
  veil.transmission = 0.5;
  scene.materials.push_back(veil);
  scene.materials[0].albedo = {0, 0, 1};
  scene.planes.push_back(PlaneDesc{{0, 0, -1}, {0, 0, 1}, 0, true, 0});
  scene.planes.push_back(PlaneDesc{{0, 0, 1}, {0, 0, 1}, 1, true, 1});
  const auto image = render_image(*PreparedScene::build(scene));
  const float* centre = &image[(kHeight / 2 * kWidth + kWidth / 2) * 4];
  EXPECT_GT(centre[0], 0.1f);  // the veil
  EXPECT_GT(centre[2], 0.1f);  // the wall behind it
}

// A ray through a torus's hole along its equator crosses the surface four times; each
// crossing of a half-opaque torus halves what is left of the background (blue here).
TEST(ShapesRender, TransparencyCompositesAllFourTorusCrossings) {
  SceneDescription scene = base_scene(IntegratorKind::kTransparency);
  scene.camera.position = {5, 0, 0};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.fov_degrees = 1.0;
  scene.background.color = {0, 0, 1};
  scene.materials[0].albedo = {1, 0, 0};
  scene.materials[0].transmission = 0.5;
  scene.tori.push_back(TorusDesc{{0, 0, 0}, {0, 1, 0}, 1.0, 0.3, 0, true, 0});
  const auto image = render_image(*PreparedScene::build(scene));
  for (std::size_t i = 0; i < image.size(); i += 4) ASSERT_NEAR(image[i + 2], 0.0625f, 1e-6f);
}

// Irradiance at the centre of a floor under emitters, seen through a narrow camera straight
// down: L = albedo / pi * E. An emitting disk is sampled by next-event estimation; a
// signed-distance sphere (a capsule of zero length, which has no light sampler) is counted
// when a bounced ray hits it. Both together must add up: nothing missed, nothing twice.
TEST(ShapesRender, EmittersWithAndWithoutSamplersAreEachCountedOnce) {
  const double albedo = 0.5, emission = 2.0;
  const auto floor_radiance = [&](bool disk, bool sdf_sphere, bool instanced_sphere) {
    SceneDescription scene = base_scene(IntegratorKind::kPath);
    scene.camera.position = {0, 0.5, 0};
    scene.camera.look_at = {0, 0, 0};
    scene.camera.up = {0, 0, 1};
    scene.camera.fov_degrees = 2.0;
    scene.render.width = 16;
    scene.render.height = 16;
    scene.render.samples_per_pixel = 128;
    scene.render.max_depth = 4;
    scene.materials[0].albedo = glm::dvec3(albedo);
    MaterialDesc lamp;
    lamp.name = "lamp";
    lamp.type = MaterialType::kLight;
    lamp.emission = glm::dvec3(emission);
    scene.materials.push_back(lamp);
    scene.planes.push_back(PlaneDesc{{0, 0, 0}, {0, 1, 0}, 0, true, 0});
    // Disk of radius 0.5 at height 1 straight above: E = pi Le R^2 / (h^2 + R^2). It fills
    // the directions up to 26.6 degrees from the normal.
    if (disk) scene.disks.push_back(DiskDesc{{0, 1, 0}, {0, -1, 0}, 0.5, 0.0, 1, true, 1});
    // Sphere of radius 1 at distance 2.5, 53.1 degrees from the normal (it fills 29.5 to
    // 76.7 degrees, so the two never shadow each other): E = pi Le (R / d)^2 cos(theta).
    if (sdf_sphere)
      scene.sdf_capsules.push_back(SdfCapsuleDesc{{2, 1.5, 0}, {2, 1.5, 0}, 1.0, 1, true, 2});
    // The same sphere as an Instance (non-uniform scale, off by 1e-4): no sampler either.
    if (instanced_sphere)
      scene.spheres.push_back(SphereDesc{
          {0, 0, 0}, 1.0, 1, true, 3, TransformDesc{{2, 1.5, 0}, {0, 0, 1}, 0.0, {1, 1, 1.0001}}});
    const auto image = render_image(*PreparedScene::build(scene));
    double sum = 0.0;
    for (std::size_t i = 0; i < image.size(); i += 4) sum += image[i];
    return sum / (image.size() / 4);
  };
  const double disk_expected = albedo * emission * 0.25 / 1.25;
  const double sphere_expected = albedo * emission * (1.0 / 6.25) * 0.6;
  const double disk_only = floor_radiance(true, false, false);
  const double sphere_only = floor_radiance(false, true, false);
  const double instanced_only = floor_radiance(false, false, true);
  const double both = floor_radiance(true, true, false);
  EXPECT_NEAR(disk_only, disk_expected, 0.02 * disk_expected);
  EXPECT_NEAR(sphere_only, sphere_expected, 0.06 * sphere_expected);
  EXPECT_NEAR(instanced_only, sphere_expected, 0.06 * sphere_expected);
  EXPECT_NEAR(both, disk_expected + sphere_expected, 0.03 * (disk_expected + sphere_expected));
}

}  // namespace
}  // namespace tessera
