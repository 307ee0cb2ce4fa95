#pragma once
// An edge-avoiding à-trous wavelet denoiser (Dammertz et al. 2010, with the variance-guided
// luminance weight of SVGF, Schied et al. 2017) for a finished image. It filters the
// illumination (the beauty divided by the first-hit albedo) so texture and material edges
// survive, and stops at edges through three guides the path tracer writes as AOVs: the
// normal, the albedo and the variance of each pixel's mean. Debian 12 packages no Open
// Image Denoise (nor any other image denoiser), hence this filter.
#include <cstdint>
#include <span>
#include <vector>

namespace tessera {

struct DenoiseOptions {
  std::uint32_t iterations = 5;  // à-trous levels: the footprint is 4 * 2^iterations + 1 pixels
  float normal_power = 64.0f;    // weight dot(n_p, n_q)^power
  float albedo_sigma = 0.1f;     // weight exp(-|a_p - a_q|^2 / sigma^2)
  float luminance_sigma = 1.0f;  // weight exp(-|l_p - l_q| / (sigma * standard error))
};

// One image and its guides, width * height pixels of 3 floats each (RGB; normals XYZ, zero
// where the camera ray missed; variance: of the pixel's mean, per channel).
struct DenoiseInput {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::span<const float> beauty;
  std::span<const float> albedo;
  std::span<const float> normal;
  std::span<const float> variance;
};

// The denoised beauty, width * height * 3 floats. Pixels without a surface (normal 0) are
// returned unchanged and never blend with surfaces. Throws std::invalid_argument when a
// plane's size does not match width * height * 3. Linear in the pixel count.
std::vector<float> denoise(const DenoiseInput& input, const DenoiseOptions& options = {});

}  // namespace tessera
