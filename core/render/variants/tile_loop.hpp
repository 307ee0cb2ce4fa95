#pragma once
// Shared by the variant translation units: builds one pipeline per integrator and runs
// it over a tile. Private to core/render.
#include "tessera/render/first_hit_integrators.hpp"
#include "tessera/render/path_tracer.hpp"
#include "tessera/render/pixel_variance.hpp"
#include "tessera/render/render_variants.hpp"
#include "tessera/render/shadow_integrator.hpp"
#include "tessera/render/tile_cancel.hpp"
#include "tessera/render/transparency_integrator.hpp"

namespace tessera::variants {

// Checks the thread's cancel flag (TileCancelScope) every kCancelCheckSamples samples, so a
// cancel reaches a tile within a fraction of a second whatever its size and spp.
inline constexpr std::uint32_t kCancelCheckSamples = 256;

// Runs every pixel's samples from film.first_sample to settings.samples_per_pixel. With
// adaptive sampling (settings.adaptive()) a pixel stops once its estimated error meets
// settings.target_error; the ray generation then adds samples at weight 1 and the pixel's
// planes are divided by the count it took. A sample's value is read back from the beauty
// plane (the change it made), so this works for every integrator. When refining (first
// sample > 0) the planes are rescaled to the new count and the pixel's running statistics
// resume from its beauty and variance planes.
template <typename P>
void run_tile(const P& pipeline, const TileRect& tile, const RenderSettings& settings,
              const FilmPlanes& film) {
  const std::atomic<bool>* cancel = current_tile_cancel_flag();
  std::uint32_t until_check = 0;
  const bool adaptive = settings.adaptive();
  const bool track = adaptive || film.variance != nullptr;
  const std::uint32_t first = film.first_sample, end = settings.samples_per_pixel;
  // Non-adaptive samples land at weight 1 / spp.
  const float sample_scale = adaptive ? 1.0f : static_cast<float>(end);
  const float target = static_cast<float>(settings.target_error);
  const float keep = static_cast<float>(first) / static_cast<float>(end);
  float* const averaged[] = {film.beauty, film.albedo, film.normal, film.depth};
  const auto beauty_at = [&](std::size_t at) {
    return vec3(film.beauty[at], film.beauty[at + 1], film.beauty[at + 2]);
  };
  for (std::uint32_t y = tile.y; y < tile.y + tile.height; ++y)
    for (std::uint32_t x = tile.x; x < tile.x + tile.width; ++x) {
      const std::size_t at = FilmPlanes::offset(tile, x, y);
      PixelVariance stats;
      if (first > 0) {
        if (film.variance) {
          const float pairs = static_cast<float>(first) * static_cast<float>(first - 1);
          stats.count = first;
          stats.mean = beauty_at(at);
          stats.m2 = vec3(film.variance[at], film.variance[at + 1], film.variance[at + 2]) * pairs;
          for (int c = 0; c < 3; ++c) film.variance[at + c] = 0.0f;
        }
        if (film.sample_count)
          for (int c = 0; c < 3; ++c) film.sample_count[at + c] = 0.0f;
        for (float* plane : averaged)
          if (plane)
            for (int c = 0; c < 4; ++c) plane[at + c] *= keep;
      }
      std::uint32_t taken = first;
      while (taken < end) {
        if (until_check-- == 0) {
          if (cancel && cancel->load(std::memory_order_relaxed)) return;
          until_check = kCancelCheckSamples - 1;
        }
        const vec3 before = track ? beauty_at(at) : vec3(0.0f);
        pipeline.launch(x, y, taken);
        ++taken;
        if (!track) continue;
        stats.add((beauty_at(at) - before) * sample_scale);
        if (adaptive && pixel_converged(stats, settings.min_samples_per_pixel, target)) break;
      }
      if (adaptive) {
        const float inv = 1.0f / static_cast<float>(taken);
        for (float* plane : averaged)
          if (plane)
            for (int c = 0; c < 4; ++c) plane[at + c] *= inv;
      }
      if (film.variance) FilmPlanes::add(film.variance, at, stats.variance_of_mean(), 1.0f);
      if (film.sample_count)
        FilmPlanes::add(film.sample_count, at, vec3(static_cast<float>(taken)), 1.0f);
    }
}

// What each sample adds to the film: 1 / spp, or 1 under adaptive sampling (run_tile
// divides by the count each pixel took).
inline float sample_weight(const RenderSettings& settings) {
  return settings.adaptive() ? 1.0f : 1.0f / static_cast<float>(settings.samples_per_pixel);
}

template <unsigned kShapes>
BvhTracer<SceneIntersection<kShapes>> make_tracer(const SceneView& scene) {
  return BvhTracer<SceneIntersection<kShapes>>(scene.bvh, SceneIntersection<kShapes>{scene});
}

// Runs Config's pipeline over one tile. Every integrator's ray generation is a camera-ray
// program with the same fields, so one function builds them all; only the hit and miss
// programs differ.
template <typename Config>
TileStats render_camera_pipeline(const SceneView& scene, const RenderSettings& settings,
                                 const TileRect& tile, const FilmPlanes& film,
                                 typename Config::Hit hit, typename Config::Miss miss) {
  TileStats stats;
  const typename Config::RayGeneration rays{
      scene.camera, settings.seed,   tile, sample_weight(settings), film,
      &stats.rays,  settings.sampler};
  const Pipeline<Config> pipeline(rays, make_tracer<Config::Intersection::kShapeMask>(scene), hit,
                                  miss);
  run_tile(pipeline, tile, settings, film);
  return stats;
}

template <PipelineFeatures kFeatures>
TileStats render_path(const SceneView& scene, const RenderSettings& settings, const TileRect& tile,
                      const FilmPlanes& film) {
  return render_camera_pipeline<PathTracerConfig<kFeatures>>(
      scene, settings, tile, film,
      PathHit<kFeatures>{scene, settings.max_depth, settings.light_strategy},
      BackgroundMiss{scene.background});
}

template <unsigned kShapes>
TileStats render_shadow(const SceneView& scene, const RenderSettings& settings,
                        const TileRect& tile, const FilmPlanes& film) {
  return render_camera_pipeline<ShadowConfig<kShapes>>(
      scene, settings, tile, film, ShadowHit<kShapes>{scene}, BackgroundMiss{scene.background});
}

template <unsigned kShapes>
TileStats render_transparency(const SceneView& scene, const RenderSettings& settings,
                              const TileRect& tile, const FilmPlanes& film) {
  return render_camera_pipeline<TransparencyConfig<kShapes>>(scene, settings, tile, film,
                                                             TransparencyHit<kShapes>{scene},
                                                             BackgroundMiss{scene.background});
}

template <unsigned kShapes, FirstHitOutput kOutput>
TileStats render_first_hit(const SceneView& scene, const RenderSettings& settings,
                           const TileRect& tile, const FilmPlanes& film) {
  return render_camera_pipeline<FirstHitConfig<kShapes, kOutput>>(
      scene, settings, tile, film, FirstHitShade<kShapes, kOutput>{scene}, BlackMiss{});
}

// The 8 path-tracer variants of one shape class: lights x specular x AOVs, false first.
template <unsigned kShapes>
std::array<RenderVariant, 8> path_variants();

// The preview integrators of one shape class.
template <unsigned kShapes>
std::array<RenderVariant, 5> preview_variants();

template <unsigned kShapes>
std::array<RenderVariant, 8> make_path_variants() {
  const auto entry = [](auto lights, auto specular, auto aovs) {
    constexpr PipelineFeatures f{kShapes, decltype(lights)::value, decltype(specular)::value,
                                 decltype(aovs)::value};
    return RenderVariant{IntegratorKind::kPath, f, &render_path<f>};
  };
  using F = std::false_type;
  using T = std::true_type;
  return {entry(F{}, F{}, F{}), entry(F{}, F{}, T{}), entry(F{}, T{}, F{}), entry(F{}, T{}, T{}),
          entry(T{}, F{}, F{}), entry(T{}, F{}, T{}), entry(T{}, T{}, F{}), entry(T{}, T{}, T{})};
}

template <unsigned kShapes>
std::array<RenderVariant, 5> make_preview_variants() {
  constexpr PipelineFeatures f{kShapes, false, false, false};
  return {
      RenderVariant{IntegratorKind::kNormals, f,
                    &render_first_hit<kShapes, FirstHitOutput::kNormals>},
      RenderVariant{IntegratorKind::kAlbedo, f,
                    &render_first_hit<kShapes, FirstHitOutput::kAlbedo>},
      RenderVariant{IntegratorKind::kDepth, f, &render_first_hit<kShapes, FirstHitOutput::kDepth>},
      RenderVariant{IntegratorKind::kShadow, PipelineFeatures{kShapes, true, false, false},
                    &render_shadow<kShapes>},
      RenderVariant{IntegratorKind::kTransparency, f, &render_transparency<kShapes>}};
}

}  // namespace tessera::variants
