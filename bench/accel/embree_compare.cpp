// embree_compare: traces one ray file with Embree 3 (rtcIntersect1 / rtcOccluded1) and with
// Tessera's default structure, on the same threads and the same harness, and prints the
// ratio of our throughput to Embree's. Embree is a yardstick here only: nothing outside
// bench/ links it.
//   embree_compare --mesh FILE --rays FILE.rays [--threads N] [--query closest|any] [--repeat R]
//                  [--accel wide|bvh|octree|brute|auto] [--isa auto|sse2]
//                  [--leaf-size N] [--bins N] [--merge N] [--traversal-cost C]
#include <embree3/rtcore.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "mesh_files.hpp"
#include "ray_file.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "trace_runner.hpp"

namespace {

using namespace tessera;
using namespace tessera::bench;

class EmbreeScene {
 public:
  EmbreeScene(const IndexedMesh& mesh, unsigned threads) {
    device_ = rtcNewDevice(("threads=" + std::to_string(threads)).c_str());
    if (device_ == nullptr) throw std::runtime_error("rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(
        device_,
        [](void* user, ssize_t bytes, bool) {
          auto* total = static_cast<std::atomic<std::int64_t>*>(user);
          *total += bytes;
          return true;
        },
        &bytes_);
    const auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.positions.size()));
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * 3 * sizeof(float));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangle_count()));
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(unsigned));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  double build_seconds() const { return build_seconds_; }
  // Memory Embree reports through its monitor once the scene is built (BVH, primitive
  // data and the vertex and index buffers it was given).
  std::int64_t bytes() const { return bytes_.load(); }

  float closest(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    fill(ray, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : kInfinity;
  }

  bool occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    fill(ray, r);
    rtcOccluded1(scene_, &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
  }

 private:
  static void fill(const Ray& ray, RTCRay& r) {
    r.org_x = ray.origin.x;
    r.org_y = ray.origin.y;
    r.org_z = ray.origin.z;
    r.dir_x = ray.direction.x;
    r.dir_y = ray.direction.y;
    r.dir_z = ray.direction.z;
    r.tnear = ray.t_min;
    r.tfar = ray.t_max;
    r.time = 0.0f;
    r.mask = 0xffffffffU;
    r.id = 0;
    r.flags = 0;
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  double build_seconds_ = 0.0;
  std::atomic<std::int64_t> bytes_{0};
};

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  CLI::App app{"Tessera against Embree on one ray file"};
  std::string mesh_path, rays_path, query = "closest", accel_name = "wide", isa = "auto";
  unsigned threads = std::max(1u, std::thread::hardware_concurrency()), repeat = 3;
  app.add_option("--mesh", mesh_path, "mesh file")->required()->check(CLI::ExistingFile);
  app.add_option("--rays", rays_path, "ray file")->required()->check(CLI::ExistingFile);
  app.add_option("--threads", threads, "worker threads")->check(CLI::Range(1u, 1024u));
  app.add_option("--query", query, "closest or any")->check(CLI::IsMember({"closest", "any"}));
  app.add_option("--repeat", repeat, "runs over all rays; the fastest counts")
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--accel", accel_name, "our structure")
      ->check(CLI::IsMember({"bvh", "wide", "octree", "brute", "auto"}));
  app.add_option("--isa", isa, "our kernels: auto or sse2")->check(CLI::IsMember({"auto", "sse2"}));
  // Tuning (as tessera-bench trace): measured as ratios, which move less on a busy machine.
  std::uint32_t leaf_size = 0, bins = 0;
  int merge_limit = -1;
  float traversal_cost = 0.0f;
  app.add_option("--leaf-size", leaf_size, "tuning: most triangles per BVH leaf");
  app.add_option("--bins", bins, "tuning: SAH bins per axis")->check(CLI::Range(2u, 64u));
  app.add_option("--merge", merge_limit, "tuning: largest subtree merged into one wide leaf")
      ->check(CLI::Range(0, 124));
  app.add_option("--traversal-cost", traversal_cost, "tuning: SAH node cost per block cost");
  CLI11_PARSE(app, argc, argv);

  try {
    const IndexedMesh mesh = load_mesh_with_assimp(mesh_path);
    const std::vector<Triangle> triangles = to_triangles(mesh);
    const std::vector<Ray> rays = read_ray_file(rays_path);
    std::printf("mesh: %s, %zu triangles; rays: %zu from %s; %u threads; query %s\n",
                mesh_path.c_str(), triangles.size(), rays.size(), rays_path.c_str(), threads,
                query.c_str());

    const EmbreeScene embree(mesh, threads);
    const double buffer_bytes =
        static_cast<double>(mesh.positions.size() * 12 + mesh.indices.size() * 4);
    std::printf("embree build: %.3f s, %.1f bytes/triangle besides the vertex and index buffers\n",
                embree.build_seconds(),
                (static_cast<double>(embree.bytes()) - buffer_bytes) /
                    static_cast<double>(triangles.size()));
    AccelBuildOptions options;
    options.kind = *parse_accel_kind(accel_name);
    options.allow_avx2 = isa != "sse2";
    if (leaf_size != 0) options.wide.max_leaf_size = leaf_size;
    if (bins != 0) options.wide.bin_count = bins;
    if (traversal_cost != 0.0f) options.wide.traversal_cost = traversal_cost;
    if (merge_limit >= 0) options.wide_merge_limit = static_cast<std::uint32_t>(merge_limit);
    const TriangleAccel ours = TriangleAccel::build(triangles, options);
    const AccelStats& s = ours.stats();
    std::printf(
        "tessera build: %.3f s (%s, %s, %.1f bytes/triangle)\n", s.build_seconds,
        std::string(accel_kind_name(s.kind)).c_str(), std::string(s.isa).c_str(),
        static_cast<double>(s.bytes) / static_cast<double>(std::max<std::size_t>(1, s.triangles)));

    const bool any = query == "any";
    const TraceChunk embree_chunk = [&](std::size_t begin, std::size_t end, float* t) {
      for (std::size_t i = begin; i < end; ++i)
        t[i - begin] =
            any ? (embree.occluded(rays[i]) ? 0.0f : kInfinity) : embree.closest(rays[i]);
    };
    const TraceChunk our_chunk = [&](std::size_t begin, std::size_t end, float* t) {
      for (std::size_t i = begin; i < end; ++i) {
        if (any) {
          t[i - begin] = ours.occluded(rays[i]) ? 0.0f : kInfinity;
        } else {
          HitRecord hit;
          t[i - begin] = ours.closest(rays[i], hit) ? hit.t : kInfinity;
        }
      }
    };
    std::vector<float> embree_t, our_t;
    // Alternate the two so both see the same machine load.
    TraceTiming embree_timing = run_trace(rays.size(), threads, 1, embree_chunk, &embree_t);
    TraceTiming our_timing = run_trace(rays.size(), threads, 1, our_chunk, &our_t);
    for (unsigned r = 1; r < repeat; ++r) {
      const TraceTiming e = run_trace(rays.size(), threads, 1, embree_chunk);
      const TraceTiming o = run_trace(rays.size(), threads, 1, our_chunk);
      if (e.best_seconds < embree_timing.best_seconds) embree_timing.best_seconds = e.best_seconds;
      if (o.best_seconds < our_timing.best_seconds) our_timing.best_seconds = o.best_seconds;
      embree_timing.best_cpu_seconds = std::min(embree_timing.best_cpu_seconds, e.best_cpu_seconds);
      our_timing.best_cpu_seconds = std::min(our_timing.best_cpu_seconds, o.best_cpu_seconds);
    }

    std::size_t hit_mismatch = 0, t_mismatch = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool eh = !std::isinf(embree_t[i]), oh = !std::isinf(our_t[i]);
      if (eh != oh) {
        ++hit_mismatch;
      } else if (eh && std::fabs(embree_t[i] - our_t[i]) >
                           1e-4f * std::max(1.0f, std::fabs(embree_t[i]))) {
        ++t_mismatch;
      }
    }
    embree_timing.mrays_per_s =
        static_cast<double>(rays.size()) / embree_timing.best_seconds * 1e-6;
    our_timing.mrays_per_s = static_cast<double>(rays.size()) / our_timing.best_seconds * 1e-6;
    const auto per_cpu_second = [&](const TraceTiming& t) {
      return static_cast<double>(rays.size()) / t.best_cpu_seconds * 1e-6;
    };
    std::printf(
        "per CPU-second (steadier on a busy machine): embree %.3f, tessera %.3f Mrays, ratio "
        "%.3f\n",
        per_cpu_second(embree_timing), per_cpu_second(our_timing),
        per_cpu_second(our_timing) / per_cpu_second(embree_timing));
    std::printf("embree:  ");
    print_result_line(embree_timing);
    std::printf("tessera: ");
    print_result_line(our_timing);
    std::printf("rays hit by one only: %zu (%.4f%%), hit by both at different t: %zu\n",
                hit_mismatch,
                100.0 * static_cast<double>(hit_mismatch) /
                    static_cast<double>(std::max<std::size_t>(1, rays.size())),
                t_mismatch);
    std::printf("ratio=%.3f tessera_mrays_per_s=%.3f embree_mrays_per_s=%.3f\n",
                our_timing.mrays_per_s / embree_timing.mrays_per_s, our_timing.mrays_per_s,
                embree_timing.mrays_per_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embree_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
