// Micro-benchmarks of choosing the light to sample at a shading point (pick_light) and of the
// probability MIS asks for afterwards (light_pick_pmf), over scenes of many emitters: by the
// light tree, and by power alone (the alias table, what a scene without a tree uses).
//
// Two emitter layouts at several counts: `grid`, a square grid of small triangles under the
// ceiling of a 3 x 2.2 x 3 m room (converge suite's emissive_triangles at 32 x 32), picked from
// points on its floor and walls; `scatter`, triangles of uneven power in a slab over a floor
// (the light tree tests' layout), picked from points on the floor. Each benchmark cycles
// through 4,096 precomputed points and 65,536 uniform numbers, so branch prediction cannot
// learn one pick.
//
// `Independent` picks do not wait for each other (throughput); `Chained` picks take their u
// from the previous pick's result, so each waits for the one before (latency, what a path
// vertex pays, since its light sample needs the pick).
//   tessera-bench-light-pick [--benchmark_filter=REGEX]
#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "tessera/render/light_sampling.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace {

using namespace tessera;

struct Probe {
  vec3 p, n;
};

struct Setup {
  std::shared_ptr<const PreparedScene> prepared;
  SceneView view;
  std::vector<Probe> probes;  // 4,096
  std::vector<float> u;       // 65,536
};

MaterialDesc named(const std::string& name, MaterialType type, glm::dvec3 colour) {
  MaterialDesc m;
  m.name = name;
  m.type = type;
  if (type == MaterialType::kLight)
    m.emission = colour;
  else
    m.albedo = colour;
  return m;
}

void add_triangle(TriangleMeshDesc& mesh, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c});
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
}

// `side` x `side` triangles under the ceiling, probes on the floor and three walls.
SceneDescription grid_scene(int side, std::vector<Probe>& probes) {
  SceneDescription scene;
  scene.materials = {named("white", MaterialType::kLambertian, glm::dvec3(0.75)),
                     named("glow", MaterialType::kLight, glm::dvec3(12.0, 11.0, 9.0))};
  scene.quads.push_back(QuadDesc{.corner = {-1.5, 0, -1.5}, .u = {3, 0, 0}, .v = {0, 0, 3}});
  scene.quads.push_back(QuadDesc{.corner = {-1.5, 2.2, -1.5}, .u = {3, 0, 0}, .v = {0, 0, 3}});
  TriangleMeshDesc mesh;
  mesh.material = 1;
  const double size = 2.4, cell = size / side, extent = 0.6 * cell;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const double x = -size / 2 + (i + 0.2) * cell, z = -size / 2 + (j + 0.2) * cell;
      add_triangle(mesh, {x, 2.15, z}, {x + extent, 2.15, z}, {x, 2.15, z + extent});
    }
  scene.meshes.push_back(mesh);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 4096; ++i) {
    const float a = u(rng), b = u(rng);
    switch (i % 4) {
      case 0:
        probes.push_back({vec3(-1.5f + 3 * a, 0.0f, -1.5f + 3 * b), vec3(0, 1, 0)});
        break;
      case 1:
        probes.push_back({vec3(-1.5f + 3 * a, 2.2f * b, -1.5f), vec3(0, 0, 1)});
        break;
      case 2:
        probes.push_back({vec3(-1.5f, 2.2f * b, -1.5f + 3 * a), vec3(1, 0, 0)});
        break;
      default:
        probes.push_back({vec3(1.5f, 2.2f * b, -1.5f + 3 * a), vec3(-1, 0, 0)});
        break;
    }
  }
  return scene;
}

