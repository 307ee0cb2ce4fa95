// The GPU backend (core/cuda): device listing, upload and tile rendering. Built whenever
// nvcc is found; the tests that need a device skip on machines without one (CI has nvcc and
// no GPU), and the rest run everywhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "../render/device_test_scenes.hpp"
#include "tessera/gpu/gpu_renderer.hpp"
#include "tessera/render/film.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

const std::filesystem::path kExamples =
    std::filesystem::path(TESSERA_SOURCE_DIR) / "examples" / "scenes";

std::shared_ptr<const PreparedScene> example(const char* name) {
  LoadedScene loaded = load_scene_file(kExamples / name);
  RenderSettings& r = loaded.scene.render;
  r.width = 48;
  r.height = 32;
  r.samples_per_pixel = 8;
  r.max_depth = 6;
  r.tile_size = 16;
  return PreparedScene::build(loaded.scene);
}

TEST(Gpu, ListingDevicesNeverThrows) {
  const std::vector<gpu::DeviceInfo> devices = gpu::list_devices();
  for (const gpu::DeviceInfo& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.memory_bytes, 0u);
    EXPECT_GT(d.multiprocessors, 0);
  }
}

// What the driver says each kernel costs a multiprocessor; one `kernel` line each for
// bench/gpu/device_checks.sh. At least one block must fit, or no launch could run.
TEST(Gpu, KernelsReportTheirRegistersAndOccupancy) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  const std::vector<gpu::KernelInfo> kernels = gpu::path_tracer_kernels(0);
  ASSERT_EQ(kernels.size(), 2u);
  for (const gpu::KernelInfo& k : kernels) {
    std::printf(
        "kernel %s: %d registers, %zu bytes of local memory per thread, %d blocks of %d "
        "per multiprocessor, occupancy %.3f\n",
        k.name.c_str(), k.registers, k.local_bytes, k.blocks_per_multiprocessor,
        k.threads_per_block, k.occupancy);
    EXPECT_GT(k.registers, 0);
    EXPECT_LE(k.registers, 255);
    EXPECT_GE(k.blocks_per_multiprocessor, 1);
    EXPECT_GT(k.occupancy, 0.0);
    EXPECT_LE(k.occupancy, 1.0);
  }
}

// Refused before any CUDA call, so this runs without a device too.
TEST(Gpu, ScenesTheDeviceCannotRenderAreRefusedWithTheReason) {
  try {
    gpu::TileRenderer renderer(0, example("patches.yaml"));
    FAIL() << "a scene with spline patches was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("patches"), std::string::npos) << e.what();
  }
}

// A ridged 16 x 16 grid placed three times, turned and stretched (the CPU shares it through
// an instance level; the device layout bakes each placement), beside a sphere light.
std::shared_ptr<const PreparedScene> shared_mesh_scene() {
  SceneDescription scene;
  scene.camera.position = {0.0, 1.0, 4.0};
  scene.camera.look_at = {0.0, 0.0, 0.0};
  MaterialDesc white;
  white.name = "white";
  MaterialDesc light;
  light.name = "light";
  light.type = MaterialType::kLight;
  light.emission = glm::dvec3(6.0);
  scene.materials = {white, light};
  TriangleMeshDesc grid;
  constexpr std::uint32_t kCells = 16, kRow = kCells + 1;
  for (std::uint32_t j = 0; j <= kCells; ++j)
    for (std::uint32_t i = 0; i <= kCells; ++i)
      grid.positions.push_back({-1.0 + 2.0 * i / kCells, 0.1 * (i % 2), -1.0 + 2.0 * j / kCells});
  for (std::uint32_t j = 0; j < kCells; ++j)
    for (std::uint32_t i = 0; i < kCells; ++i)
      for (std::uint32_t k : {0u, 1u, kRow, 1u, kRow + 1, kRow})
        grid.indices.push_back(j * kRow + i + k);
  for (int c = 0; c < 3; ++c) {
    TriangleMeshDesc& placed = scene.meshes.emplace_back(grid);
    placed.transform = TransformDesc{.translate = {0.0, -0.6 + 0.5 * c, 0.0},
                                     .rotate_axis = {0.0, 1.0, 0.0},
                                     .rotate_degrees = 30.0 * c,
                                     .scale = {1.0 + 0.2 * c, 1.0, 0.9}};
  }
  SphereDesc lamp{.center = {0.0, 2.0, 1.0}, .radius = 0.4};
  lamp.material = 1;
  scene.spheres.push_back(lamp);
  scene.render.width = 48;
  scene.render.height = 32;
  scene.render.samples_per_pixel = 8;
  scene.render.max_depth = 6;
  scene.render.tile_size = 16;
  auto prepared = PreparedScene::build(scene);
  EXPECT_EQ(prepared->shared_mesh_placements(), 3u);
  return prepared;
}

