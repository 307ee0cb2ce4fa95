#include "tessera/render/pixel_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace tessera {

double PixelFilter::default_width(PixelFilterKind kind) {
  return kind == PixelFilterKind::kBox ? 1.0 : 3.0;
}

double PixelFilter::evaluate(PixelFilterKind kind, double width, double x) {
  const double radius = 0.5 * width;
  if (std::fabs(x) > radius) return 0.0;
  switch (kind) {
    case PixelFilterKind::kBox:
      return 1.0;
    case PixelFilterKind::kGaussian: {
      const double sigma = width / 6.0;
      return std::exp(-0.5 * x * x / (sigma * sigma));
    }
    case PixelFilterKind::kBlackmanHarris: {
      const double t = 2.0 * std::numbers::pi * (x + radius) / width;  // 0 .. 2 pi
      return 0.35875 - 0.48829 * std::cos(t) + 0.14128 * std::cos(2.0 * t) -
             0.01168 * std::cos(3.0 * t);
    }
  }
  return 0.0;
}

PixelFilter PixelFilter::make(PixelFilterKind kind, double width) {
  if (!(width > 0.0)) width = default_width(kind);
  PixelFilter filter;
  filter.kind = kind;
  filter.width = static_cast<float>(width);
  if (kind == PixelFilterKind::kBox) return filter;
  // Each cell's share by Simpson's rule on 16 sub-intervals (the filters are smooth).
  const double radius = 0.5 * width;
  const double cell = width / kTableCells;
  std::vector<double> cdf(kTableCells + 1, 0.0);
  for (std::uint32_t i = 0; i < kTableCells; ++i) {
    constexpr int kSub = 16;
    const double h = cell / kSub;
    const double x0 = -radius + i * cell;
    double sum = evaluate(kind, width, x0) + evaluate(kind, width, x0 + cell);
    for (int k = 1; k < kSub; ++k)
      sum += (k % 2 == 1 ? 4.0 : 2.0) * evaluate(kind, width, x0 + k * h);
    cdf[i + 1] = cdf[i] + std::max(0.0, sum * h / 3.0);
  }
  for (std::uint32_t i = 0; i <= kTableCells; ++i)
    filter.cdf[i] = static_cast<float>(cdf[i] / cdf.back());
  filter.cdf[kTableCells] = 1.0f;
  return filter;
}

}  // namespace tessera
