#pragma once
// How one pixel's samples run, shared by the CPU tile loop and the CUDA kernel: samples
// [first, end) of the pixel's sequence, and under adaptive sampling only until the pixel's
// error estimate meets the target. The ray generation adds each sample's value to the film
// at sample_weight(); a sample's value is read back from the change it made to the beauty
// plane, so this works for every integrator.
#include <cstdint>

#include "tessera/math/vec.hpp"
#include "tessera/render/film.hpp"
#include "tessera/render/pixel_variance.hpp"
#include "tessera/render/tile.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

struct PixelSampling {
  std::uint32_t first = 0;  // samples the film already holds (progressive refinement)
  std::uint32_t end = 1;    // one past the last sample; the most a pixel takes
  std::uint32_t min_samples = 16;
  float target_error = 0.0f;  // 0: every sample runs
  // Accumulating passes (FilmPlanes::total_samples): samples are weighted for a render of
  // `total` samples and the film holds partial sums; 0: the film holds an image of `end`.
  std::uint32_t total = 0;

  TESSERA_HD bool adaptive() const { return target_error > 0.0f; }
  TESSERA_HD bool accumulating() const { return total != 0; }
  // The sample count each sample's weight is for: `total` when accumulating, else `end`.
  TESSERA_HD std::uint32_t weight_count() const { return accumulating() ? total : end; }
  // What each sample adds to the film: 1 / weight_count(), or 1 under adaptive sampling
  // (the pixel's planes are divided by the count it took at the end).
  TESSERA_HD float sample_weight() const {
    return adaptive() ? 1.0f : 1.0f / static_cast<float>(weight_count());
  }
};

namespace pixel_detail {
TESSERA_HD inline vec3 rgb_at(const float* plane, std::size_t at) {
  return vec3(plane[at], plane[at + 1], plane[at + 2]);
}
}  // namespace pixel_detail

// Runs pixel (x, y)'s samples. `interrupted()` is asked before each sample (the CPU's cancel
// flag; never on the GPU); when it says true the pixel is left unfinished and this returns
// false. When refining (first > 0) the pixel's planes are rescaled to the new count and its
// running statistics resume from its beauty and variance planes. When accumulating, nothing
// is rescaled: the samples are added at their final weight and the running statistics
// resume from (and are saved to) the film's running planes, so passes that split [0, total)
// end with exactly the floats one render of `total` gives.
template <typename Pipeline, typename Interrupted>
TESSERA_HD bool render_pixel(const Pipeline& pipeline, std::uint32_t x, std::uint32_t y,
                             const TileRect& tile, const FilmPlanes& film,
                             const PixelSampling& sampling, Interrupted& interrupted) {
  using pixel_detail::rgb_at;
  const bool adaptive = sampling.adaptive();
  const bool track = adaptive || film.variance != nullptr;
  // A sample's value from the change it made: non-adaptive samples land at 1 / end.
  const float sample_scale = adaptive ? 1.0f : static_cast<float>(sampling.weight_count());
  // Depth is the nearest hit, not an average: it is neither rescaled nor divided.
  float* const averaged[3] = {film.beauty, film.albedo, film.normal};
  const std::size_t at = FilmPlanes::offset(tile, x, y);
  PixelVariance stats;
  if (sampling.accumulating() && sampling.first > 0) {
    if (film.variance) {
      stats.count = sampling.first;
      if (film.running_mean) stats.mean = rgb_at(film.running_mean, at);
      if (film.running_m2) stats.m2 = rgb_at(film.running_m2, at);
      for (int c = 0; c < 3; ++c) film.variance[at + c] = 0.0f;
    }
    if (film.sample_count)
      for (int c = 0; c < 3; ++c) film.sample_count[at + c] = 0.0f;
  } else if (sampling.first > 0) {
    const float first = static_cast<float>(sampling.first);
    if (film.variance) {
      stats.count = sampling.first;
      stats.mean = rgb_at(film.beauty, at);
      stats.m2 = rgb_at(film.variance, at) * (first * (first - 1.0f));
      for (int c = 0; c < 3; ++c) film.variance[at + c] = 0.0f;
    }
    if (film.sample_count)
      for (int c = 0; c < 3; ++c) film.sample_count[at + c] = 0.0f;
    const float keep = first / static_cast<float>(sampling.end);
    for (float* plane : averaged)
      if (plane)
        for (int c = 0; c < 4; ++c) plane[at + c] *= keep;
  }
  AdaptiveStop stop;
  std::uint32_t taken = sampling.first;
  while (taken < sampling.end) {
    if (interrupted()) return false;
    const vec3 before = track ? rgb_at(film.beauty, at) : vec3(0.0f);
    pipeline.launch(x, y, taken);
    ++taken;
    if (!track) continue;
    stats.add((rgb_at(film.beauty, at) - before) * sample_scale);
    if (adaptive && stop.converged(stats, sampling.min_samples, sampling.target_error)) break;
  }
  if (adaptive) {
    const float inv = 1.0f / static_cast<float>(taken);
    for (float* plane : averaged)
      if (plane)
        for (int c = 0; c < 4; ++c) plane[at + c] *= inv;
  }
  if (film.variance) FilmPlanes::add(film.variance, at, stats.variance_of_mean(), 1.0f);
  if (sampling.accumulating() && film.running_mean && film.running_m2)
    for (int c = 0; c < 3; ++c) {
      film.running_mean[at + c] = stats.mean[c];
      film.running_m2[at + c] = stats.m2[c];
    }
  if (film.sample_count)
    FilmPlanes::add(film.sample_count, at, vec3(static_cast<float>(taken)), 1.0f);
  return true;
}

// The sampling of every pixel of a render, on the CPU and the GPU alike: settings.samples_per_pixel
// is the end, the film says where refinement starts.
inline PixelSampling pixel_sampling(const RenderSettings& settings, const FilmPlanes& film) {
  return PixelSampling{film.first_sample, settings.samples_per_pixel,
                       settings.min_samples_per_pixel, static_cast<float>(settings.target_error),
                       film.total_samples};
}

}  // namespace tessera
