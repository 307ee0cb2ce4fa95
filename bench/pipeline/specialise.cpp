// `tessera-bench specialise`: renders procedural scenes three ways — the specialisation
// the renderer picks, the same pipeline compiled with every feature on, and a conventional
// virtual-dispatch path tracer (virtual_path_tracer.cpp) — on one thread, and reports the
// speedups. All three consume random numbers identically, so their images must agree;
// the tool checks that before timing.
#include "specialise.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>

#include "bench_scenes.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "virtual_path_tracer.hpp"

namespace tessera::bench {

namespace {

using TileRenderer = std::function<void(const TileRect&, std::span<float>)>;

std::vector<float> render_all(const RenderSettings& s, const TileRenderer& render) {
  std::vector<float> image(static_cast<std::size_t>(s.width) * s.height * 4);
  std::vector<float> tile_buffer;
  for (const TileRect& tile : make_tiles(s.width, s.height, s.tile_size)) {
    tile_buffer.resize(tile.pixel_count() * 4);
    render(tile, tile_buffer);
    for (std::uint32_t row = 0; row < tile.height; ++row)
      std::copy_n(
          tile_buffer.begin() + static_cast<std::ptrdiff_t>(row) * tile.width * 4, tile.width * 4,
          image.begin() + (static_cast<std::ptrdiff_t>(tile.y + row) * s.width + tile.x) * 4);
  }
  return image;
}

// Best of `repeats` wall times, in seconds.
double time_render(const RenderSettings& s, const TileRenderer& render, int repeats) {
  double best = 1e30;
  for (int i = 0; i < repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    render_all(s, render);
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

double max_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::fabs(a[i] - b[i])));
  return worst;
}

}  // namespace

// The benchmark scenes with the options' sampler.
static std::vector<NamedScene> scenes_for(const SpecialiseOptions& options) {
  std::vector<NamedScene> scenes =
      specialisation_scenes(options.width, options.height, options.spp);
  const auto sampler = sampler_from_string(options.sampler);
  if (!sampler) throw std::invalid_argument("unknown sampler " + options.sampler);
  for (NamedScene& named : scenes) named.scene.render.sampler = *sampler;
  return scenes;
}

int run_specialise(const SpecialiseOptions& options) {
  if (!options.only_renderer.empty()) {
    for (const NamedScene& named : scenes_for(options)) {
      if (named.name != options.only_scene) continue;
      if (options.only_renderer == "virtual") {
        const VirtualPathTracer conventional(named.scene, options.light_tree);
        render_all(named.scene.render, [&](const TileRect& t, std::span<float> out) {
          conventional.render_tile(t, out);
        });
        return 0;
      }
      const auto scene = PreparedScene::build(
          named.scene, PrepareOptions{.all_features = options.only_renderer == "all",
                                      .light_tree = options.light_tree});
      render_all(named.scene.render,
                 [&](const TileRect& t, std::span<float> out) { scene->render_tile(t, out); });
      return 0;
    }
    std::fprintf(stderr, "no scene called '%s'\n", options.only_scene.c_str());
    return 2;
  }
  double log_all = 0.0, log_virtual = 0.0;
  int count = 0, virtual_count = 0;
  bool images_agree = true;
  for (const NamedScene& named : scenes_for(options)) {
    const auto specialised =
        PreparedScene::build(named.scene, PrepareOptions{.light_tree = options.light_tree});
    const auto general = PreparedScene::build(
        named.scene, PrepareOptions{.all_features = true, .light_tree = options.light_tree});
    // The baseline models emissive spheres, quads and meshes only; a scene whose lights it
    // cannot model (an environment is a sampled light) is compared with the all-features
    // variant alone.
    std::optional<VirtualPathTracer> conventional;
    try {
      conventional.emplace(named.scene, options.light_tree);
    } catch (const std::invalid_argument& e) {
      std::printf("scene=%s: no virtual baseline (%s)\n", named.name.c_str(), e.what());
    }
    const TileRenderer run_specialised = [&](const TileRect& t, std::span<float> out) {
      specialised->render_tile(t, out);
    };
    const TileRenderer run_general = [&](const TileRect& t, std::span<float> out) {
      general->render_tile(t, out);
    };
    const TileRenderer run_virtual = [&](const TileRect& t, std::span<float> out) {
      conventional->render_tile(t, out);
    };
    const RenderSettings& s = named.scene.render;
    const auto reference = render_all(s, run_specialised);
    const double diff_general = max_difference(reference, render_all(s, run_general));
    const double diff_virtual =
        conventional ? max_difference(reference, render_all(s, run_virtual)) : 0.0;
    if (diff_general != 0.0 || diff_virtual != 0.0) images_agree = false;

    const double t_specialised = time_render(s, run_specialised, options.repeats);
    const double t_general = time_render(s, run_general, options.repeats);
    const double t_virtual =
        conventional ? time_render(s, run_virtual, options.repeats) : std::nan("");
    const auto& f = specialised->variant().features;
    std::printf(
        "scene=%-14s primitives=%-7zu variant=[shapes=%#x lights=%d specular=%d aovs=%d] "
        "specialised_ms=%.1f "
        "all_features_ms=%.1f virtual_ms=%.1f speedup_vs_all=%.3f speedup_vs_virtual=%.3f "
        "max_diff_all=%g max_diff_virtual=%g\n",
        named.name.c_str(), specialised->features().primitive_count, f.shapes, f.direct_lighting,
        f.specular, f.aovs, 1e3 * t_specialised, 1e3 * t_general, 1e3 * t_virtual,
        t_general / t_specialised, t_virtual / t_specialised, diff_general, diff_virtual);
    log_all += std::log(t_general / t_specialised);
    ++count;
    if (!conventional) continue;
    log_virtual += std::log(t_virtual / t_specialised);
    ++virtual_count;
  }
  if (!images_agree) std::printf("warning: the three renderers did not produce the same images\n");
  std::printf("speedup_vs_all_features=%.3f speedup_vs_virtual=%.3f\n", std::exp(log_all / count),
              std::exp(log_virtual / std::max(virtual_count, 1)));
  return images_agree ? 0 : 1;
}

}  // namespace tessera::bench
