// tessera-bench: ray files and tracing throughput of the acceleration structures.
//   tessera-bench rays  --mesh FILE --kind primary|diffuse --width W --height H --out FILE.rays
//   tessera-bench trace --mesh FILE --rays FILE.rays [--threads N]
//                       [--accel bvh|wide|octree|brute|auto] [--query closest|any]
//                       [--repeat R] [--isa auto|sse2|avx2|avx512]
//   tessera-bench mesh  --shape knot|scatter|tubes|uneven --triangles N --out FILE.ply
//                       [--strips S --rings R]  (tubes: tessellation of each tube)
//   tessera-bench load  --mesh FILE [--repeat R]
//   tessera-bench device-walk --mesh FILE --rays FILE.rays [--threads N] [--repeat R]
//   tessera-bench gpu-trace --mesh FILE --rays FILE.rays [--threads N] [--repeat R]
//                           [--device D]  (built with the GPU backend)
//   tessera-bench sizes [--sizes N...] [--rays N] [--repeat R]
//   tessera-bench converge SCENE.yaml [--reference REF.exr] [--reference-spp N]
//                          [--spp 1,2,4,...] [--csv OUT.csv] [--plot OUT.png]
//                          [--peer cycles [--blender B] [--peer-dir DIR]] [--export-json F]
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "converge.hpp"
#include "specialise.hpp"

#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "device_walk.hpp"
#if defined(TESSERA_HAS_CUDA)
#include "gpu_trace.hpp"
#endif
#include "mesh_files.hpp"
#include "ray_file.hpp"
#include "ray_generation.hpp"
#include "size_sweep.hpp"
#include "synthetic_meshes.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "trace_runner.hpp"

