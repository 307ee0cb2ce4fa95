// Two-level instancing against baking: K placements of one mesh file (suzanne by default),
// prepared once with shared geometry and once with every placement baked into world
// triangles. Prints build time and triangle storage of each, and the time to render a
// small image on one thread. Skips (exit 0) when the mesh file is absent.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/mesh_loader.hpp"

namespace tessera {
namespace {

struct Options {
  std::string mesh = "../shared/meshes/suzanne-sub4.ply";
  int placements = 16;
  std::uint32_t width = 128, height = 96, spp = 4;
  int repeats = 3;
};

SceneDescription grid_scene(const TriangleMeshDesc& mesh, const Options& o) {
  SceneDescription scene;
  MaterialDesc white;
  white.name = "white";
  scene.materials.push_back(white);
  MaterialDesc light;
  light.name = "light";
  light.type = MaterialType::kLight;
  light.emission = {3.0, 3.0, 3.0};
  scene.materials.push_back(light);
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(o.placements))));
  for (int i = 0; i < o.placements; ++i) {
    TriangleMeshDesc placed = mesh;
    TransformDesc t;
    t.translate = {2.5 * (i % side - 0.5 * (side - 1)), 0.0, -2.5 * (i / side)};
    t.rotate_axis = {0.0, 1.0, 0.0};
    t.rotate_degrees = 17.0 * i;
    t.scale = glm::dvec3(0.8 + 0.05 * (i % 5));
    placed.transform = t;
    placed.source_index = static_cast<std::uint32_t>(i);
    scene.meshes.push_back(std::move(placed));
  }
  QuadDesc lamp;
  lamp.corner = {-3.0, 6.0, -3.0};
  lamp.u = {6.0, 0.0, 0.0};
  lamp.v = {0.0, 0.0, 6.0};
  lamp.material = 1;
  scene.quads.push_back(lamp);
  scene.camera.position = {0.0, 3.0 + 0.6 * side, 5.0};
  scene.camera.look_at = {0.0, 0.0, -1.25 * (side - 1)};
  scene.camera.fov_degrees = 55.0;
  scene.render.width = o.width;
  scene.render.height = o.height;
  scene.render.samples_per_pixel = o.spp;
  scene.render.integrator = IntegratorKind::kPath;
  scene.render.seed = 1;
  return scene;
}

std::size_t image_pixels(const Options& o) {
  return static_cast<std::size_t>(o.width) * o.height;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run(const Options& o) {
  if (!std::filesystem::exists(o.mesh)) {
    std::printf("skipped: %s not found\n", o.mesh.c_str());
    return 0;
  }
  spdlog::set_level(spdlog::level::warn);
  const TriangleMeshDesc mesh = load_mesh_file(o.mesh);
  const SceneDescription scene = grid_scene(mesh, o);
  std::printf("%d placements of %s (%zu triangles each), %ux%u path %u spp, one thread\n",
              o.placements, o.mesh.c_str(), mesh.indices.size() / 3, o.width, o.height, o.spp);
  std::printf("%-9s %10s %12s %10s %11s %10s %10s\n", "mode", "build s", "triangle MB", "render s",
              "placements", "covered", "mean");
  for (const bool instancing : {true, false}) {
    PrepareOptions options;
    options.instancing = instancing;
    double best_build = 1e30, best_render = 1e30;
    std::size_t bytes = 0, shared = 0, covered = 0;
    double mean = 0.0;  // the two modes must render the same image
    for (int r = 0; r < o.repeats; ++r) {
      auto start = std::chrono::steady_clock::now();
      const auto prepared = PreparedScene::build(scene, options);
      best_build = std::min(best_build, seconds_since(start));
      bytes = prepared->triangle_bytes();
      shared = prepared->shared_mesh_placements();
      start = std::chrono::steady_clock::now();
      const std::vector<float> image = render_image(*prepared);
      best_render = std::min(best_render, seconds_since(start));
      covered = 0;
      mean = 0.0;
      for (std::size_t p = 0; p < image.size(); p += 4) {
        covered += image[p] + image[p + 1] + image[p + 2] > 0.0f ? 1 : 0;
        mean += (image[p] + image[p + 1] + image[p + 2]) / 3.0;
      }
      mean /= static_cast<double>(image.size() / 4);
    }
    std::printf("%-9s %10.3f %12.1f %10.3f %11zu %9.1f%% %10.5f\n",
                instancing ? "instanced" : "baked", best_build,
                static_cast<double>(bytes) / (1024.0 * 1024.0), best_render, shared,
                100.0 * static_cast<double>(covered) / static_cast<double>(image_pixels(o)), mean);
  }
  return 0;
}

}  // namespace
}  // namespace tessera

int main(int argc, char** argv) {
  CLI::App app{"Shared mesh geometry (two-level) vs baked placements: build, memory, render"};
  tessera::Options o;
  app.add_option("--mesh", o.mesh, "mesh file placed K times (skipped when absent)");
  app.add_option("--placements", o.placements, "K")->check(CLI::Range(2, 4096));
  app.add_option("--width", o.width, "image width")->check(CLI::Range(8u, 4096u));
  app.add_option("--height", o.height, "image height")->check(CLI::Range(8u, 4096u));
  app.add_option("--spp", o.spp, "samples per pixel")->check(CLI::Range(1u, 1024u));
  app.add_option("--repeats", o.repeats, "timed runs; the best counts")->check(CLI::Range(1, 20));
  CLI11_PARSE(app, argc, argv);
  return tessera::run(o);
}
