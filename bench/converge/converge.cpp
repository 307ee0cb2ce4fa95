// tessera-bench converge: time against error at doubling sample counts, optionally beside
// Blender Cycles (bench/peers/cycles_render.py) measured the same way.
#include "converge.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "scene_export.hpp"
#include "tessera/image/denoise.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/image/image_error.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"
#if defined(TESSERA_HAS_CUDA)
#include "tessera/gpu/gpu_renderer.hpp"
#endif

#ifndef TESSERA_SOURCE_DIR
#define TESSERA_SOURCE_DIR "."
#endif

namespace tessera::bench {
namespace {

struct Render {
  RgbaImage image;
  double seconds = 0.0;  // the render alone: what the curves use
  double wall = 0.0;     // with the peer's per-render scene synchronisation
};

// Calls render_tile(tile, scratch) once for every tile, on `threads` threads, each with its
// own Scratch (a tile buffer, kept between the thread's tiles).
template <typename Scratch, typename RenderTile>
void for_each_tile(const std::vector<TileRect>& tiles, unsigned threads, RenderTile render_tile) {
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    Scratch scratch;
    for (std::size_t t = next++; t < tiles.size(); t = next++) render_tile(tiles[t], scratch);
  };
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
  work();
  for (auto& thread : pool) thread.join();
}

// Every tile on `threads` threads: the same image as any other tiling or thread count. With
// `gpu`, the whole image as one tile on CUDA device 0 instead (the scene's upload, like its
// preparation, is not timed).
Render render(const SceneDescription& description, std::uint32_t spp, unsigned threads,
              bool light_tree, double target_error = 0.0, bool gpu = false) {
  SceneDescription scene = description;
  scene.render.samples_per_pixel = spp;
  scene.render.target_error = target_error;
  scene.render.min_samples_per_pixel = std::min(scene.render.min_samples_per_pixel, spp);
  const auto prepared = PreparedScene::build(scene, PrepareOptions{.light_tree = light_tree});
  const RenderSettings& s = prepared->settings();
  Render out;
  out.image = RgbaImage{s.width, s.height, std::vector<float>(std::size_t{s.width} * s.height * 4)};
  if (gpu) {
#if defined(TESSERA_HAS_CUDA)
    gpu::TileRenderer renderer(0, prepared);
    const auto start = std::chrono::steady_clock::now();
    renderer.render_tile(TileRect{0, 0, 0, s.width, s.height}, out.image.pixels);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.wall = out.seconds;
    return out;
#else
    throw std::runtime_error("this tessera-bench was built without the GPU backend");
#endif
  }
  const std::vector<TileRect> tiles = make_tiles(s.width, s.height, s.tile_size);
  const auto start = std::chrono::steady_clock::now();
  for_each_tile<std::vector<float>>(
      tiles, threads, [&](const TileRect& tile, std::vector<float>& buffer) {
        buffer.resize(tile.pixel_count() * 4);
        prepared->render_tile(tile, buffer);
        for (std::uint32_t row = 0; row < tile.height; ++row)
          std::copy_n(
              buffer.begin() + std::ptrdiff_t{row} * tile.width * 4, tile.width * 4,
              out.image.pixels.begin() + (std::ptrdiff_t{tile.y + row} * s.width + tile.x) * 4);
      });
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.wall = out.seconds;
  return out;
}

// render() with the denoiser's guides, then the denoiser; the time includes both.
Render render_denoised(const SceneDescription& description, std::uint32_t spp, unsigned threads,
                       bool light_tree) {
  SceneDescription scene = description;
  scene.render.samples_per_pixel = spp;
  scene.render.aovs = kAovAlbedo | kAovNormal | kAovVariance;
  const auto prepared = PreparedScene::build(scene, PrepareOptions{.light_tree = light_tree});
  const RenderSettings& s = prepared->settings();
  const std::size_t floats = std::size_t{s.width} * s.height * 3;
  std::vector<float> beauty(floats), albedo(floats), normal(floats), variance(floats);
  const std::vector<TileRect> tiles = make_tiles(s.width, s.height, s.tile_size);
  const auto start = std::chrono::steady_clock::now();
  for_each_tile<TilePasses>(tiles, threads, [&](const TileRect& tile, TilePasses& passes) {
    prepared->render_tile(tile, passes);
    const std::pair<const std::vector<float>*, std::vector<float>*> planes[] = {
        {&passes.beauty, &beauty},
        {&passes.aovs[0], &albedo},
        {&passes.aovs[1], &normal},
        {&passes.aovs[4], &variance}};
    for (const auto& [from, to] : planes)
      for (std::uint32_t y = 0; y < tile.height; ++y)
        for (std::uint32_t x = 0; x < tile.width; ++x)
          for (int c = 0; c < 3; ++c)
            (*to)[((std::size_t{tile.y} + y) * s.width + tile.x + x) * 3 + c] =
                (*from)[(std::size_t{y} * tile.width + x) * 4 + c];
  });
  const std::vector<float> clean = denoise({s.width, s.height, beauty, albedo, normal, variance});
  Render out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.wall = out.seconds;
  out.image =
      RgbaImage{s.width, s.height, std::vector<float>(std::size_t{s.width} * s.height * 4, 1.0f)};
  for (std::size_t p = 0; p < std::size_t{s.width} * s.height; ++p)
    for (int c = 0; c < 3; ++c) out.image.pixels[p * 4 + c] = clean[p * 3 + c];
  return out;
}

struct Sample {
  std::uint32_t spp = 0;      // the most a pixel takes, under adaptive sampling
  double target_error = 0.0;  // adaptive sampling's, 0 when off
  double seconds = 0.0;
  double wall = 0.0;
  ImageError error;
};

// One renderer's curve: its renders and what they say about reaching the target.
struct Series {
  std::string name;
  std::vector<Sample> samples;
  std::optional<TimeToError> at_target;
  std::array<float, 3> colour{};