namespace tessera::bench {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Aabb bounds_of(std::span<const Triangle> triangles) {
  Aabb box;
  for (const Triangle& t : triangles) box.extend(bounds(t));
  return box;
}

std::vector<Triangle> load_triangles(const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  const IndexedMesh mesh = load_mesh_with_assimp(path);
  std::vector<Triangle> triangles = to_triangles(mesh);
  std::printf("mesh: %s, %zu triangles, loaded through assimp in %.3f s\n", path.c_str(),
              triangles.size(), seconds_since(start));
  return triangles;
}

void print_accel(const TriangleAccel& accel) {
  const AccelStats& s = accel.stats();
  std::printf(
      "accel: %s (%s), build %.3f s, %.1f bytes/triangle, %zu nodes, depth %u, %.2f "
      "references/triangle, box fill ratio %.1f, pre-split budget %.2f (%s), spatial-split budget "
      "%.2f (%s), SAH cost %.3f (nodes %.3f + blocks %.3f)\n",
      std::string(accel_kind_name(s.kind)).c_str(), std::string(s.isa).c_str(), s.build_seconds,
      s.triangles ? static_cast<double>(s.bytes) / static_cast<double>(s.triangles) : 0.0, s.nodes,
      s.depth,
      s.triangles ? static_cast<double>(s.leaf_references) / static_cast<double>(s.triangles) : 0.0,
      s.fill_ratio, static_cast<double>(s.presplit_budget), s.presplit_chosen ? "chosen" : "given",
      static_cast<double>(s.spatial_split_budget), s.spatial_split_chosen ? "chosen" : "given",
      s.sah.nodes + s.sah.leaves, s.sah.nodes, s.sah.leaves);
}

int run_rays(const std::string& mesh_path, const std::string& kind, std::uint32_t width,
             std::uint32_t height, const std::string& out) {
  const std::vector<Triangle> triangles = load_triangles(mesh_path);
  const Aabb box = bounds_of(triangles);
  std::vector<Ray> rays = make_primary_rays(box, width, height);
  if (kind == "diffuse") {
    const TriangleAccel accel = TriangleAccel::build(triangles);
    std::vector<HitRecord> hits(rays.size());
    accel.closest(rays, hits);
    rays = make_diffuse_rays(rays, hits, triangles, box);
  }
  write_ray_file(out, rays);
  std::printf("wrote %zu %s rays to %s\n", rays.size(), kind.c_str(), out.c_str());
  return 0;
}

struct TuneOptions {
  std::uint32_t leaf_size = 0;  // 0: the library's defaults
  std::uint32_t bins = 0;
  float traversal_cost = 0.0f;
  int merge_limit = -1;           // -1: the library's default
  std::optional<float> presplit;  // AccelBuildOptions::presplit_budget (unset: chosen)
  std::optional<float> sbvh;      // AccelBuildOptions::spatial_split_budget (unset: chosen)
};

int run_trace_command(const std::string& mesh_path, const std::string& rays_path, unsigned threads,
                      const std::string& accel_name, const std::string& query, unsigned repeat,
                      const std::string& isa, const TuneOptions& tune) {
  const std::vector<Triangle> triangles = load_triangles(mesh_path);
  const std::vector<Ray> rays = read_ray_file(rays_path);
  std::printf("rays: %zu from %s\n", rays.size(), rays_path.c_str());
  AccelBuildOptions options;
  options.kind = *parse_accel_kind(accel_name);
  if (isa != "auto") options.max_isa = *parse_kernel_isa(isa);
  for (BvhBuildOptions* bvh : {&options.bvh, &options.wide}) {
    if (tune.leaf_size != 0) bvh->max_leaf_size = tune.leaf_size;
    if (tune.bins != 0) bvh->bin_count = tune.bins;
    if (tune.traversal_cost != 0.0f) bvh->traversal_cost = tune.traversal_cost;
  }
  if (tune.leaf_size != 0) options.octree.leaf_size = tune.leaf_size;
  if (tune.merge_limit >= 0)
    options.wide_merge_limit = static_cast<std::uint32_t>(tune.merge_limit);
  options.presplit_budget = tune.presplit;
  options.spatial_split_budget = tune.sbvh;
  const TriangleAccel accel = TriangleAccel::build(triangles, options);
  print_accel(accel);

  TraceChunk chunk;
  if (query == "any") {
    chunk = [&](std::size_t begin, std::size_t end, float* t) {
      for (std::size_t i = begin; i < end; ++i)
        t[i - begin] = accel.occluded(rays[i]) ? 0.0f : kInfinity;
    };
  } else {
    chunk = [&](std::size_t begin, std::size_t end, float* t) {
      for (std::size_t i = begin; i < end; ++i) {
        HitRecord hit;
        t[i - begin] = accel.closest(rays[i], hit) ? hit.t : kInfinity;
      }
    };
  }
  const TraceTiming timing = run_trace(rays.size(), threads, repeat, chunk);
  std::printf(
      "trace: %s, %u threads, best of %u: %.3f s wall, %.3f s CPU (%.3f Mrays per CPU-second)\n",
      query.c_str(), threads, repeat, timing.best_seconds, timing.best_cpu_seconds,
      static_cast<double>(rays.size()) / timing.best_cpu_seconds * 1e-6);
  print_result_line(timing);
  return 0;
}

int run_mesh(const std::string& shape, std::size_t triangles, TubeTessellation tubes,
             const std::string& out) {
  const IndexedMesh mesh = make_synthetic_mesh(*parse_synthetic_mesh(shape), triangles, tubes);
  write_binary_ply(out, mesh);
  std::printf("wrote %s: %zu triangles, %zu vertices\n", out.c_str(), mesh.triangle_count(),
              mesh.positions.size());
  return 0;
}

int run_load(const std::string& mesh_path, unsigned repeat) {
  double assimp_best = 1e300, direct_best = 1e300;
  std::size_t assimp_triangles = 0, direct_triangles = 0;
  for (unsigned r = 0; r < std::max(1u, repeat); ++r) {
    auto start = std::chrono::steady_clock::now();
    assimp_triangles = load_mesh_with_assimp(mesh_path).triangle_count();
    assimp_best = std::min(assimp_best, seconds_since(start));
    start = std::chrono::steady_clock::now();
    direct_triangles = load_binary_ply_direct(mesh_path).triangle_count();
    direct_best = std::min(direct_best, seconds_since(start));
  }
  std::printf("assimp (tessera::load_mesh_file): %.3f s, %zu triangles\n", assimp_best,
              assimp_triangles);
  std::printf("direct binary PLY read:           %.3f s, %zu triangles\n", direct_best,
              direct_triangles);
  std::printf("assimp_s=%.3f direct_s=%.3f ratio=%.1f\n", assimp_best, direct_best,
              assimp_best / direct_best);
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  spdlog::set_level(spdlog::level::warn);
  CLI::App app{"Tessera acceleration-structure benchmark"};
  app.require_subcommand(1);

  std::string mesh, out, kind = "primary", rays_path, accel = "wide", query = "closest",
                         isa = "auto", shape;
  std::uint32_t width = 1024, height = 1024;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency()), repeat = 3;
  std::size_t triangles = 1'000'000;

