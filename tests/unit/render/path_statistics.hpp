#pragma once
// Renders a PreparedScene through the real path tracer (PathHit, the scene's BVH and
// shapes, the renderer's camera rays and sample streams) with a chosen LightStrategy, and
// keeps every pixel's sample mean and the variance of that mean, so accuracy tests can
// state their tolerances in measured standard errors. RenderSettings has no strategy
// field yet; this local pipeline is the same PathTracerConfig with the Hit program's
// strategy set and a ray generation that records statistics instead of the film.
#include <cmath>
#include <cstdint>
#include <vector>

#include "tessera/pipeline/bvh_tracer.hpp"
#include "tessera/pipeline/pipeline.hpp"
#include "tessera/render/path_tracer.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera::test {

// Spheres, quads and disks, with lights and specular materials: what the accuracy scenes use.
inline constexpr PipelineFeatures kStatisticsFeatures{
    kShapeSphere | kShapeQuad | kShapeDisk | kShapeCylinder | kShapeCone, true, true, false};

struct PixelStatistics {
  std::uint32_t width = 0, height = 0;
  std::vector<double> mean;              // red channel, per pixel
  std::vector<double> variance_of_mean;  // sample variance / samples
  std::uint64_t dropped = 0;             // non-finite samples (the film drops them too)

  double at(std::uint32_t x, std::uint32_t y) const { return mean[y * width + x]; }
};

struct StatisticsRayGeneration {
  using Payload = PathPayload<false>;
  PathRayGeneration<false> base;  // the renderer's camera rays and sample streams
  std::uint32_t width;
  double* sum;
  double* sum2;
  std::uint64_t* dropped;

  void init_payload(std::uint32_t x, std::uint32_t y, std::uint32_t sample,
                    Payload& payload) const {
    base.init_payload(x, y, sample, payload);
  }
  Ray generate(std::uint32_t x, std::uint32_t y, std::uint32_t sample, Payload& payload) const {
    return base.generate(x, y, sample, payload);
  }
  void on_result(std::uint32_t x, std::uint32_t y, std::uint32_t, const Payload& payload) const {
    const double r = payload.radiance.x;
    if (!std::isfinite(r) || !std::isfinite(payload.radiance.y) ||
        !std::isfinite(payload.radiance.z)) {
      ++*dropped;
      return;
    }
    sum[y * width + x] += r;
    sum2[y * width + x] += r * r;
  }
};

struct StatisticsConfig {
  using RayGeneration = StatisticsRayGeneration;
  using Intersection = SceneIntersection<kStatisticsFeatures.shapes>;
  using Hit = PathHit<kStatisticsFeatures>;
  using Miss = PathMiss<kStatisticsFeatures>;
};

inline PixelStatistics render_statistics(const PreparedScene& prepared, LightStrategy strategy,
                                         std::uint32_t samples_per_pixel, std::uint64_t seed = 1) {
  const RenderSettings& settings = prepared.settings();
  const SceneView scene = prepared.view();
  PixelStatistics out;
  out.width = settings.width;
  out.height = settings.height;
  std::vector<double> sum(std::size_t{out.width} * out.height, 0.0), sum2(sum.size(), 0.0);
  std::uint64_t rays = 0;
  const TileRect tile{0, 0, 0, out.width, out.height};
  const PathRayGeneration<false> base{scene.camera, seed, tile, 1.0f, FilmPlanes{}, &rays};
  const StatisticsRayGeneration generation{base, out.width, sum.data(), sum2.data(), &out.dropped};
  const Pipeline<StatisticsConfig> pipeline(
      generation,
      BvhTracer<StatisticsConfig::Intersection>(scene.bvh, StatisticsConfig::Intersection{scene}),
      PathHit<kStatisticsFeatures>{scene, settings.max_depth, strategy},
      PathMiss<kStatisticsFeatures>{scene, strategy});
  for (std::uint32_t y = 0; y < out.height; ++y)
    for (std::uint32_t x = 0; x < out.width; ++x)
      for (std::uint32_t s = 0; s < samples_per_pixel; ++s) pipeline.launch(x, y, s);
  const double n = samples_per_pixel;
  out.mean.resize(sum.size());
  out.variance_of_mean.resize(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i) {
    out.mean[i] = sum[i] / n;
    out.variance_of_mean[i] = std::max(0.0, sum2[i] / n - out.mean[i] * out.mean[i]) / (n - 1.0);
  }
  return out;
}

}  // namespace tessera::test
