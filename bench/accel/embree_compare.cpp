// embree_compare: traces one ray file with Embree 3 (rtcIntersect1 / rtcOccluded1) and with
// Tessera's default structure, on the same threads and the same harness, and prints the
// ratio of our throughput to Embree's, next to each build's time and memory. Embree is
// built at medium quality (its default, a binned SAH build) and at high quality (what a
// renderer picks for a static scene: spatial splits), the two yardsticks the comparison
// is judged against. Embree is a yardstick here only: nothing outside bench/ links it.
//   embree_compare --mesh FILE --rays FILE.rays [--threads N] [--query closest|any] [--repeat R]
//                  [--embree-quality both|medium|high] [--embree-config verbose=2]
//                  [--accel wide|bvh|octree|brute|auto] [--isa auto|sse2|avx2|avx512]
//                  [--leaf-size N] [--bins N] [--merge N] [--traversal-cost C] [--presplit F]
#include <embree3/rtcore.h>
#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "mesh_files.hpp"
#include "ray_file.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "trace_runner.hpp"

namespace {

using namespace tessera;
using namespace tessera::bench;

class EmbreeScene {
 public:
  EmbreeScene(const IndexedMesh& mesh, unsigned threads, RTCBuildQuality quality,
              const std::string& config) {
    const std::string device_config =
        "threads=" + std::to_string(threads) + (config.empty() ? "" : "," + config);
    device_ = rtcNewDevice(device_config.c_str());
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
    // Scene and geometry quality both: RTC_BUILD_QUALITY_HIGH on the scene is what turns on
    // Embree's spatial-split (SBVH) builder for a static scene.
    rtcSetSceneBuildQuality(scene_, quality);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, quality);
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

struct Contender {
  std::string name;
  double build_seconds = 0.0;
  double bytes_per_triangle = 0.0;
  TraceChunk trace;
  TraceTiming timing;
  std::vector<float> t;
};

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  CLI::App app{"Tessera against Embree on one ray file"};
  std::string mesh_path, rays_path, query = "closest", accel_name = "wide", isa = "auto",
                                    quality = "both", embree_config;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency()), repeat = 3;
  app.add_option("--mesh", mesh_path, "mesh file")->required()->check(CLI::ExistingFile);
  app.add_option("--rays", rays_path, "ray file")->required()->check(CLI::ExistingFile);
  app.add_option("--threads", threads, "worker threads (tracing and both builds)")
      ->check(CLI::Range(1u, 1024u));
  app.add_option("--query", query, "closest or any")->check(CLI::IsMember({"closest", "any"}));
  app.add_option("--repeat", repeat, "runs over all rays; the fastest counts")
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--embree-quality", quality, "Embree build quality: both, medium or high")
      ->check(CLI::IsMember({"both", "medium", "high"}));
  app.add_option("--embree-config", embree_config,
                 "appended to Embree's device configuration (e.g. verbose=2: prints the builder)");
  app.add_option("--accel", accel_name, "our structure")
      ->check(CLI::IsMember({"bvh", "wide", "octree", "brute", "auto"}));
  app.add_option(
         "--isa", isa,
         "our kernels: auto (the widest the processor runs) or at most sse2, avx2 or avx512")
      ->check(CLI::IsMember({"auto", "sse2", "avx2", "avx512"}));
  // Tuning (as tessera-bench trace): measured as ratios, which move less on a busy machine.
  std::uint32_t leaf_size = 0, bins = 0;
  int merge_limit = -1;
  float traversal_cost = 0.0f;
  std::optional<float> sbvh;
  std::optional<float> presplit;
  app.add_option("--presplit", presplit,
                 "tuning: pre-split budget, extra references per triangle (0: off; default: "
                 "chosen from the mesh)")
      ->check(CLI::Range(0.0f, 16.0f));
  app.add_option("--leaf-size", leaf_size, "tuning: most triangles per BVH leaf");
  app.add_option("--bins", bins, "tuning: SAH bins per axis")->check(CLI::Range(2u, 64u));
  app.add_option("--merge", merge_limit, "tuning: largest subtree merged into one wide leaf")
      ->check(CLI::Range(0, 124));
  app.add_option("--sbvh", sbvh,
                 "wide BVH: spatial splits, up to this many extra references per triangle (0: "
                 "binned build; default: chosen from the mesh)")
      ->check(CLI::Range(0.0f, 16.0f));
  app.add_option("--traversal-cost", traversal_cost, "tuning: SAH node cost per block cost");
  std::size_t dump_mismatches = 0;
  app.add_option("--dump-mismatches", dump_mismatches,
                 "print up to this many rays that one Embree build hits and ours misses, or the "
                 "reverse (origin, direction, t_min, both t), to judge them exactly");
  CLI11_PARSE(app, argc, argv);

