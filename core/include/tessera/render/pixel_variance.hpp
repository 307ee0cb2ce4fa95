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

// Adaptive sampling's stopping rule. A pixel is checked at min_samples * 2^k samples (Sobol
// points are best balanced at powers of two, and each decision sees twice the samples of the
// one before) and stops once its estimate has met the target at two checkpoints in a row: an
// estimate from a few samples that missed a rare bright path (a caustic) underestimates the
// variance, and a second, larger look catches most of those. The decision depends only on the
// pixel's own samples, so the image does not depend on tiles or threads.
struct AdaptiveStop {
  bool met_at_last_checkpoint = false;

  TESSERA_HD static bool checkpoint(std::uint32_t count, std::uint32_t min_samples) {
    if (count < min_samples || count % min_samples != 0) return false;
    const std::uint32_t multiple = count / min_samples;
    return (multiple & (multiple - 1)) == 0;
  }

  TESSERA_HD bool converged(const PixelVariance& stats, std::uint32_t min_samples,
                            float target_error) {
    if (!checkpoint(stats.count, min_samples)) return false;
    const bool met = stats.relative_error() < target_error;
    const bool stop = met && met_at_last_checkpoint;
    met_at_last_checkpoint = met;
    return stop;
  }
};

}  // namespace tessera
