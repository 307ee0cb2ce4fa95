// One compiled path-tracing pipeline per shape mask; PreparedScene picks the one that
// covers the scene so absent shape types cost nothing per ray.
#include "render_tile_variants.hpp"

#include "tessera/render/path_tracer.hpp"

namespace tessera {
namespace {

template <unsigned kShapes>
TileStats render_tile_with(const SceneView& scene, const RenderSettings& settings,
                           const TileRect& tile, float* film) {
  using Config = PathTracerConfig<kShapes>;
  TileStats stats;
  const PathRayGeneration ray_generation{
      scene.camera, settings.seed, tile, 1.0f / static_cast<float>(settings.samples_per_pixel),
      film,         &stats.rays};
  const SceneIntersection<kShapes> intersection{scene.spheres, scene.quads, scene.triangles};
  const Pipeline<Config> pipeline(
      ray_generation, BvhTracer<SceneIntersection<kShapes>>(scene.bvh, intersection),
      PathHit<kShapes>{scene, settings.max_depth}, BackgroundMiss{scene.background});
  for (std::uint32_t y = tile.y; y < tile.y + tile.height; ++y)
    for (std::uint32_t x = tile.x; x < tile.x + tile.width; ++x)
      for (std::uint32_t s = 0; s < settings.samples_per_pixel; ++s) pipeline.launch(x, y, s);
  return stats;
}

template <unsigned... kMasks>
constexpr std::array<RenderTileFunction, sizeof...(kMasks)> make_table(
    std::integer_sequence<unsigned, kMasks...>) {
  return {&render_tile_with<kMasks>...};
}

constexpr auto kVariants = make_table(std::make_integer_sequence<unsigned, kAllShapes + 1>{});

}  // namespace

RenderTileFunction select_render_tile(unsigned shape_mask) {
  return kVariants[shape_mask & kAllShapes];
}

}  // namespace tessera