  auto* rays = app.add_subcommand("rays", "write a ray file of primary or diffuse rays for a mesh");
  rays->add_option("--mesh", mesh, "mesh file (any format assimp reads)")
      ->required()
      ->check(CLI::ExistingFile);
  rays->add_option("--kind", kind, "primary or diffuse")
      ->check(CLI::IsMember({"primary", "diffuse"}));
  rays->add_option("--width", width, "image width in pixels")->check(CLI::Range(1u, 16384u));
  rays->add_option("--height", height, "image height in pixels")->check(CLI::Range(1u, 16384u));
  rays->add_option("--out", out, "ray file to write")->required();

  auto* trace = app.add_subcommand("trace", "trace a ray file and print throughput");
  trace->add_option("--mesh", mesh, "mesh file")->required()->check(CLI::ExistingFile);
  trace->add_option("--rays", rays_path, "ray file")->required()->check(CLI::ExistingFile);
  trace->add_option("--threads", threads, "worker threads")->check(CLI::Range(1u, 1024u));
  trace->add_option("--accel", accel, "bvh, wide, octree, brute or auto")
      ->check(CLI::IsMember({"bvh", "wide", "octree", "brute", "auto"}));
  trace->add_option("--query", query, "closest or any")->check(CLI::IsMember({"closest", "any"}));
  trace->add_option("--repeat", repeat, "runs over all rays; the fastest counts")
      ->check(CLI::Range(1u, 1000u));
  TuneOptions tune;
  trace
      ->add_option("--leaf-size", tune.leaf_size,
                   "tuning: most triangles per BVH leaf / octree cell")
      ->check(CLI::Range(1u, 124u));
  trace
      ->add_option(
          "--merge", tune.merge_limit,
          "tuning: the wide BVH makes binary subtrees of at most this many triangles one leaf")
      ->check(CLI::Range(0, 124));
  trace
      ->add_option("--sbvh", tune.sbvh,
                   "wide BVH: spatial splits (instead of pre-splitting), up to this many extra "
                   "references per triangle (0: the binned build; default: chosen from the mesh)")
      ->check(CLI::Range(0.0f, 16.0f));
  trace->add_option("--bins", tune.bins, "tuning: SAH bins per axis")->check(CLI::Range(2u, 64u));
  trace
      ->add_option("--presplit", tune.presplit,
                   "wide BVH: pre-split poorly fitting triangles, this many extra references "
                   "per triangle at most (0: off; default: chosen from the mesh)")
      ->check(CLI::Range(0.0f, 16.0f));
  trace
      ->add_option("--traversal-cost", tune.traversal_cost,
                   "tuning: SAH node cost per triangle-block cost")
      ->check(CLI::Range(0.01f, 100.0f));
  trace
      ->add_option("--isa", isa,
                   "auto (the widest the processor runs) or at most sse2, avx2 or avx512")
      ->check(CLI::IsMember({"auto", "sse2", "avx2", "avx512"}));

