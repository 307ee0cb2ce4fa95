#pragma once
#include <cstdint>

#include "tessera/math/host_device.hpp"

namespace tessera {

enum class PixelFilterKind : std::uint8_t { kBox, kGaussian, kBlackmanHarris };

// The pixel reconstruction filter, applied by filter importance sampling: each sample's
// position in the pixel is drawn from the filter's own distribution, so every sample keeps
// weight 1 and the pixel is the plain average (no weights to normalise, no negative lobes
// to ring; the filters here are non-negative). Separable: x and y offsets are drawn
// independently from the 1D filter.
//
// Box: uniform over `width` pixels. Gaussian: standard deviation width / 6, truncated at
// +-width / 2 (3 sigma). Blackman-Harris: the four-term window stretched over `width`.
// The tabulated filters keep the CDF at kTableCells + 1 equally spaced offsets (computed in
// double on the host from the filter's integral) and invert it by binary search, uniform
// within a cell: the sampled density is the filter averaged over cells of width / 128
// pixels, so even the tails (where an equal-probability table would stretch one step
// over a third of a pixel) follow the filter.
struct PixelFilter {
  static constexpr std::uint32_t kTableCells = 128;

  PixelFilterKind kind = PixelFilterKind::kBox;
  float width = 1.0f;  // full support, pixels
  // The share of the filter at offsets below -width / 2 + i * width / kTableCells, from 0
  // to 1 (tabulated filters only).
  float cdf[kTableCells + 1] = {};

  // `width` 0: the filter's default (box 1 pixel, Gaussian and Blackman-Harris 3 pixels).
  static PixelFilter make(PixelFilterKind kind, double width = 0.0);
  // The filter's unnormalised value at offset `x` from the pixel centre (host, for tests).
  static double evaluate(PixelFilterKind kind, double width, double x);
  static double default_width(PixelFilterKind kind);

  // The sample's position within the pixel, from its corner, for a uniform `u` in [0, 1).
  // The 1-pixel box gives u itself, so the default filter leaves images as they were.
  TESSERA_HD float position(float u) const {
    if (kind == PixelFilterKind::kBox) return (0.5f - 0.5f * width) + u * width;
    std::uint32_t lo = 0, hi = kTableCells;  // the cell with cdf[lo] <= u < cdf[lo + 1]
    while (hi - lo > 1) {
      const std::uint32_t mid = (lo + hi) / 2;
      if (cdf[mid] <= u)
        lo = mid;
      else
        hi = mid;
    }
    const float span = cdf[lo + 1] - cdf[lo];
    const float t = span > 0.0f ? (u - cdf[lo]) / span : 0.5f;
    const float cell = width / static_cast<float>(kTableCells);
    return 0.5f - 0.5f * width + (static_cast<float>(lo) + t) * cell;
  }
};

}  // namespace tessera