  try {
    const IndexedMesh mesh = load_mesh_with_assimp(mesh_path);
    const std::vector<Triangle> triangles = to_triangles(mesh);
    const std::vector<Ray> rays = read_ray_file(rays_path);
    const double triangle_count = static_cast<double>(std::max<std::size_t>(1, triangles.size()));
    std::printf("mesh: %s, %zu triangles; rays: %zu from %s; %u threads; query %s\n",
                mesh_path.c_str(), triangles.size(), rays.size(), rays_path.c_str(), threads,
                query.c_str());
    const bool any = query == "any";

    // Embree scenes, one per quality asked for. Each device gets `threads` threads, which it
    // also builds with; ours builds in a TBB arena of the same size, so build times compare.
    std::vector<std::unique_ptr<EmbreeScene>> embree;
    std::vector<Contender> contenders;
    const double buffer_bytes =
        static_cast<double>(mesh.positions.size() * 12 + mesh.indices.size() * 4);
    for (const auto& [name, level] : {std::pair{"medium", RTC_BUILD_QUALITY_MEDIUM},
                                      std::pair{"high", RTC_BUILD_QUALITY_HIGH}}) {
      if (quality != "both" && quality != name) continue;
      embree.push_back(std::make_unique<EmbreeScene>(mesh, threads, level, embree_config));
      const EmbreeScene* scene = embree.back().get();
      Contender c;
      c.name = std::string("embree ") + name;
      c.build_seconds = scene->build_seconds();
      // Memory besides the vertex and index buffers it was given.
      c.bytes_per_triangle = (static_cast<double>(scene->bytes()) - buffer_bytes) / triangle_count;
      c.trace = [scene, &rays, any](std::size_t begin, std::size_t end, float* t) {
        for (std::size_t i = begin; i < end; ++i)
          t[i - begin] =
              any ? (scene->occluded(rays[i]) ? 0.0f : kInfinity) : scene->closest(rays[i]);
      };
      contenders.push_back(std::move(c));
    }

    AccelBuildOptions options;
    options.kind = *parse_accel_kind(accel_name);
    if (isa != "auto") options.max_isa = *parse_kernel_isa(isa);
    if (leaf_size != 0) options.wide.max_leaf_size = leaf_size;
    if (bins != 0) options.wide.bin_count = bins;
    if (traversal_cost != 0.0f) options.wide.traversal_cost = traversal_cost;
    if (merge_limit >= 0) options.wide_merge_limit = static_cast<std::uint32_t>(merge_limit);
    options.presplit_budget = presplit;
    options.spatial_split_budget = sbvh;
    tbb::task_arena arena(static_cast<int>(threads));
    TriangleAccel ours;
    arena.execute([&] { ours = TriangleAccel::build(triangles, options); });
    const AccelStats& s = ours.stats();
    {
      Contender c;
      c.name = "tessera " + std::string(accel_kind_name(s.kind)) + " (" + std::string(s.isa) + ")";
      c.build_seconds = s.build_seconds;
      c.bytes_per_triangle = static_cast<double>(s.bytes) / triangle_count;
      c.trace = [&ours, &rays, any](std::size_t begin, std::size_t end, float* t) {
        for (std::size_t i = begin; i < end; ++i) {
          if (any) {
            t[i - begin] = ours.occluded(rays[i]) ? 0.0f : kInfinity;
          } else {
            HitRecord hit;
            t[i - begin] = ours.closest(rays[i], hit) ? hit.t : kInfinity;
          }
        }
      };
      contenders.push_back(std::move(c));
    }
    Contender& tessera = contenders.back();

    // Round-robin, so every contender sees the same machine load; the fastest run counts.
    for (unsigned r = 0; r < repeat; ++r) {
      for (Contender& c : contenders) {
        const TraceTiming timing =
            run_trace(rays.size(), threads, 1, c.trace, r == 0 ? &c.t : nullptr);
        if (r == 0) {
          c.timing = timing;
        } else {
          c.timing.best_seconds = std::min(c.timing.best_seconds, timing.best_seconds);
          c.timing.best_cpu_seconds = std::min(c.timing.best_cpu_seconds, timing.best_cpu_seconds);
        }
      }
    }

    const double ray_count = static_cast<double>(rays.size());
    std::printf("%-22s %9s %10s %9s %11s %8s %8s %10s %8s\n", "", "build s", "bytes/tri", "Mrays/s",
                "Mrays/CPU-s", "hits", "ours/it", "ours/it CPU", "hit diff");
    for (Contender& c : contenders) {
      c.timing.mrays_per_s = ray_count / c.timing.best_seconds * 1e-6;
      std::size_t hits = 0, hit_mismatch = 0, t_mismatch = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool ch = !std::isinf(c.t[i]), oh = !std::isinf(tessera.t[i]);
        hits += ch ? 1 : 0;
        if (ch != oh) {
          if (&c != &tessera && hit_mismatch < dump_mismatches) {
            const Ray& r = rays[i];
            std::printf(
                "mismatch %s ray %zu: origin %.9g %.9g %.9g direction %.9g %.9g %.9g "
                "t_min %.9g, theirs %.9g, ours %.9g\n",
                c.name.c_str(), i, r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y,
                r.direction.z, r.t_min, c.t[i], tessera.t[i]);
          }
          ++hit_mismatch;
        } else if (ch &&
                   std::fabs(c.t[i] - tessera.t[i]) > 1e-4f * std::max(1.0f, std::fabs(c.t[i]))) {
          ++t_mismatch;
        }
      }
      const double cpu_rate = ray_count / c.timing.best_cpu_seconds * 1e-6;
      const double our_cpu_rate = ray_count / tessera.timing.best_cpu_seconds * 1e-6;
      std::printf("%-22s %9.3f %10.1f %9.3f %11.3f %8zu %8.3f %10.3f %8zu\n", c.name.c_str(),
                  c.build_seconds, c.bytes_per_triangle, c.timing.mrays_per_s, cpu_rate, hits,
                  ray_count / tessera.timing.best_seconds * 1e-6 / c.timing.mrays_per_s,
                  our_cpu_rate / cpu_rate, hit_mismatch);
      if (&c != &tessera && t_mismatch != 0)
        std::printf("%-22s hit by both at different t: %zu\n", "", t_mismatch);
    }
    // One machine-readable line: ours over each Embree build, and the build-time ratios.
    std::printf(
        "tessera_mrays_per_s=%.3f tessera_build_s=%.3f tessera_bytes_per_tri=%.1f "
        "refs_per_tri=%.2f fill_ratio=%.1f presplit=%.2f(%s) sbvh=%.2f(%s) sah_nodes=%.3f "
        "sah_blocks=%.3f",
        tessera.timing.mrays_per_s, tessera.build_seconds, tessera.bytes_per_triangle,
        static_cast<double>(s.leaf_references) / triangle_count, s.fill_ratio,
        static_cast<double>(s.presplit_budget), s.presplit_chosen ? "chosen" : "given",
        static_cast<double>(s.spatial_split_budget), s.spatial_split_chosen ? "chosen" : "given",
        s.sah.nodes, s.sah.leaves);
    for (const Contender& c : contenders) {
      if (&c == &tessera) continue;
      const std::string key = c.name.substr(c.name.find(' ') + 1);
      std::printf(
          " ratio_%s=%.3f cpu_ratio_%s=%.3f embree_%s_mrays_per_s=%.3f embree_%s_build_s=%.3f "
          "embree_%s_bytes_per_tri=%.1f build_ratio_%s=%.3f",
          key.c_str(), tessera.timing.mrays_per_s / c.timing.mrays_per_s, key.c_str(),
          c.timing.best_cpu_seconds / tessera.timing.best_cpu_seconds, key.c_str(),
          c.timing.mrays_per_s, key.c_str(), c.build_seconds, key.c_str(), c.bytes_per_triangle,
          key.c_str(), tessera.build_seconds / c.build_seconds);
    }
    std::printf("\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embree_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
