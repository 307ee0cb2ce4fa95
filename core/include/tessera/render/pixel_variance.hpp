#pragma once
// The running mean and variance of one pixel's samples (Welford, per colour channel), from
// which adaptive sampling decides when the pixel has converged and the variance AOV is
// written.
#include <cmath>
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

// Radiance below which a pixel's error counts as absolute rather than relative: the same
// 0.01 the converge benchmark's relMSE adds to the squared reference, so a pixel whose
// estimate meets target_error contributes about target_error^2 to the image's relMSE.
inline constexpr float kRelativeErrorFloor = 0.01f;

struct PixelVariance {
  std::uint32_t count = 0;
  vec3 mean{0.0f};
  vec3 m2{0.0f};  // sum of squared deviations from the running mean

  TESSERA_HD void add(const vec3& sample) {
    ++count;
    const vec3 delta = sample - mean;
    mean += delta / static_cast<float>(count);
    m2 += delta * (sample - mean);
  }

  // The variance of the pixel's mean estimate, per channel (0 below two samples).
  TESSERA_HD vec3 variance_of_mean() const {
    if (count < 2) return vec3(0.0f);
    const float n = static_cast<float>(count);
    return m2 / (n * (n - 1.0f));
  }

  // The largest channel's standard error over sqrt(mean^2 + floor), the estimate adaptive
  // sampling compares with render.target_error.
  TESSERA_HD float relative_error() const {
    const vec3 v = variance_of_mean();
    const vec3 scale = mean * mean + vec3(kRelativeErrorFloor);
    const float worst = glm::max(v.x / scale.x, glm::max(v.y / scale.y, v.z / scale.z));
    return std::sqrt(worst);
  }
};

// Whether a pixel with `stats` has met adaptive sampling's target. Checked every
// kAdaptiveCheckInterval samples once min_samples are in, so the decision (and the image)
// depends only on the pixel's own samples.
inline constexpr std::uint32_t kAdaptiveCheckInterval = 8;
TESSERA_HD inline bool pixel_converged(const PixelVariance& stats, std::uint32_t min_samples,
                                       float target_error) {
  if (stats.count < min_samples) return false;
  if ((stats.count - min_samples) % kAdaptiveCheckInterval != 0) return false;
  return stats.relative_error() < target_error;
}

}  // namespace tessera
