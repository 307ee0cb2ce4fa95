#include "tessera/image/denoise.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {

namespace {

// Below this albedo a channel is filtered as radiance rather than illumination (black
// surfaces, emitters and misses have no albedo to divide by).
constexpr float kAlbedoFloor = 1e-3f;

struct Rgb {
  float r = 0.0f, g = 0.0f, b = 0.0f;
};

Rgb at(std::span<const float> plane, std::size_t pixel) {
  return {plane[pixel * 3], plane[pixel * 3 + 1], plane[pixel * 3 + 2]};
}

float luminance(const Rgb& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

float demodulator(float albedo) {
  return albedo > kAlbedoFloor ? albedo : 1.0f;
}

}  // namespace

std::vector<float> denoise(const DenoiseInput& in, const DenoiseOptions& options) {
  const std::size_t pixels = std::size_t{in.width} * in.height;
  const auto check = [&](std::span<const float> plane, const char* name) {
    if (plane.size() != pixels * 3)
      throw std::invalid_argument(std::string("denoise: the ") + name + " plane holds " +
                                  std::to_string(plane.size()) + " floats, expected " +
                                  std::to_string(pixels * 3));
  };
  check(in.beauty, "beauty");
  check(in.albedo, "albedo");
  check(in.normal, "normal");
  check(in.variance, "variance");

  // Illumination and its variance (the beauty's divided by albedo squared).
  std::vector<float> light(pixels * 3), variance(pixels * 3);
  for (std::size_t p = 0; p < pixels * 3; ++p) {
    const float a = demodulator(in.albedo[p]);
    light[p] = in.beauty[p] / a;
    variance[p] = in.variance[p] / (a * a);
  }
  // Unit normals: averaged over a pixel's samples they can be shorter than 1.
  std::vector<float> normal(in.normal.begin(), in.normal.end());
  for (std::size_t p = 0; p < pixels; ++p) {
    float* n = &normal[p * 3];
    const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; ++c) n[c] = length > 1e-6f ? n[c] / length : 0.0f;
  }
  std::vector<float> next_light(pixels * 3), next_variance(pixels * 3);
  constexpr float kKernel[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
  const auto has_surface = [&](std::size_t p) {
    return normal[p * 3] != 0.0f || normal[p * 3 + 1] != 0.0f || normal[p * 3 + 2] != 0.0f;
  };
  for (std::uint32_t level = 0; level < options.iterations; ++level) {
    const int step = 1 << level;
    for (std::uint32_t y = 0; y < in.height; ++y)
      for (std::uint32_t x = 0; x < in.width; ++x) {
        const std::size_t p = std::size_t{y} * in.width + x;
        if (!has_surface(p)) {
          for (int c = 0; c < 3; ++c) {
            next_light[p * 3 + c] = light[p * 3 + c];
            next_variance[p * 3 + c] = variance[p * 3 + c];
          }
          continue;
        }
        const Rgb np = at(normal, p), ap = at(in.albedo, p);
        const float lp = luminance(at(light, p));
        const float sigma_l =
            options.luminance_sigma * std::sqrt(std::max(luminance(at(variance, p)), 0.0f)) + 1e-6f;
        float sum[3] = {0, 0, 0}, sum_var[3] = {0, 0, 0}, weights = 0.0f;
        for (int j = -2; j <= 2; ++j) {
          const long qy = static_cast<long>(y) + j * step;
          if (qy < 0 || qy >= static_cast<long>(in.height)) continue;
          for (int i = -2; i <= 2; ++i) {
            const long qx = static_cast<long>(x) + i * step;
            if (qx < 0 || qx >= static_cast<long>(in.width)) continue;
            const std::size_t q = static_cast<std::size_t>(qy) * in.width + qx;
            if (!has_surface(q)) continue;
            const Rgb nq = at(normal, q), aq = at(in.albedo, q);
            const float cos_n = np.r * nq.r + np.g * nq.g + np.b * nq.b;
            if (cos_n <= 0.0f) continue;
            const float da2 = (ap.r - aq.r) * (ap.r - aq.r) + (ap.g - aq.g) * (ap.g - aq.g) +
                              (ap.b - aq.b) * (ap.b - aq.b);
            const float dl = std::fabs(lp - luminance(at(light, q)));
            const float w =
                kKernel[i + 2] * kKernel[j + 2] *
                std::pow(std::min(cos_n, 1.0f), options.normal_power) *
                std::exp(-da2 / (options.albedo_sigma * options.albedo_sigma) - dl / sigma_l);
            for (int c = 0; c < 3; ++c) {
              sum[c] += w * light[q * 3 + c];
              sum_var[c] += w * w * variance[q * 3 + c];
            }
            weights += w;
          }
        }
        // The centre pixel always contributes (unit normal, so weight kKernel[2]^2 > 0).
        for (int c = 0; c < 3; ++c) {
          next_light[p * 3 + c] = sum[c] / weights;
          next_variance[p * 3 + c] = sum_var[c] / (weights * weights);
        }
      }
    light.swap(next_light);
    variance.swap(next_variance);
  }
  std::vector<float> out(pixels * 3);
  for (std::size_t p = 0; p < pixels * 3; ++p) out[p] = light[p] * demodulator(in.albedo[p]);
  return out;
}

}  // namespace tessera
