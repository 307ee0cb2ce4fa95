#pragma once
// Shared by the variant translation units: builds one pipeline per integrator and runs
// it over a tile. Private to core/render.
#include "tessera/render/first_hit_integrators.hpp"
#include "tessera/render/path_tracer.hpp"
#include "tessera/render/pixel_sampling.hpp"
#include "tessera/render/render_variants.hpp"
#include "tessera/render/shadow_integrator.hpp"
#include "tessera/render/tile_cancel.hpp"
#include "tessera/render/transparency_integrator.hpp"

namespace tessera::variants {

// Checks the thread's cancel flag (TileCancelScope) every kCancelCheckSamples samples, so a
// cancel reaches a tile within a fraction of a second whatever its size and spp.
inline constexpr std::uint32_t kCancelCheckSamples = 256;

// Polls the thread's cancel flag (TileCancelScope) every kCancelCheckSamples samples.
class CancelPoll {
 public:
  bool operator()() {
    if (until_check_-- != 0) return false;
    until_check_ = kCancelCheckSamples - 1;
    return flag_ && flag_->load(std::memory_order_relaxed);
  }

 private:
  const std::atomic<bool>* flag_ = current_tile_cancel_flag();
  std::uint32_t until_check_ = 0;
};

template <typename P>
void run_tile(const P& pipeline, const TileRect& tile, const PixelSampling& sampling,
              const FilmPlanes& film) {
  CancelPoll interrupted;
  for (std::uint32_t y = tile.y; y < tile.y + tile.height; ++y)
    for (std::uint32_t x = tile.x; x < tile.x + tile.width; ++x)
      if (!render_pixel(pipeline, x, y, tile, film, sampling, interrupted)) return;
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
  const PixelSampling sampling = pixel_sampling(settings, film);
  SobolSeedMemo sobol_memo;  // the tile's pixels run one after another on this thread
  const typename Config::RayGeneration rays{
      scene.camera, settings.seed,    tile,       sampling.sample_weight(), film,
      &stats.rays,  settings.sampler, &sobol_memo};
  const Pipeline<Config> pipeline(rays, make_tracer<Config::Intersection::kShapeMask>(scene), hit,
                                  miss);
  run_tile(pipeline, tile, sampling, film);
  return stats;
}

template <PipelineFeatures kFeatures>
TileStats render_path(const SceneView& scene, const RenderSettings& settings, const TileRect& tile,
                      const FilmPlanes& film) {
  return render_camera_pipeline<PathTracerConfig<kFeatures>>(
      scene, settings, tile, film,
      PathHit<kFeatures>{scene, settings.max_depth, settings.light_strategy,
                         static_cast<float>(settings.clamp)},
      PathMiss<kFeatures>{scene, settings.light_strategy, settings.transparent_background,
                          static_cast<float>(settings.clamp)});
}

template <unsigned kShapes>
TileStats render_shadow(const SceneView& scene, const RenderSettings& settings,
                        const TileRect& tile, const FilmPlanes& film) {
  return render_camera_pipeline<ShadowConfig<kShapes>>(
      scene, settings, tile, film, ShadowHit<kShapes>{scene},
      BackgroundMiss{scene.background, settings.transparent_background});
}

template <unsigned kShapes>
TileStats render_transparency(const SceneView& scene, const RenderSettings& settings,
                              const TileRect& tile, const FilmPlanes& film) {
  return render_camera_pipeline<TransparencyConfig<kShapes>>(
      scene, settings, tile, film, TransparencyHit<kShapes>{scene, settings.transparent_background},
      BackgroundMiss{scene.background, settings.transparent_background});
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

// The preview integrators of one shape class: normals, albedo, depth, phong, shadow,
// transparency.
inline constexpr std::size_t kPreviewVariantCount = 6;
template <unsigned kShapes>
std::array<RenderVariant, kPreviewVariantCount> preview_variants();

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
std::array<RenderVariant, kPreviewVariantCount> make_preview_variants() {
  constexpr PipelineFeatures f{kShapes, false, false, false};
  return {
      RenderVariant{IntegratorKind::kNormals, f,
                    &render_first_hit<kShapes, FirstHitOutput::kNormals>},
      RenderVariant{IntegratorKind::kAlbedo, f,
                    &render_first_hit<kShapes, FirstHitOutput::kAlbedo>},
      RenderVariant{IntegratorKind::kDepth, f, &render_first_hit<kShapes, FirstHitOutput::kDepth>},
      RenderVariant{IntegratorKind::kPhong, f, &render_first_hit<kShapes, FirstHitOutput::kPhong>},
      RenderVariant{IntegratorKind::kShadow, PipelineFeatures{kShapes, true, false, false},
                    &render_shadow<kShapes>},
      RenderVariant{IntegratorKind::kTransparency, f, &render_transparency<kShapes>}};
}

}  // namespace tessera::variants