  std::vector<ErrorPoint> points() const {
    std::vector<ErrorPoint> out;
    for (const Sample& s : samples) out.push_back({s.seconds, s.error.rel_mse});
    return out;
  }
};

// 5x7 glyphs of the letters the legend needs, one row per byte, bit 4 leftmost: the plot
// has no font library to draw with.
const std::map<char, std::array<std::uint8_t, 7>>& glyphs() {
  static const std::map<char, std::array<std::uint8_t, 7>> table{
      {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
      {'C', {0x0F, 0x10, 0x10, 0x10, 0x10, 0x10, 0x0F}},
      {'D', {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E}},
      {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
      {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
      {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
      {'N', {0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11}},
      {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
      {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
      {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
      {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
      {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
      {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
      {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}},
  };
  return table;
}

// A log-log plot of relMSE against seconds: grid lines per decade, each series as a
// polyline in its colour with a dot per render, the target as a horizontal green line, and
// a legend naming the series in their colours.
void write_plot(const std::string& path, const std::vector<Series>& all, double target) {
  constexpr std::uint32_t kWidth = 640, kHeight = 420, kMargin = 40;
  RgbaImage image{kWidth, kHeight, std::vector<float>(std::size_t{kWidth} * kHeight * 4, 1.0f)};
  double t0 = 1e300, t1 = 0, e0 = target, e1 = target;
  // Log axes: a render identical to its reference (relMSE 0) has no place on them.
  std::vector<std::vector<Sample>> drawn;
  for (const Series& series : all) {
    auto& kept = drawn.emplace_back();
    for (const Sample& p : series.samples)
      if (p.seconds > 0.0 && p.error.rel_mse > 0.0) kept.push_back(p);
  }
  for (const auto& kept : drawn)
    for (const Sample& p : kept) {
      t0 = std::min(t0, p.seconds);
      t1 = std::max(t1, p.seconds);
      e0 = std::min(e0, p.error.rel_mse);
      e1 = std::max(e1, p.error.rel_mse);
    }
  const double lt0 = std::floor(std::log10(t0)), lt1 = std::ceil(std::log10(t1 * 1.0001));
  const double le0 = std::floor(std::log10(e0)), le1 = std::ceil(std::log10(e1 * 1.0001));
  const auto px = [&](double t) {
    return kMargin + (std::log10(t) - lt0) / std::max(lt1 - lt0, 1.0) * (kWidth - 2 * kMargin);
  };
  const auto py = [&](double e) {
    return kHeight - kMargin -
           (std::log10(e) - le0) / std::max(le1 - le0, 1.0) * (kHeight - 2 * kMargin);
  };
  const auto dot = [&](double x, double y, std::array<float, 3> c) {
    if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) return;
    float* p = &image.pixels[(std::size_t(y) * kWidth + std::size_t(x)) * 4];
    std::copy(c.begin(), c.end(), p);
  };
  const auto line = [&](double xa, double ya, double xb, double yb, std::array<float, 3> c) {
    const int steps = static_cast<int>(std::max(std::abs(xb - xa), std::abs(yb - ya))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double f = static_cast<double>(i) / steps;
      dot(xa + f * (xb - xa), ya + f * (yb - ya), c);
    }
  };
  const auto text = [&](double x, double y, const std::string& s, std::array<float, 3> c) {
    constexpr int kScale = 2;
    for (char ch : s) {
      if (const auto g = glyphs().find(ch); g != glyphs().end())
        for (int row = 0; row < 7; ++row)
          for (int col = 0; col < 5; ++col)
            if (g->second[row] & (0x10 >> col))
              for (int sy = 0; sy < kScale; ++sy)
                for (int sx = 0; sx < kScale; ++sx)
                  dot(x + col * kScale + sx, y + row * kScale + sy, c);
      x += 6 * kScale;
    }
  };
  const std::array<float, 3> grey{0.8f, 0.8f, 0.8f}, green{0.2f, 0.6f, 0.2f};
  for (double d = lt0; d <= lt1; d += 1.0)
    line(px(std::pow(10.0, d)), kMargin, px(std::pow(10.0, d)), kHeight - kMargin, grey);
  for (double d = le0; d <= le1; d += 1.0)
    line(kMargin, py(std::pow(10.0, d)), kWidth - kMargin, py(std::pow(10.0, d)), grey);
  line(kMargin, py(target), kWidth - kMargin, py(target), green);
  double legend_y = kMargin + 6;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Series& series = all[k];
    const auto& s = drawn[k];
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double x = px(s[i].seconds), y = py(s[i].error.rel_mse);
      if (i > 0) line(px(s[i - 1].seconds), py(s[i - 1].error.rel_mse), x, y, series.colour);
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) dot(x + dx, y + dy, series.colour);
    }
    std::string label = series.name;
    std::transform(label.begin(), label.end(), label.begin(),
                   [](char c) { return static_cast<char>(std::toupper(c)); });
    const double lx = kWidth - kMargin - 130.0;
    for (int w = -1; w <= 1; ++w)
      line(lx, legend_y + 7 + w, lx + 24, legend_y + 7 + w, series.colour);
    text(lx + 32, legend_y, label, series.colour);
    legend_y += 22;
  }
  write_image(path, image);
}

void print_series(const Series& series, double target) {
  std::printf("%s:\n%8s %8s %10s %10s %12s %12s %10s %10s\n", series.name.c_str(), "spp", "target",
              "seconds", "wall", "rmse", "relmse", "mean", "ref mean");
  for (const Sample& s : series.samples)
    std::printf("%8u %8.4g %10.3f %10.3f %12.5g %12.5g %10.5f %10.5f\n", s.spp, s.target_error,
                s.seconds, s.wall, s.error.rmse, s.error.rel_mse, s.error.mean,
                s.error.reference_mean);
  if (const auto& at = series.at_target) {
    std::printf("%s time to relMSE %g: %.3g s (%s; relMSE ~ time^%.2f)\n", series.name.c_str(),
                target, at->seconds, at->extrapolated ? "extrapolated" : "measured", at->slope);
    if (at->extrapolated)
      std::printf("%s time to relMSE %g at slope -1 from the last render: %.3g s\n",
                  series.name.c_str(), target, at->seconds_at_unit_slope);
    if (at->shallow)
      std::printf(
          "%s: warning: relMSE fell only as time^%.2f over the later renders, where an "
          "unbiased renderer's falls as time^-1: fireflies not averaged yet, bias, or a "
          "reference too noisy for this error. The extrapolated time is unreliable; add larger "
          "counts to --spp (and --reference-spp) to measure it\n",
          series.name.c_str(), at->slope);
  } else {
    std::printf("%s time to relMSE %g: not reached and not falling\n", series.name.c_str(), target);
  }
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  out += '\'';
  return out;
}

struct PeerRenders {
  std::map<std::uint32_t, Render> series;  // by spp
  Render reference;
};

// Runs Blender once for every sample count and the reference (start-up paid once) and
// reads back each render's time and image. Blender's own output goes to DIR/blender.log;
// the script's warnings are echoed.
PeerRenders run_cycles(const ConvergeOptions& options, const SceneDescription& scene,
                       unsigned threads, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path json = dir / "scene.json";
  write_scene_json(scene, json);
  const std::string script = options.peer_script.empty()
                                 ? std::string(TESSERA_SOURCE_DIR) + "/bench/peers/cycles_render.py"
                                 : options.peer_script;
  std::string list;
  for (std::uint32_t n : options.spp) {
    if (!list.empty()) list += ',';
    list += std::to_string(n);
  }
  const std::filesystem::path log = dir / "blender.log";
  const std::string command = quoted(options.blender) + " -b --factory-startup --python " +
                              quoted(script) + " -- --scene " + quoted(json.string()) + " --out " +
                              quoted(dir.string()) + " --spp " + list + " --reference-spp " +
                              std::to_string(options.reference_spp) + " --threads " +
                              std::to_string(threads) + " > " + quoted(log.string()) + " 2>&1";
  std::printf("cycles: %s\n", command.c_str());
  std::fflush(stdout);
  const int status = std::system(command.c_str());

  PeerRenders out;
  bool have_reference = false;
  std::ifstream in(log);
  for (std::string text; std::getline(in, text);) {
    if (text.rfind("cycles_render.py:", 0) == 0) std::printf("%s\n", text.c_str());
    if (text.rfind("TESSERA_PEER ", 0) != 0) continue;
    std::istringstream fields(text.substr(13));
    std::uint32_t n = 0;
    double wall = 0.0, sync = 0.0;
    bool reference = false;
    std::string exr;
    for (std::string field; fields >> field;) {
      const auto eq = field.find('=');
      const std::string key = field.substr(0, eq), value = field.substr(eq + 1);
      if (key == "spp") n = static_cast<std::uint32_t>(std::stoul(value));
      if (key == "wall") wall = std::stod(value);
      if (key == "sync") sync = std::stod(value);
      if (key == "reference") reference = value == "1";
      if (key == "exr") exr = value;
    }
    // Cycles reports synchronisation in 10 ms steps, so a tiny render can come out at or
    // below zero; 1 ms keeps it on the log axes without pretending to more precision.
    Render r{read_image(exr), std::max(wall - sync, 1e-3), wall};
    if (reference) {
      out.reference = std::move(r);
      have_reference = true;
    } else {
      out.series[n] = std::move(r);
    }
  }
  const auto failed = [&](const std::string& what) {
    return std::runtime_error("Blender did not render " + what + " (exit status " +
                              std::to_string(status) + "); see " + log.string());
  };
  for (std::uint32_t n : options.spp)
    if (!out.series.contains(n)) throw failed(std::to_string(n) + " spp");
  if (!have_reference) throw failed("the reference");
  return out;
}

}  // namespace

int run_converge(const ConvergeOptions& options) {
  SceneDescription scene = load_scene_file(options.scene).scene;
  if (options.width != 0) scene.render.width = options.width;
  if (options.height != 0) scene.render.height = options.height;
  if (options.max_depth != 0) scene.render.max_depth = options.max_depth;
  // Estimator switches for ablations: they change Tessera's renders, not the peer's.
  if (!options.sampler.empty()) {
    const auto kind = sampler_from_string(options.sampler);
    if (!kind) throw std::runtime_error("unknown sampler '" + options.sampler + "'");
    scene.render.sampler = *kind;
  }
  if (!options.light_strategy.empty()) {
    const auto strategy = light_strategy_from_string(options.light_strategy);
    if (!strategy)
      throw std::runtime_error("unknown light strategy '" + options.light_strategy + "'");
    scene.render.light_strategy = *strategy;
  }
  if (!options.export_json.empty()) {
    write_scene_json(scene, options.export_json);
    std::printf("scene written to %s\n", options.export_json.c_str());
    return 0;
  }
  if (!options.peer.empty() && options.peer != "cycles")
    throw std::runtime_error("unknown peer '" + options.peer + "' (known: cycles)");
  const unsigned threads =
      options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  if (options.device != "cpu" && options.device != "gpu")
    throw std::runtime_error("unknown device '" + options.device + "' (cpu or gpu)");
  const bool gpu = options.device == "gpu";
  if (gpu && options.denoise)
    throw std::runtime_error("--denoise needs AOVs, which the GPU path does not render");
#if defined(TESSERA_HAS_CUDA)
  if (gpu && gpu::list_devices().empty())
    throw std::runtime_error("--device gpu, but this machine has no CUDA device");
#else
  if (gpu) throw std::runtime_error("this tessera-bench was built without the GPU backend");
#endif

  RgbaImage reference;
  if (!options.reference.empty()) {
    reference = read_image(options.reference);
    std::printf("reference: %s\n", options.reference.c_str());
  } else {
    // Another seed: with the series' seed, an n-spp render would be the first n samples of
    // the reference, and its error would look smaller than it is.
    SceneDescription reference_scene = scene;
    ++reference_scene.render.seed;
    const Render r = render(reference_scene, options.reference_spp, threads, options.light_tree);
    reference = r.image;
    std::printf("reference: rendered at %u spp in %.2f s\n", options.reference_spp, r.seconds);
    if (!options.save_reference.empty()) write_image(options.save_reference, reference);
  }
  if (reference.width != scene.render.width || reference.height != scene.render.height)
    throw std::runtime_error("the reference is " + std::to_string(reference.width) + "x" +
                             std::to_string(reference.height) + ", the render " +
                             std::to_string(scene.render.width) + "x" +
                             std::to_string(scene.render.height));

  std::printf("scene: %s, %ux%u, max depth %u, %u threads\n", options.scene.c_str(),
              scene.render.width, scene.render.height, scene.render.max_depth, threads);
  std::vector<Series> all;
  all.reserve(4);  // `tessera`, `adaptive`, `denoised` and `cycles` are references into it
  Series& tessera = all.emplace_back(Series{"tessera", {}, {}, {0.1f, 0.2f, 0.8f}});
  for (std::uint32_t spp : options.spp) {
    const Render r = render(scene, spp, threads, options.light_tree, 0.0, gpu);
    tessera.samples.push_back({spp, 0.0, r.seconds, r.wall, image_error(r.image, reference)});
  }
  tessera.at_target = time_to_error(tessera.points(), options.target);
  print_series(tessera, options.target);
  if (!options.adaptive_targets.empty()) {
    Series& adaptive = all.emplace_back(Series{"adaptive", {}, {}, {0.1f, 0.6f, 0.3f}});
    const std::uint32_t cap = options.adaptive_max_spp != 0
                                  ? options.adaptive_max_spp
                                  : 4 * *std::max_element(options.spp.begin(), options.spp.end());
    for (double target : options.adaptive_targets) {
      const Render r = render(scene, cap, threads, options.light_tree, target, gpu);
      adaptive.samples.push_back({cap, target, r.seconds, r.wall, image_error(r.image, reference)});
    }
    adaptive.at_target = time_to_error(adaptive.points(), options.target);
    print_series(adaptive, options.target);
    if (tessera.at_target && adaptive.at_target)
      std::printf("time to relMSE %g: plain / adaptive = %.3g\n", options.target,
                  tessera.at_target->seconds / adaptive.at_target->seconds);
  }

  if (options.denoise) {
    Series& denoised = all.emplace_back(Series{"denoised", {}, {}, {0.6f, 0.1f, 0.6f}});
    for (std::uint32_t spp : options.spp) {
      const Render r = render_denoised(scene, spp, threads, options.light_tree);
      denoised.samples.push_back({spp, 0.0, r.seconds, r.wall, image_error(r.image, reference)});
    }
    denoised.at_target = time_to_error(denoised.points(), options.target);
    print_series(denoised, options.target);
    if (tessera.at_target && denoised.at_target)
      std::printf("time to relMSE %g: plain / denoised = %.3g\n", options.target,
                  tessera.at_target->seconds / denoised.at_target->seconds);
  }

  std::optional<ImageError> references;  // Tessera's reference against Cycles'
  if (options.peer == "cycles") {
    // Cycles is measured against its own reference, so each curve shows its renderer's
    // convergence, not the bias between the two; the references are compared separately.
    std::filesystem::path dir = options.peer_dir;
    if (dir.empty())
      dir = options.csv.empty()
                ? std::filesystem::temp_directory_path() / "tessera-converge-cycles"
                : std::filesystem::path(options.csv).replace_extension("") += "_cycles";
    const PeerRenders renders = run_cycles(options, scene, threads, dir);
    const Render& cycles_reference = renders.reference;
    std::printf(
        "cycles reference: %u spp in %.2f s (%s)\n", options.reference_spp,
        cycles_reference.seconds,
        (dir / ("cycles_reference_" + std::to_string(options.reference_spp) + ".exr")).c_str());
    Series& cycles = all.emplace_back(Series{"cycles", {}, {}, {0.9f, 0.45f, 0.05f}});
    for (std::uint32_t n : options.spp) {
      const Render& r = renders.series.at(n);
      cycles.samples.push_back(
          {n, 0.0, r.seconds, r.wall, image_error(r.image, cycles_reference.image)});
    }
    cycles.at_target = time_to_error(cycles.points(), options.target);
    print_series(cycles, options.target);
    if (tessera.at_target && cycles.at_target) {
      std::printf("time to relMSE %g: Cycles / Tessera = %.3g\n", options.target,
                  cycles.at_target->seconds / tessera.at_target->seconds);
      if (tessera.at_target->extrapolated || cycles.at_target->extrapolated)
        std::printf(
            "time to relMSE %g at slope -1 from the last renders: Cycles / Tessera = %.3g\n",
            options.target,
            cycles.at_target->seconds_at_unit_slope / tessera.at_target->seconds_at_unit_slope);
    }
    references = image_error(reference, cycles_reference.image);
    std::printf(
        "references: Tessera mean %.5f, Cycles mean %.5f (Tessera %+.2f%%), relMSE of Tessera's "
        "against Cycles' %.4g\n",
        references->mean, references->reference_mean,
        100.0 * (references->mean / references->reference_mean - 1.0), references->rel_mse);
  }

  // One line with every figure, for scripts (bench/converge/run_suite.sh).
  const auto time_of = [](const Series* s) {
    return s && s->at_target ? s->at_target->seconds : std::nan("");
  };
  const auto unit_slope_time_of = [](const Series* s) {
    return s && s->at_target ? s->at_target->seconds_at_unit_slope : std::nan("");
  };
  const auto slope_of = [](const Series* s) {
    return s && s->at_target ? s->at_target->slope : std::nan("");
  };
  const auto shallow_of = [](const Series* s) {
    return s && s->at_target && s->at_target->shallow ? 1 : 0;
  };
  const Series* cycles = all.back().name == "cycles" ? &all.back() : nullptr;
  const Series *adaptive = nullptr, *denoised = nullptr;
  for (const Series& series : all) {
    if (series.name == "adaptive") adaptive = &series;
    if (series.name == "denoised") denoised = &series;
  }
  std::printf(
      "summary: tessera_time=%.6g cycles_time=%.6g ratio=%.6g tessera_ref_mean=%.6g "
      "cycles_ref_mean=%.6g ref_relmse=%.6g adaptive_time=%.6g denoised_time=%.6g\n",
      time_of(&tessera), time_of(cycles), time_of(cycles) / time_of(&tessera),
      image_error(reference, reference).mean,
      references ? references->reference_mean : std::nan(""),
      references ? references->rel_mse : std::nan(""), time_of(adaptive), time_of(denoised));
  // Separate from the line above, whose fields scripts read by position as well as by name.
  std::printf(
      "summary_slopes: tessera_slope=%.3g cycles_slope=%.3g tessera_shallow=%d cycles_shallow=%d "
      "tessera_time_unit_slope=%.6g cycles_time_unit_slope=%.6g ratio_unit_slope=%.6g\n",
      slope_of(&tessera), slope_of(cycles), shallow_of(&tessera), shallow_of(cycles),
      unit_slope_time_of(&tessera), unit_slope_time_of(cycles),
      unit_slope_time_of(cycles) / unit_slope_time_of(&tessera));

  if (!options.csv.empty()) {
    std::ofstream csv(options.csv);
    csv << "renderer,spp,target_error,seconds,wall_seconds,rmse,relmse,mean,reference_mean\n";
    for (const Series& series : all)
      for (const Sample& s : series.samples)
        csv << series.name << ',' << s.spp << ',' << s.target_error << ',' << s.seconds << ','
            << s.wall << ',' << s.error.rmse << ',' << s.error.rel_mse << ',' << s.error.mean << ','
            << s.error.reference_mean << '\n';
  }
  if (!options.plot.empty()) write_plot(options.plot, all, options.target);
  return 0;
}

}  // namespace tessera::bench