  auto* mesh_cmd =
      app.add_subcommand("mesh", "write a deterministic synthetic benchmark mesh as PLY");
  mesh_cmd->add_option("--shape", shape, "knot, scatter, tubes (long thin) or uneven (sizes)")
      ->required()
      ->check(CLI::IsMember({"knot", "scatter", "tubes", "uneven"}));
  mesh_cmd->add_option("--triangles", triangles, "at least this many triangles")
      ->check(CLI::Range(1000, 50'000'000));
  TubeTessellation tubes;
  mesh_cmd->add_option("--strips", tubes.strips, "tubes: strips around each tube")
      ->check(CLI::Range(3u, 4096u));
  mesh_cmd->add_option("--rings", tubes.rings, "tubes: rings of strips along each tube")
      ->check(CLI::Range(1u, 4096u));
  mesh_cmd->add_option("--out", out, "PLY file to write")->required();

  auto* sizes_cmd =
      app.add_subcommand("sizes", "throughput of every structure on random soups of growing size");
  std::vector<std::uint32_t> sizes{1, 2, 4, 8, 16, 32, 64, 128, 256, 1024, 4096, 65536};
  std::uint32_t sweep_rays = 200000;
  sizes_cmd->add_option("--sizes", sizes, "triangle counts");
  sizes_cmd->add_option("--rays", sweep_rays, "rays per measurement")
      ->check(CLI::Range(1000u, 100000000u));
  sizes_cmd->add_option("--repeat", repeat, "runs; the fastest counts")
      ->check(CLI::Range(1u, 100u));

  auto* load = app.add_subcommand("load", "time assimp against a direct binary PLY read");
  load->add_option("--mesh", mesh, "binary little-endian PLY file")
      ->required()
      ->check(CLI::ExistingFile);
  load->add_option("--repeat", repeat, "loads of each kind; the fastest counts")
      ->check(CLI::Range(1u, 100u));

  auto* device_walk = app.add_subcommand(
      "device-walk",
      "the GPU layout's binary and compressed eight-wide BVH walks, scalar, on this CPU");
  device_walk->add_option("--mesh", mesh, "mesh file")->required()->check(CLI::ExistingFile);
  device_walk->add_option("--rays", rays_path, "ray file")->required()->check(CLI::ExistingFile);
  device_walk->add_option("--threads", threads, "worker threads")->check(CLI::Range(1u, 1024u));
  device_walk->add_option("--repeat", repeat, "runs over all rays; the fastest counts")
      ->check(CLI::Range(1u, 1000u));

#if defined(TESSERA_HAS_CUDA)
  int gpu_device = 0;
  auto* gpu_trace = app.add_subcommand(
      "gpu-trace", "closest hits on a CUDA device (compressed and binary walks) against the CPU");
  gpu_trace->add_option("--mesh", mesh, "mesh file")->required()->check(CLI::ExistingFile);
  gpu_trace->add_option("--rays", rays_path, "ray file")->required()->check(CLI::ExistingFile);
  gpu_trace->add_option("--threads", threads, "CPU worker threads")->check(CLI::Range(1u, 1024u));
  gpu_trace->add_option("--repeat", repeat, "runs of each; the fastest counts")
      ->check(CLI::Range(1u, 1000u));
  gpu_trace->add_option("--device", gpu_device, "CUDA device index")->check(CLI::Range(0, 63));
#endif

  // The pipeline-specialisation benchmark (bench/pipeline) shares this front end.
  tessera::bench::SpecialiseOptions specialise_options;
  auto* specialise = app.add_subcommand(
      "specialise",
      "specialised pipeline vs all features vs virtual dispatch, on procedural scenes");
  specialise->add_option("--width", specialise_options.width, "image width")
      ->check(CLI::Range(8u, 4096u));
  specialise->add_option("--height", specialise_options.height, "image height")
      ->check(CLI::Range(8u, 4096u));
  specialise->add_option("--spp", specialise_options.spp, "samples per pixel")
      ->check(CLI::Range(1u, 4096u));
  specialise
      ->add_option("--repeats", specialise_options.repeats,
                   "timed runs per renderer; the best counts")
      ->check(CLI::Range(1, 100));

