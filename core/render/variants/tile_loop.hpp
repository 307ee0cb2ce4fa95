#pragma once
// Shared by the variant translation units: builds one pipeline per integrator and runs
// it over a tile. Private to core/render.
#include "tessera/render/first_hit_integrators.hpp"
#include "tessera/render/path_tracer.hpp"
#include "tessera/render/render_variants.hpp"
#include "tessera/render/shadow_integrator.hpp"
#include "tessera/render/transparency_integrator.hpp"

namespace tessera::variants {

template <typename P>
void run_tile(const P& pipeline, const TileRect& tile, std::uint32_t samples_per_pixel) {
  for (std::uint32_t y = tile.y; y < tile.y + tile.height; ++y)
    for (std::uint32_t x = tile.x; x < tile.x + tile.width; ++x)
      for (std::uint32_t s = 0; s < samples_per_pixel; ++s) pipeline.launch(x, y, s);
}

template <unsigned kShapes>
BvhTracer<SceneIntersection<kShapes>> make_tracer(const SceneView& scene) {
  return BvhTracer<SceneIntersection<kShapes>>(
      scene.bvh, SceneIntersection<kShapes>{scene.spheres, scene.quads, scene.triangles});
}

template <bool kAovs>
PathRayGeneration<kAovs> make_camera_rays(const SceneView& scene, const RenderSettings& settings,
                                          const TileRect& tile, const FilmPlanes& film,
                                          TileStats& stats) {
  return PathRayGeneration<kAovs>{
      scene.camera, settings.seed, tile, 1.0f / static_cast<float>(settings.samples_per_pixel),
      film,         &stats.rays};
}

template <PipelineFeatures kFeatures>
TileStats render_path(const SceneView& scene, const RenderSettings& settings, const TileRect& tile,
                      const FilmPlanes& film) {
  TileStats stats;
  const Pipeline<PathTracerConfig<kFeatures>> pipeline(
      make_camera_rays<kFeatures.aovs>(scene, settings, tile, film, stats),
      make_tracer<kFeatures.shapes>(scene), PathHit<kFeatures>{scene, settings.max_depth},
      BackgroundMiss{scene.background});
  run_tile(pipeline, tile, settings.samples_per_pixel);
  return stats;
}

template <unsigned kShapes>
TileStats render_shadow(const SceneView& scene, const RenderSettings& settings,
                        const TileRect& tile, const FilmPlanes& film) {
  TileStats stats;
  const Pipeline<ShadowConfig<kShapes>> pipeline(
      make_camera_rays<false>(scene, settings, tile, film, stats), make_tracer<kShapes>(scene),
      ShadowHit<kShapes>{scene}, BackgroundMiss{scene.background});
  run_tile(pipeline, tile, settings.samples_per_pixel);
  return stats;
}

template <unsigned kShapes>
TileStats render_transparency(const SceneView& scene, const RenderSettings& settings,
                              const TileRect& tile, const FilmPlanes& film) {
  TileStats stats;
  const Pipeline<TransparencyConfig<kShapes>> pipeline(
      make_camera_rays<false>(scene, settings, tile, film, stats), make_tracer<kShapes>(scene),
      TransparencyHit<kShapes>{scene}, BackgroundMiss{scene.background});
  run_tile(pipeline, tile, settings.samples_per_pixel);
  return stats;
}

template <unsigned kShapes, FirstHitOutput kOutput>
TileStats render_first_hit(const SceneView& scene, const RenderSettings& settings,
                           const TileRect& tile, const FilmPlanes& film) {
  TileStats stats;
  const FirstHitRayGeneration rays{
      scene.camera, settings.seed, tile, 1.0f / static_cast<float>(settings.samples_per_pixel),
      film,         &stats.rays};
  const Pipeline<FirstHitConfig<kShapes, kOutput>> pipeline(
      rays, make_tracer<kShapes>(scene), FirstHitShade<kShapes, kOutput>{scene}, BlackMiss{});
  run_tile(pipeline, tile, settings.samples_per_pixel);
  return stats;
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
