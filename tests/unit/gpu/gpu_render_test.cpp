// The GPU backend (core/cuda): device listing, upload and tile rendering. Built whenever
// nvcc is found; the tests that need a device skip on machines without one (CI has nvcc and
// no GPU), and the rest run everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "tessera/gpu/gpu_renderer.hpp"
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

// Refused before any CUDA call, so this runs without a device too.
TEST(Gpu, ScenesTheDeviceCannotRenderAreRefusedWithTheReason) {
  try {
    gpu::TileRenderer renderer(0, example("patches.yaml"));
    FAIL() << "a scene with spline patches was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("patches"), std::string::npos) << e.what();
  }
}

// The device draws the samples the CPU draws, through the same layout: images agree up to
// float differences (nvcc contracts multiply-adds), which can send a path another way, so
// the bound is on the image mean (1%) and on how many pixels differ by more than 1e-3
// relative (5%).
TEST(Gpu, TilesMatchTheCpuRenderOfTheDeviceLayout) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  for (const char* name : {"cornell.yaml", "shapes.yaml", "textures.yaml"}) {
    SCOPED_TRACE(name);
    const auto scene = example(name);
    gpu::TileRenderer renderer(0, scene);
    EXPECT_GT(renderer.uploaded_bytes(), 0u);
    const RenderSettings& r = scene->settings();
    double cpu_sum = 0.0, gpu_sum = 0.0;
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
        far += std::fabs(cpu[i] - device[i]) > 1e-3f * (1.0f + std::fabs(cpu[i])) ? 1 : 0;
        ++values;
      }
    }
    EXPECT_NEAR(gpu_sum, cpu_sum, 0.01 * cpu_sum);
    EXPECT_LE(far, values / 20);
  }
}

}  // namespace
}  // namespace tessera
