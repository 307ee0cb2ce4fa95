#pragma once
#include <optional>
#include <span>

#include "tessera/image/exr.hpp"

namespace tessera {

// How far an image is from a reference, over the R, G and B of every pixel.
struct ImageError {
  double rmse = 0.0;
  // Relative MSE as renderer comparisons use it: mean((x - r)^2 / (r^2 + 0.01)); the 0.01
  // keeps black reference pixels from dominating.
  double rel_mse = 0.0;
  double mean = 0.0;            // mean of the image's R, G, B
  double reference_mean = 0.0;  // the same of the reference
};

// Throws std::invalid_argument when the sizes differ.
ImageError image_error(const RgbaImage& image, const RgbaImage& reference);

// One render of a convergence series: its wall time and its error.
struct ErrorPoint {
  double seconds = 0.0;
  double rel_mse = 0.0;
};

struct TimeToError {
  double seconds = 0.0;
  // The fitted exponent of relMSE against time (-1 for an unbiased estimator whose
  // variance falls as 1/samples; flatter means bias or fireflies that do not average out).
  double slope = 0.0;
  bool extrapolated = false;  // the series never reached the target; a power-law fit did
  // The time the last render predicts if relMSE falls as 1 / time from it on (an unbiased
  // estimator's asymptotic rate): relMSE x seconds of that render / target. Where the fitted
  // slope is much flatter than -1 (`shallow`) the fit extrapolates a transient by orders of
  // magnitude: rare bright samples (a small light's caustics) not averaged yet flatten the
  // later renders' errors until they are (a held-out scene lit by a small sun, fitted at
  // 32-256 spp: slope -0.55 and 535 s; fitted at 64-2,048 spp: slope -1.12 and 18.5 s; this
  // figure from its 256-spp render: 28.5 s). A flat slope can also be bias or a reference
  // too noisy for the error: render more samples to measure the time instead. Equal to
  // `seconds` when the series reached the target.
  double seconds_at_unit_slope = 0.0;
  bool shallow = false;  // extrapolated with a slope flatter than kShallowSlope
};

// A fitted slope flatter than this (relMSE falling slower than time^-0.8) marks an
// extrapolation as unreliable (TimeToError::shallow).
inline constexpr double kShallowSlope = -0.8;

// The time at which the series reaches `target` relMSE: interpolated (log-log) between the
// two renders that bracket it, or extrapolated from a least-squares power law through the
// later half of the renders (at least two; the series is in order of time), whose slope is
// reported either way. Empty when fewer than two points are usable or the fit does not fall.
std::optional<TimeToError> time_to_error(std::span<const ErrorPoint> series, double target);

}  // namespace tessera