  tessera::bench::ConvergeOptions converge_options;
  auto* converge = app.add_subcommand(
      "converge", "render at doubling spp and measure the error against a reference");
  converge->add_option("scene", converge_options.scene, "scene YAML file")->required();
  converge->add_option("--reference", converge_options.reference, "Tessera's reference EXR");
  // With --reference it still sets the peer's reference, which is always rendered.
  converge
      ->add_option("--reference-spp", converge_options.reference_spp,
                   "spp of the references rendered (Tessera's when no --reference is given)")
      ->check(CLI::Range(1u, 1u << 20));
  converge->add_option("--spp", converge_options.spp, "sample counts, e.g. 1,2,4,8")
      ->delimiter(',')
      ->check(CLI::Range(1u, 1u << 20));
  converge->add_option("--width", converge_options.width, "override the scene's width")
      ->check(CLI::Range(1u, 16384u));
  converge->add_option("--height", converge_options.height, "override the scene's height")
      ->check(CLI::Range(1u, 16384u));
  converge->add_option("--max-depth", converge_options.max_depth, "override the scene's depth")
      ->check(CLI::Range(1u, 64u));
  converge->add_option("--threads", converge_options.threads, "render threads (0: all)");
  converge->add_option("--target", converge_options.target, "relMSE to estimate the time of")
      ->check(CLI::PositiveNumber);
  converge->add_option("--csv", converge_options.csv, "write spp, seconds, rmse, relmse");
  converge->add_option("--plot", converge_options.plot, "write a log-log plot (PNG)");
  converge->add_option("--save-reference", converge_options.save_reference,
                       "write the rendered reference (EXR)");
  converge
      ->add_option("--peer", converge_options.peer,
                   "also measure this renderer against its own reference (cycles)")
      ->check(CLI::IsMember({"cycles"}));
  converge->add_option("--blender", converge_options.blender, "Blender executable (--peer cycles)");
  converge->add_option("--peer-script", converge_options.peer_script,
                       "the peer's render script (default: bench/peers/cycles_render.py)");
  converge->add_option("--peer-dir", converge_options.peer_dir,
                       "folder for the exported scene, the peer's EXRs and its log "
                       "(default: beside --csv)");
  converge->add_option("--sampler", converge_options.sampler, "Tessera's sampler (ablation)")
      ->check(CLI::IsMember({"sobol", "independent"}));
  converge
      ->add_option("--light-strategy", converge_options.light_strategy,
                   "Tessera's direct-light estimator (ablation)")
      ->check(CLI::IsMember({"mis", "light", "bsdf"}));
  converge->add_flag("!--no-light-tree", converge_options.light_tree,
                     "Tessera picks lights by power alone (ablation)");
  converge
      ->add_option("--adaptive", converge_options.adaptive_targets,
                   "also render with adaptive sampling at these render.target_error values "
                   "(comma-separated)")
      ->delimiter(',')
      ->check(CLI::Range(1e-4, 1.0));
  converge
      ->add_option("--adaptive-max-spp", converge_options.adaptive_max_spp,
                   "the most samples a pixel takes under --adaptive (default: 4 x the largest "
                   "--spp)")
      ->check(CLI::Range(1u, 1u << 20));
  converge
      ->add_option("--device", converge_options.device,
                   "where the series render: cpu, or gpu (CUDA device 0; the reference still "
                   "renders on the CPU)")
      ->check(CLI::IsMember({"cpu", "gpu"}));
  converge->add_flag("--denoise", converge_options.denoise,
                     "also measure the denoised render at each --spp (denoiser time included)");
  converge->add_option("--export-json", converge_options.export_json,
                       "write the scene as the peer reads it (JSON) and stop");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*converge) return tessera::bench::run_converge(converge_options);
    if (*specialise) return tessera::bench::run_specialise(specialise_options);
    if (*rays) return run_rays(mesh, kind, width, height, out);
    if (*trace) return run_trace_command(mesh, rays_path, threads, accel, query, repeat, isa, tune);
    if (*mesh_cmd) return run_mesh(shape, triangles, tubes, out);
    if (*load) return run_load(mesh, repeat);
    if (*device_walk) return run_device_walk(mesh, rays_path, threads, repeat);
#if defined(TESSERA_HAS_CUDA)
    if (*gpu_trace) return run_gpu_trace(mesh, rays_path, threads, repeat, gpu_device);
#endif
    if (*sizes_cmd) {
      run_size_sweep(sizes, sweep_rays, repeat);
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