// The device draws the samples the CPU draws, through the same layout: images agree up to
// float differences (nvcc contracts multiply-adds), which can send a path another way, so
// the bound is on the image mean (1%) and on how many pixels differ by more than 1e-3
// relative (5%). Every scene the CPU's device-layout test renders (device_test_scenes.hpp),
// and a mesh placed three times; one `cpu-gpu` line per scene gives the differences
// (bench/gpu/device_checks.sh collects them).
TEST(Gpu, TilesMatchTheCpuRenderOfTheDeviceLayout) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  std::vector<device_tests::DeviceTestScene> scenes = device_tests::device_test_scenes();
  scenes.push_back({"shared meshes", {}});
  for (const device_tests::DeviceTestScene& test : scenes) {
    SCOPED_TRACE(test.name);
    const auto scene =
        test.name == "shared meshes" ? shared_mesh_scene() : PreparedScene::build(test.scene);
    gpu::TileRenderer renderer(0, scene);
    EXPECT_GT(renderer.uploaded_bytes(), 0u);
    const RenderSettings& r = scene->settings();
    double cpu_sum = 0.0, gpu_sum = 0.0, largest = 0.0;
    std::size_t far = 0, values = 0;
    for (const TileRect& tile : make_tiles(r.width, r.height, r.tile_size)) {
      std::vector<float> cpu(tile.pixel_count() * 4), device(tile.pixel_count() * 4);
      scene->render_tile_device_layout(tile, cpu);
      const TileStats stats = renderer.render_tile(tile, device);
      EXPECT_GT(stats.rays, 0u);
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        if (i % 4 == 3) continue;
        ASSERT_TRUE(std::isfinite(device[i]));
        cpu_sum += cpu[i];
        gpu_sum += device[i];
        const double apart = std::fabs(cpu[i] - device[i]);
        largest = std::max(largest, apart);
        far += apart > 1e-3 * (1.0 + std::fabs(cpu[i])) ? 1 : 0;
        ++values;
      }
    }
    std::printf(
        "cpu-gpu %s: mean %.6g / %.6g (%+.2e relative), %zu of %zu values apart by "
        "more than 1e-3 relative, largest difference %.3g\n",
        test.name.c_str(), cpu_sum / static_cast<double>(values),
        gpu_sum / static_cast<double>(values), (gpu_sum - cpu_sum) / cpu_sum, far, values, largest);
    EXPECT_NEAR(gpu_sum, cpu_sum, 0.01 * cpu_sum);
    EXPECT_LE(far, values / 20);
  }
}

// Every AOV plane of a job, rendered in one batch, against the CPU's render of the device
// layout: the same bounds as the beauty's per plane, ids compared as integers and depth's
// +inf (no hit) as itself. One `cpu-gpu aov` line per plane.
TEST(Gpu, AovPlanesMatchTheCpuRenderOfTheDeviceLayout) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  LoadedScene loaded = load_scene_file(kExamples / "cornell.yaml");
  device_tests::shrink_for_device_tests(loaded.scene.render);
  loaded.scene.render.aovs = kAllAovs;
  const auto scene = PreparedScene::build(loaded.scene);
  gpu::TileRenderer renderer(0, scene);
  const RenderSettings& r = scene->settings();
  const std::vector<TileRect> tiles = make_tiles(r.width, r.height, r.tile_size);
  std::vector<TilePasses> device(tiles.size());
  const std::vector<TileStats> stats = renderer.render_tiles(tiles, device);
  ASSERT_EQ(stats.size(), tiles.size());
  for (std::size_t a = 0; a <= kAovCount; ++a) {
    const std::string name = a == 0 ? "beauty" : std::string(aov_names()[a - 1]);
    SCOPED_TRACE(name);
    const bool ids = a > 0 && (1u << (a - 1)) == kAovPrimitiveId;
    std::size_t far = 0, values = 0;
    double cpu_sum = 0.0, gpu_sum = 0.0;
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      TilePasses cpu;
      scene->render_tile_device_layout(tiles[t], cpu);
      const std::vector<float>& want = a == 0 ? cpu.beauty : cpu.aovs[a - 1];
      const std::vector<float>& got = a == 0 ? device[t].beauty : device[t].aovs[a - 1];
      ASSERT_EQ(got.size(), want.size()) << "tile " << t;
      ASSERT_EQ(got.size(), tiles[t].pixel_count() * 4) << "tile " << t;
      for (std::size_t i = 0; i < want.size(); ++i) {
        if (i % 4 == 3) continue;
        ++values;
        if (ids) {
          far += float_as_id(want[i]) == float_as_id(got[i]) ? 0 : 1;
          continue;
        }
        if (!std::isfinite(want[i]) || !std::isfinite(got[i])) {
          far += want[i] == got[i] ? 0 : 1;
          continue;
        }
        cpu_sum += want[i];
        gpu_sum += got[i];
        far += std::fabs(want[i] - got[i]) > 1e-3 * (1.0 + std::fabs(want[i])) ? 1 : 0;
      }
    }
    std::printf("cpu-gpu aov %s: sum %.6g / %.6g, %zu of %zu values apart\n", name.c_str(), cpu_sum,
                gpu_sum, far, values);
    EXPECT_NEAR(gpu_sum, cpu_sum, 0.01 * std::fabs(cpu_sum) + 1e-6);
    EXPECT_LE(far, values / 20);
  }
}

// A batch is one launch over several tiles (blockIdx.z): each tile must land in its own
// buffer with its own ray count, and equal the same tile rendered alone on the device.
TEST(Gpu, ABatchOfTilesIsEachTileRenderedAlone) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  const auto scene = example("cornell.yaml");
  gpu::TileRenderer renderer(0, scene);
  const RenderSettings& r = scene->settings();
  const std::vector<TileRect> tiles = make_tiles(r.width, r.height, r.tile_size);
  ASSERT_GT(tiles.size(), 2u);
  std::vector<std::vector<float>> batched;
  std::vector<std::span<float>> planes;
  for (const TileRect& tile : tiles) batched.emplace_back(tile.pixel_count() * 4, -1.0f);
  for (auto& plane : batched) planes.emplace_back(plane);
  const std::vector<TileStats> stats = renderer.render_tiles(tiles, planes);
  ASSERT_EQ(stats.size(), tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    std::vector<float> alone(tiles[t].pixel_count() * 4);
    const TileStats single = renderer.render_tile(tiles[t], alone);
    EXPECT_EQ(batched[t], alone) << "tile " << t;  // the same samples, the same kernel
    EXPECT_EQ(stats[t].rays, single.rays) << "tile " << t;
  }
}

}  // namespace
}  // namespace tessera
