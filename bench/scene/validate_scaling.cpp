// How YAML loading, protobuf conversion and validate_scene scale with the number of
// materials and of shapes referring to them. Each size doubles or decuples the last, so a
// quadratic step shows as a time ratio near the size ratio squared.
//
//   tessera-bench-validate --sizes 6000 60000 [--repeat 3]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// `count` materials with distinct names and one sphere per material, each referring to it.
std::string scene_yaml(std::size_t count) {
  std::ostringstream out;
  out << "materials:\n";
  for (std::size_t i = 0; i < count; ++i)
    out << "  - { name: m" << i << ", type: lambertian, albedo: [0.5, 0.5, 0.5] }\n";
  out << "geometry:\n";
  for (std::size_t i = 0; i < count; ++i)
    out << "  - { type: sphere, material: m" << i << ", center: [" << i
        << ", 0, 0], radius: 0.4 }\n";
  return out.str();
}

template <typename Fn>
double best_of(int repeat, Fn&& fn) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto start = Clock::now();
    fn();
    best = std::min(best, seconds_since(start));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Scene validation cost against scene size", "tessera-bench-validate");
  std::vector<std::size_t> sizes{600, 6000, 60000};
  int repeat = 3;
  app.add_option("--sizes", sizes, "material (and sphere) counts");
  app.add_option("--repeat", repeat, "runs per size; the best is printed")
      ->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);

  std::printf("%10s %14s %14s %14s %14s\n", "materials", "yaml load s", "validate s",
              "proto->scene s", "proto bytes");
  for (std::size_t n : sizes) {
    const std::string text = scene_yaml(n);
    tessera::SceneDescription scene;
    const double load =
        best_of(repeat, [&] { scene = tessera::load_scene_yaml(text, "bench.yaml", ".").scene; });
    const double validate = best_of(repeat, [&] {
      if (!tessera::validate_scene(scene).empty()) std::abort();
    });
    const tessera::v1::Scene proto = tessera::scene_to_proto(scene);
    const tessera::v1::RenderSettings settings = tessera::settings_to_proto(scene.render);
    const double convert = best_of(repeat, [&] {
      if (!tessera::scene_from_proto(proto, settings).ok()) std::abort();
    });
    std::printf("%10zu %14.4f %14.4f %14.4f %14zu\n", n, load, validate, convert,
                proto.ByteSizeLong());
  }
  return 0;
}
