#include "bench_scenes.hpp"

#include <cmath>

namespace tessera::bench {

namespace {

MaterialDesc material(const std::string& name, MaterialType type, glm::dvec3 albedo,
                      double roughness = 0.0) {
  MaterialDesc m;
  m.name = name;
  m.type = type;
  m.albedo = albedo;
  m.roughness = roughness;
  return m;
}

MaterialDesc light(const std::string& name, double power) {
  MaterialDesc m = material(name, MaterialType::kLight, glm::dvec3(1.0));
  m.emission = glm::dvec3(power);
  return m;
}

// A UV sphere as triangles.
TriangleMeshDesc uv_sphere(glm::dvec3 center, double radius, int rings, int segments,
                           std::uint32_t material) {
  TriangleMeshDesc mesh;
  mesh.material = material;
  for (int r = 0; r <= rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2.0 * M_PI * s / segments;
      mesh.positions.push_back(center + radius * glm::dvec3(std::sin(theta) * std::cos(phi),
                                                            std::cos(theta),
                                                            std::sin(theta) * std::sin(phi)));
    }
  }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const auto a = static_cast<std::uint32_t>(r * (segments + 1) + s);
      const auto b = a + static_cast<std::uint32_t>(segments + 1);
      mesh.indices.insert(mesh.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  return mesh;
}

TriangleMeshDesc quad_mesh(glm::dvec3 corner, glm::dvec3 u, glm::dvec3 v, std::uint32_t material) {
  TriangleMeshDesc mesh;
  mesh.material = material;
  mesh.positions = {corner, corner + u, corner + u + v, corner + v};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

void frame(SceneDescription& s, std::uint32_t width, std::uint32_t height, std::uint32_t spp) {
  s.camera.position = {0, 1.5, 6};
  s.camera.look_at = {0, 0.6, 0};
  s.camera.fov_degrees = 45;
  s.render.width = width;
  s.render.height = height;
  s.render.samples_per_pixel = spp;
  s.render.max_depth = 6;
  s.render.tile_size = 16;
  s.render.seed = 3;
}

}  // namespace

std::vector<NamedScene> specialisation_scenes(std::uint32_t width, std::uint32_t height,
                                              std::uint32_t spp) {
  std::vector<NamedScene> scenes;

  {  // Diffuse meshes lit by an emissive triangle pair.
    SceneDescription s;
    frame(s, width, height, spp);
    s.materials = {material("clay", MaterialType::kLambertian, {0.7, 0.6, 0.5}),
                   material("floor", MaterialType::kLambertian, {0.5, 0.5, 0.5}),
                   light("lamp", 12)};
    for (int i = 0; i < 3; ++i)
      s.meshes.push_back(uv_sphere({-1.6 + 1.6 * i, 0.6, 0}, 0.6, 48, 96, 0));
    s.meshes.push_back(quad_mesh({-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 1));
    s.meshes.push_back(quad_mesh({-1, 4, -1}, {2, 0, 0}, {0, 0, 2}, 2));
    scenes.push_back({"triangles", s});
  }
  {  // RayON-style field of spheres: diffuse, metal and glass, with an area light.
    SceneDescription s;
    frame(s, width, height, spp);
    s.materials = {material("ground", MaterialType::kLambertian, {0.45, 0.45, 0.45}),
                   material("diffuse", MaterialType::kLambertian, {0.6, 0.7, 0.8}),
                   material("metal", MaterialType::kMetal, {0.9, 0.9, 0.9}, 0.05),
                   material("glass", MaterialType::kGlass, {1, 1, 1}), light("lamp", 10)};
    s.spheres.push_back(SphereDesc{{0, -1000, 0}, 1000, 0, true, 0});
    std::uint32_t index = 1;
    for (int x = -6; x <= 6; ++x)
      for (int z = -6; z <= 2; ++z)
        s.spheres.push_back(SphereDesc{{x * 0.8, 0.3, z * 0.8},
                                       0.3,
                                       1u + static_cast<std::uint32_t>((x + z + 12) % 3),
                                       true,
                                       index++});
    s.quads.push_back(QuadDesc{{-2, 5, -2}, {4, 0, 0}, {0, 0, 4}, 4, true, index++});
    scenes.push_back({"analytic", s});
  }
  {  // The Cornell box with a mesh inside: every shape type.
    SceneDescription s;
    frame(s, width, height, spp);
    s.camera.position = {0, 1.1, 5.2};
    s.camera.look_at = {0, 1.0, 0};
    s.camera.fov_degrees = 41;
    s.materials = {material("white", MaterialType::kLambertian, {0.75, 0.75, 0.75}),
                   material("red", MaterialType::kLambertian, {0.8, 0.15, 0.15}),
                   material("green", MaterialType::kLambertian, {0.18, 0.75, 0.22}),
                   material("mirror", MaterialType::kMetal, {0.9, 0.9, 0.9}, 0.02),
                   light("lamp", 16)};
    s.quads = {QuadDesc{{-1.5, 0, -1.5}, {3, 0, 0}, {0, 0, 3}, 0, true, 0},
               QuadDesc{{-1.5, 2.2, -1.5}, {3, 0, 0}, {0, 0, 3}, 0, true, 1},
               QuadDesc{{-1.5, 0, -1.5}, {3, 0, 0}, {0, 2.2, 0}, 0, true, 2},
               QuadDesc{{-1.5, 0, -1.5}, {0, 0, 3}, {0, 2.2, 0}, 1, true, 3},
               QuadDesc{{1.5, 0, -1.5}, {0, 0, 3}, {0, 2.2, 0}, 2, true, 4},
               QuadDesc{{-0.45, 2.19, -0.45}, {0.9, 0, 0}, {0, 0, 0.9}, 4, true, 5}};
    s.spheres.push_back(SphereDesc{{-0.5, 0.45, -0.4}, 0.45, 3, true, 6});
    s.meshes.push_back(uv_sphere({0.55, 0.4, 0.35}, 0.4, 32, 64, 0));
    scenes.push_back({"mixed", s});
  }
  {  // Diffuse meshes under a sky, their only light (an environment light, sampled).
    SceneDescription s = scenes.front().scene;
    s.meshes.pop_back();
    s.materials.pop_back();
    s.background.color = {0.6, 0.7, 0.9};
    scenes.push_back({"triangles_sky", s});
  }
  return scenes;
}

}  // namespace tessera::bench
