#include "tessera/image/image_error.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <vector>

namespace tessera {

ImageError image_error(const RgbaImage& image, const RgbaImage& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.pixels.size() != reference.pixels.size())
    throw std::invalid_argument("image and reference differ in size");
  ImageError e;
  double squared = 0.0, relative = 0.0, sum = 0.0, reference_sum = 0.0;
  const std::size_t pixels = std::size_t{image.width} * image.height;
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = image.pixels[p * 4 + c];
      const double r = reference.pixels[p * 4 + c];
      const double d = x - r;
      squared += d * d;
      relative += d * d / (r * r + 0.01);
      sum += x;
      reference_sum += r;
    }
  const double n = static_cast<double>(pixels * 3);
  if (n == 0.0) return e;
  e.rmse = std::sqrt(squared / n);
  e.rel_mse = relative / n;
  e.mean = sum / n;
  e.reference_mean = reference_sum / n;
  return e;
}

std::optional<TimeToError> time_to_error(std::span<const ErrorPoint> series, double target) {
  std::vector<ErrorPoint> usable;
  for (const ErrorPoint& p : series)
    if (p.seconds > 0.0 && p.rel_mse > 0.0 && std::isfinite(p.rel_mse)) usable.push_back(p);
  if (usable.size() < 2 || !(target > 0.0)) return std::nullopt;

  // Least squares of log(relMSE) on log(time) over the later half of the series (at least
  // two renders): a render's fixed cost (a renderer's per-render set-up, a thread pool's
  // start) weighs on its shortest renders and bends the low end of the curve, and a slope
  // fitted through it extrapolated too short a time (Cycles' 1-spp renders took 24 ms
  // where a sample costs 10 ms on glossy_glass: slope -1.12 through every render, -1.00
  // through the later half; tests/unit/image/image_error_test.cpp has a synthetic case).
  const std::size_t fitted_from = std::min(usable.size() / 2, usable.size() - 2);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const ErrorPoint& p : std::span(usable).subspan(fitted_from)) {
    const double x = std::log(p.seconds), y = std::log(p.rel_mse);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double n = static_cast<double>(usable.size() - fitted_from);
  const double denominator = n * sxx - sx * sx;
  if (denominator <= 0.0) return std::nullopt;
  const double slope = (n * sxy - sx * sy) / denominator;
  const double intercept = (sy - slope * sx) / n;

  // A render at or below the target: interpolate from the one before it.
  for (std::size_t i = 1; i < usable.size(); ++i) {
    const ErrorPoint& a = usable[i - 1];
    const ErrorPoint& b = usable[i];
    if (a.rel_mse > target && b.rel_mse <= target) {
      const double f =
          (std::log(target) - std::log(a.rel_mse)) / (std::log(b.rel_mse) - std::log(a.rel_mse));
      const double seconds =
          std::exp(std::log(a.seconds) + f * (std::log(b.seconds) - std::log(a.seconds)));
      return TimeToError{seconds, slope, false, seconds, false};
    }
  }
  if (usable.front().rel_mse <= target)
    return TimeToError{usable.front().seconds, slope, false, usable.front().seconds, false};
  if (!(slope < 0.0)) return std::nullopt;  // not converging: no time reaches the target
  const ErrorPoint& last = usable.back();
  return TimeToError{std::exp((std::log(target) - intercept) / slope), slope, true,
                     last.seconds * last.rel_mse / target, slope > kShallowSlope};
}

}  // namespace tessera
