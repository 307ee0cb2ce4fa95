#include "device_walk.hpp"

#include <atomic>
#include <cstdio>
#include <vector>

#include "mesh_files.hpp"
#include "ray_file.hpp"
#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/accel/compressed_wide_bvh.hpp"
#include "tessera/accel/triangle_bvh.hpp"
#include "tessera/geometry/triangle.hpp"
#include "trace_runner.hpp"

namespace tessera::bench {

int run_device_walk(const std::string& mesh_path, const std::string& rays_path, unsigned threads,
                    unsigned repeat) {
  const std::vector<Triangle> triangles = to_triangles(load_mesh_with_assimp(mesh_path));
  const std::vector<Ray> rays = read_ray_file(rays_path);
  const Bvh binary = build_triangle_bvh(triangles);  // the device layout's options
  const CompressedWideBvh compressed = compress_bvh(binary);
  if (compressed.nodes.empty()) {
    std::fprintf(stderr, "tessera-bench: this tree cannot be compressed\n");
    return 1;
  }
  BvhView view = binary.view();
  view.compressed_nodes = compressed.nodes.data();
  view.compressed_primitives = compressed.primitives.data();
  const double binary_mb =
      static_cast<double>(binary.nodes.size() * sizeof(BvhNode) + binary.primitives.size() * 4) /
      1e6;
  const double compressed_mb =
      static_cast<double>(compressed.nodes.size() * sizeof(CompressedWideNode) +
                          compressed.primitives.size() * 4) /
      1e6;
  std::printf(
      "mesh: %s, %zu triangles; rays: %zu\n"
      "binary:     %zu nodes of 32 bytes, depth %u, %.1f MB with references\n"
      "compressed: %zu nodes of 80 bytes, depth %u, %.1f MB with references\n",
      mesh_path.c_str(), triangles.size(), rays.size(), binary.nodes.size(), binary.depth,
      binary_mb, compressed.nodes.size(), compressed.depth, compressed_mb);

  double mrays[2] = {0.0, 0.0};
  for (int walk = 0; walk < 2; ++walk) {
    std::atomic<std::uint64_t> tests{0};
    const TraceChunk chunk = [&](std::size_t begin, std::size_t end, float* t) {
      std::uint64_t local_tests = 0;
      const auto test_triangle = [&](std::uint32_t ref, const Ray& r, float t_max, HitRecord& h) {
        ++local_tests;
        return intersect(triangles[ref], r, t_max, h, ref);
      };
      for (std::size_t i = begin; i < end; ++i) {
        HitRecord hit;
        hit.t = rays[i].t_max;
        const bool found = walk == 0
                               ? traverse_bvh<false>(view, rays[i], hit, test_triangle)
                               : traverse_compressed_wide<false>(view, rays[i], hit, test_triangle);
        t[i - begin] = found ? hit.t : kInfinity;
      }
      tests += local_tests;
    };
    const TraceTiming timing = run_trace(rays.size(), threads, repeat, chunk);
    mrays[walk] = timing.mrays_per_s;
    std::printf(
        "%s walk: %.1f triangle tests per ray, %.3f Mrays/s (%u threads, best of %u), "
        "hits=%llu tsum=%.6f\n",
        walk == 0 ? "binary    " : "compressed",
        static_cast<double>(tests.load()) / static_cast<double>(rays.size() * repeat),
        timing.mrays_per_s, threads, repeat, static_cast<unsigned long long>(timing.hits),
        timing.tsum);
  }
  std::printf(
      "binary_mb=%.2f compressed_mb=%.2f binary_mrays_per_s=%.3f "
      "compressed_mrays_per_s=%.3f ratio=%.3f\n",
      binary_mb, compressed_mb, mrays[0], mrays[1], mrays[1] / mrays[0]);
  return 0;
}

}  // namespace tessera::bench
