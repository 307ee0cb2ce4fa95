// tessera-bench converge: time against error at doubling sample counts.
#include "converge.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "tessera/image/exr.hpp"
#include "tessera/image/image_error.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera::bench {
namespace {

struct Render {
  RgbaImage image;
  double seconds = 0.0;
};

// Every tile on `threads` threads: the same image as any other tiling or thread count.
Render render(const SceneDescription& description, std::uint32_t spp, unsigned threads) {
  SceneDescription scene = description;
  scene.render.samples_per_pixel = spp;
  const auto prepared = PreparedScene::build(scene);
  const RenderSettings& s = prepared->settings();
  Render out;
  out.image = RgbaImage{s.width, s.height, std::vector<float>(std::size_t{s.width} * s.height * 4)};
  const std::vector<TileRect> tiles = make_tiles(s.width, s.height, s.tile_size);
  std::atomic<std::size_t> next{0};
  const auto start = std::chrono::steady_clock::now();
  const auto work = [&] {
    std::vector<float> buffer;
    for (std::size_t t = next++; t < tiles.size(); t = next++) {
      const TileRect& tile = tiles[t];
      buffer.resize(tile.pixel_count() * 4);
      prepared->render_tile(tile, buffer);
      for (std::uint32_t row = 0; row < tile.height; ++row)
        std::copy_n(
            buffer.begin() + std::ptrdiff_t{row} * tile.width * 4, tile.width * 4,
            out.image.pixels.begin() + (std::ptrdiff_t{tile.y + row} * s.width + tile.x) * 4);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
  work();
  for (auto& thread : pool) thread.join();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

// A log-log plot of relMSE against seconds: grid lines per decade, the series as a
// polyline with a dot per render, the target as a horizontal line.
void write_plot(const std::string& path, const std::vector<ErrorPoint>& series, double target) {
  constexpr std::uint32_t kWidth = 640, kHeight = 420, kMargin = 40;
  RgbaImage image{kWidth, kHeight, std::vector<float>(std::size_t{kWidth} * kHeight * 4, 1.0f)};
  double t0 = 1e300, t1 = 0, e0 = target, e1 = target;
  for (const ErrorPoint& p : series) {
    t0 = std::min(t0, p.seconds);
    t1 = std::max(t1, p.seconds);
    e0 = std::min(e0, p.rel_mse);
    e1 = std::max(e1, p.rel_mse);
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
  const auto dot = [&](double x, double y, float r, float g, float b) {
    if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) return;
    float* p = &image.pixels[(std::size_t(y) * kWidth + std::size_t(x)) * 4];
    p[0] = r;
    p[1] = g;
    p[2] = b;
  };
  const auto line = [&](double xa, double ya, double xb, double yb, float r, float g, float b) {
    const int steps = static_cast<int>(std::max(std::abs(xb - xa), std::abs(yb - ya))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double f = static_cast<double>(i) / steps;
      dot(xa + f * (xb - xa), ya + f * (yb - ya), r, g, b);
    }
  };
  for (double d = lt0; d <= lt1; d += 1.0)
    line(px(std::pow(10.0, d)), kMargin, px(std::pow(10.0, d)), kHeight - kMargin, 0.8f, 0.8f,
         0.8f);
  for (double d = le0; d <= le1; d += 1.0)
    line(kMargin, py(std::pow(10.0, d)), kWidth - kMargin, py(std::pow(10.0, d)), 0.8f, 0.8f, 0.8f);
  line(kMargin, py(target), kWidth - kMargin, py(target), 0.2f, 0.6f, 0.2f);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const double x = px(series[i].seconds), y = py(series[i].rel_mse);
    if (i > 0) line(px(series[i - 1].seconds), py(series[i - 1].rel_mse), x, y, 0.1f, 0.2f, 0.8f);
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) dot(x + dx, y + dy, 0.8f, 0.1f, 0.1f);
  }
  write_image(path, image);
}

}  // namespace

int run_converge(const ConvergeOptions& options) {
  SceneDescription scene = load_scene_file(options.scene).scene;
  if (options.width != 0) scene.render.width = options.width;
  if (options.height != 0) scene.render.height = options.height;
  if (options.max_depth != 0) scene.render.max_depth = options.max_depth;
  const unsigned threads =
      options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());

  RgbaImage reference;
  if (!options.reference.empty()) {
    reference = read_image(options.reference);
    std::printf("reference: %s\n", options.reference.c_str());
  } else {
    const Render r = render(scene, options.reference_spp, threads);
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
  std::printf("%8s %10s %12s %12s %10s %10s\n", "spp", "seconds", "rmse", "relmse", "mean",
              "ref mean");
  std::ofstream csv;
  if (!options.csv.empty()) {
    csv.open(options.csv);
    csv << "spp,seconds,rmse,relmse,mean,reference_mean\n";
  }
  std::vector<ErrorPoint> series;
  for (std::uint32_t spp : options.spp) {
    const Render r = render(scene, spp, threads);
    const ImageError e = image_error(r.image, reference);
    series.push_back({r.seconds, e.rel_mse});
    std::printf("%8u %10.3f %12.5g %12.5g %10.5f %10.5f\n", spp, r.seconds, e.rmse, e.rel_mse,
                e.mean, e.reference_mean);
    if (csv)
      csv << spp << ',' << r.seconds << ',' << e.rmse << ',' << e.rel_mse << ',' << e.mean << ','
          << e.reference_mean << '\n';
  }
  if (const auto at = time_to_error(series, options.target))
    std::printf("time to relMSE %g: %.3g s (%s; relMSE ~ time^%.2f)\n", options.target, at->seconds,
                at->extrapolated ? "extrapolated" : "measured", at->slope);
  else
    std::printf("time to relMSE %g: not reached and not falling\n", options.target);
  if (!options.plot.empty()) write_plot(options.plot, series, options.target);
  return 0;
}

}  // namespace tessera::bench
