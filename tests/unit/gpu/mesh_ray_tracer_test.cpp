// gpu::MeshRayTracer: the device's BVH walks on their own. Without a device the tracer must
// refuse with the CUDA error; with one, both walks must find the CPU's hits.
#include "tessera/gpu/mesh_ray_tracer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "../accel/accel_test_scenes.hpp"
#include "tessera/gpu/gpu_renderer.hpp"

namespace tessera {
namespace {

TEST(GpuMeshRayTracer, WithoutADeviceItThrowsNamingTheCudaError) {
  if (!gpu::list_devices().empty()) GTEST_SKIP() << "a CUDA device is present";
  try {
    gpu::MeshRayTracer tracer(0, accel_test::triangle_soup(100, 1));
    FAIL() << "constructed without a device";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("CUDA"), std::string::npos) << e.what();
  }
}

TEST(GpuMeshRayTracer, BothWalksFindTheCpusClosestHits) {
  if (gpu::list_devices().empty()) GTEST_SKIP() << "no CUDA device on this machine";
  for (const auto& [tris, extent] : {std::pair{accel_test::triangle_soup(5000, 7), 1.5f},
                                     std::pair{accel_test::closed_sphere(5), 1.5f},
                                     std::pair{accel_test::axis_aligned_grid(5), 6.0f}}) {
    const std::vector<Ray> rays = accel_test::test_rays(20000, 3, extent);
    gpu::MeshRayTracer tracer(0, tris);
    for (const gpu::DeviceWalk walk : {gpu::DeviceWalk::kCompressed, gpu::DeviceWalk::kBinary}) {
      const gpu::DeviceTraceResult result = tracer.trace(rays, walk, 1);
      ASSERT_EQ(result.t.size(), rays.size());
      std::size_t disagree = 0, hits = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const accel_test::ReferenceHit reference = accel_test::reference_closest(tris, rays[i]);
        const bool gpu_hit = std::isfinite(result.t[i]);
        hits += reference.hit ? 1 : 0;
        if (gpu_hit != reference.hit) {
          ++disagree;
          continue;
        }
        // nvcc may fuse the test's multiplies and adds where the host does not: t agrees
        // to float rounding, not bit for bit.
        if (gpu_hit) {
          EXPECT_NEAR(result.t[i], reference.record.t, 1e-4f * reference.record.t);
        }
      }
      // Fused rounding can flip a ray that grazes an edge or a silhouette: at most 1 in 1,000.
      EXPECT_LE(disagree, rays.size() / 1000) << "walk " << static_cast<int>(walk);
      EXPECT_GT(hits, rays.size() / 10);
    }
  }
}

}  // namespace
}  // namespace tessera
