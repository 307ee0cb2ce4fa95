#include "environment_map.hpp"

#include <algorithm>
#include <cmath>

namespace tessera {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// CDF entries of `weights` (count + 1 of them, 0 .. 1) appended to `cdf`; a row that weighs
// nothing gets the uniform CDF (the marginal never picks it). Returns the total.
double append_cdf(const double* weights, std::size_t count, std::vector<float>& cdf) {
  double total = 0.0;
  for (std::size_t i = 0; i < count; ++i) total += weights[i];
  double running = 0.0;
  cdf.push_back(0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    running += weights[i];
    cdf.push_back(total > 0.0 ? static_cast<float>(running / total)
                              : static_cast<float>(double(i + 1) / double(count)));
  }
  cdf.back() = 1.0f;
  return total;
}

}  // namespace

void build_environment_map(const EnvironmentDesc& description, Environment& environment,
                           EnvironmentMapTables& tables) {
  const std::uint32_t width = description.image_width, height = description.image_height;
  const std::size_t count = static_cast<std::size_t>(width) * height;
  tables.pixels.resize(count * 3);
  for (std::size_t i = 0; i < count * 3; ++i)
    tables.pixels[i] = description.image_pixels[i] * environment.scale[static_cast<int>(i % 3)];

  std::vector<double> weights(width), row_weights(height);
  tables.conditional_cdf.clear();
  tables.conditional_cdf.reserve(static_cast<std::size_t>(height) * (width + 1));
  double weighted_radiance[3] = {0.0, 0.0, 0.0}, solid_angle = 0.0;
  for (std::uint32_t row = 0; row < height; ++row) {
    const double sin_theta = std::sin(kPiD * (row + 0.5) / height);
    for (std::uint32_t column = 0; column < width; ++column) {
      const float* p = &tables.pixels[3 * (static_cast<std::size_t>(row) * width + column)];
      const double luminance = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      weights[column] = std::max(luminance, 1e-3 * std::max({p[0], p[1], p[2]})) * sin_theta;
      for (int c = 0; c < 3; ++c) weighted_radiance[c] += p[c] * sin_theta;
    }
    solid_angle += sin_theta * width;
    row_weights[row] = append_cdf(weights.data(), width, tables.conditional_cdf);
  }
  tables.marginal_cdf.clear();
  append_cdf(row_weights.data(), height, tables.marginal_cdf);

  environment.kind = EnvironmentKind::kImage;
  environment.image = tables.pixels.data();
  environment.width = width;
  environment.height = height;
  environment.distribution =
      PiecewiseConstant2D{tables.marginal_cdf.data(), tables.conditional_cdf.data(), height, width};
  const double angle = description.rotation_degrees * kPiD / 180.0;
  environment.cos_rotation = static_cast<float>(std::cos(angle));
  environment.sin_rotation = static_cast<float>(std::sin(angle));
  environment.image_average = solid_angle > 0.0
                                  ? vec3(static_cast<float>(weighted_radiance[0] / solid_angle),
                                         static_cast<float>(weighted_radiance[1] / solid_angle),
                                         static_cast<float>(weighted_radiance[2] / solid_angle))
                                  : vec3(0.0f);
}

}  // namespace tessera