// `count` triangles of uneven power scattered in a slab 1-3 m over an 8 x 8 m floor.
SceneDescription scatter_scene(int count, std::vector<Probe>& probes) {
  SceneDescription scene;
  scene.materials = {named("white", MaterialType::kLambertian, glm::dvec3(0.75))};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    scene.materials.push_back(named("lamp" + std::to_string(i), MaterialType::kLight,
                                    glm::dvec3(0.5 + 20.0 * u(rng) * u(rng))));
    const glm::dvec3 at(8.0 * u(rng) - 4.0, 1.0 + 2.0 * u(rng), 8.0 * u(rng) - 4.0);
    TriangleMeshDesc mesh;
    mesh.material = static_cast<std::uint32_t>(scene.materials.size() - 1);
    add_triangle(mesh, at, at + glm::dvec3(0.05, 0.0, 0.0), at + glm::dvec3(0.0, 0.01, 0.05));
    scene.meshes.push_back(mesh);
  }
  scene.quads.push_back(QuadDesc{.corner = {-5, 0, -5}, .u = {10, 0, 0}, .v = {0, 0, 10}});
  std::mt19937 probe_rng(7);
  std::uniform_real_distribution<float> v(-4.0f, 4.0f);
  for (int i = 0; i < 4096; ++i)
    probes.push_back({vec3(v(probe_rng), 0.0f, v(probe_rng)), vec3(0, 1, 0)});
  return scene;
}

// Scenes by (layout, emitters, tree), built once per process.
const Setup& setup(bool grid, int emitters, bool tree) {
  static std::vector<std::pair<std::tuple<bool, int, bool>, std::unique_ptr<Setup>>> built;
  for (const auto& [key, s] : built)
    if (key == std::make_tuple(grid, emitters, tree)) return *s;
  auto s = std::make_unique<Setup>();
  const SceneDescription scene =
      grid ? grid_scene(static_cast<int>(std::lround(std::sqrt(emitters))), s->probes)
           : scatter_scene(emitters, s->probes);
  s->prepared = PreparedScene::build(scene, PrepareOptions{.light_tree = tree});
  s->view = s->prepared->view();
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  s->u.resize(65536);
  for (float& x : s->u) x = u(rng);
  built.emplace_back(std::make_tuple(grid, emitters, tree), std::move(s));
  return *built.back().second;
}

void report(benchmark::State& state, const Setup& s) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["lights"] = static_cast<double>(s.view.light_count);
}

void Independent(benchmark::State& state, bool grid, bool tree) {
  const Setup& s = setup(grid, static_cast<int>(state.range(0)), tree);
  std::uint32_t i = 0;
  for (auto _ : state) {
    const Probe& probe = s.probes[i & 4095];
    const LightPick pick = pick_light(s.view, probe.p, probe.n, s.u[i & 65535]);
    benchmark::DoNotOptimize(pick);
    ++i;
  }
  report(state, s);
}

void Chained(benchmark::State& state, bool grid, bool tree) {
  const Setup& s = setup(grid, static_cast<int>(state.range(0)), tree);
  std::uint32_t i = 0;
  float carry = 0.0f;  // what the previous pick left of its u: each pick waits for the last
  for (auto _ : state) {
    const Probe& probe = s.probes[i & 4095];
    const float u = s.u[i & 65535] + 1e-30f * carry;
    const LightPick pick = pick_light(s.view, probe.p, probe.n, u < 1.0f ? u : 0.0f);
    carry = pick.reused_u + static_cast<float>(pick.index);
    ++i;
  }
  benchmark::DoNotOptimize(carry);
  report(state, s);
}

void Pmf(benchmark::State& state, bool grid, bool tree) {
  const Setup& s = setup(grid, static_cast<int>(state.range(0)), tree);
  std::uint32_t i = 0;
  for (auto _ : state) {
    const Probe& probe = s.probes[i & 4095];
    const float pmf =
        light_pick_pmf(s.view, probe.p, probe.n, (i * 2654435761u) % s.view.light_count);
    benchmark::DoNotOptimize(pmf);
    ++i;
  }
  report(state, s);
}

void register_all() {
  for (const bool grid : {true, false})
    for (const bool tree : {true, false}) {
      const std::string name = std::string(grid ? "grid" : "scatter") + (tree ? "/tree" : "/power");
      for (const std::int64_t n : {64, 1024, 16384}) {
        benchmark::RegisterBenchmark(("Independent/" + name).c_str(), Independent, grid, tree)
            ->Arg(n);
        benchmark::RegisterBenchmark(("Chained/" + name).c_str(), Chained, grid, tree)->Arg(n);
        benchmark::RegisterBenchmark(("Pmf/" + name).c_str(), Pmf, grid, tree)->Arg(n);
      }
    }
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);  // the scene builds' accelerator lines
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
