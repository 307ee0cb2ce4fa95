#pragma once
// Chi-square goodness-of-fit of a direction sampler against its density, after Mitsuba 3's
// ChiSquareTest: directions are binned in (cos theta, phi) cells of equal solid angle over a
// spherical cap (the whole sphere, or a cap about the lobe or the light so narrow
// distributions still spread over many cells); the expected count of each cell is the
// sample count times the density integrated numerically over the cell; cells expecting
// fewer than 5 samples are pooled; Pearson's statistic gives a p-value through the
// regularised upper incomplete gamma function. Everything here is double precision and
// independent of the renderer's code.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "tessera/math/vec.hpp"

namespace tessera::test {

// Uniform floats in [0, 1) from a fixed-seed 64-bit generator (24 bits: never exactly 1).
class UniformFloats {
 public:
  explicit UniformFloats(std::uint64_t seed) : engine_(seed) {}
  float operator()() { return static_cast<float>(engine_() >> 40) * 0x1p-24f; }

 private:
  std::mt19937_64 engine_;
};

// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a) (Numerical Recipes:
// series for x < a + 1, Lentz's continued fraction otherwise).
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(log_prefix));
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 0.0;
  std::string summary;  // for failure messages
};

// Pearson's chi-square over cells of observed and expected counts; cells expecting fewer
// than `min_expected` are pooled into one (and the pool into the smallest cell if it still
// expects too few).
inline Chi2Result pearson_chi2(const std::vector<double>& observed,
                               const std::vector<double>& expected, double min_expected = 5.0) {
  std::vector<std::size_t> order(observed.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
  double pooled_obs = 0.0, pooled_exp = 0.0;
  std::vector<std::pair<double, double>> cells;
  for (std::size_t i : order) {
    if (expected[i] < min_expected) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
    } else {
      cells.emplace_back(observed[i], expected[i]);
    }
  }
  if (pooled_exp > 0.0 || pooled_obs > 0.0) {
    if (pooled_exp < min_expected && !cells.empty()) {
      cells.front().first += pooled_obs;  // cells are in increasing expected order
      cells.front().second += pooled_exp;
    } else {
      cells.emplace_back(pooled_obs, pooled_exp);
    }
  }
  Chi2Result r;
  for (const auto& [obs, exp] : cells) {
    const double diff = obs - exp;
    r.statistic += exp > 0.0 ? diff * diff / exp : (obs > 0.0 ? 1e300 : 0.0);
  }
  r.dof = static_cast<int>(cells.size()) - 1;
  r.p_value = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 0.0;
  r.summary = "chi2 " + std::to_string(r.statistic) + " dof " + std::to_string(r.dof) + " p " +
              std::to_string(r.p_value) + " (pooled expected " + std::to_string(pooled_exp) +
              ", observed " + std::to_string(pooled_obs) + ")";
  return r;
}

// A cap of directions about unit `axis`: cos(angle to axis) in [cos_min, 1]. cos_min = -1
// is the whole sphere.
struct DirectionCap {
  glm::dvec3 axis{0.0, 0.0, 1.0};
  double cos_min = -1.0;
};

// Bins of equal solid angle over a cap: `rows` bands of cos theta, `columns` of phi, plus
// one last bin for directions outside the cap.
class CapHistogram {
 public:
  CapHistogram(const DirectionCap& cap, int rows, int columns)
      : cap_(cap), rows_(rows), columns_(columns) {
    const glm::dvec3 z = glm::normalize(cap.axis);
    const glm::dvec3 helper =
        std::fabs(z.x) > 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0.0, 0.0);
    x_ = glm::normalize(glm::cross(helper, z));
    y_ = glm::cross(z, x_);
    z_ = z;
  }

  int cells() const { return rows_ * columns_ + 1; }
  int outside() const { return rows_ * columns_; }

  int cell_of(const glm::dvec3& w) const {
    const glm::dvec3 d = glm::normalize(w);
    const double c = glm::dot(d, z_);
    if (c < cap_.cos_min) return outside();
    int row = static_cast<int>((c - cap_.cos_min) / (1.0 - cap_.cos_min) * rows_);
    row = std::clamp(row, 0, rows_ - 1);
    double phi = std::atan2(glm::dot(d, y_), glm::dot(d, x_));
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    int column = static_cast<int>(phi / (2.0 * std::numbers::pi) * columns_);
    column = std::clamp(column, 0, columns_ - 1);
    return row * columns_ + column;
  }

  // The integral of `density` (per solid angle) over every cell, by the midpoint rule on a
  // k x k grid in (cos theta, phi), where d omega = d cos d phi. Cells where the density is
  // not smooth (a grid of 4 and of 8 disagree) are refined to 48 x 48.
  std::vector<double> integrate(const std::function<double(const glm::dvec3&)>& density) const {
    std::vector<double> out(cells(), 0.0);
    const double dc = (1.0 - cap_.cos_min) / rows_;
    const double dphi = 2.0 * std::numbers::pi / columns_;
    const auto cell_integral = [&](int row, int column, int k) {
      double sum = 0.0;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const double c = cap_.cos_min + (row + (i + 0.5) / k) * dc;
          const double phi = (column + (j + 0.5) / k) * dphi;
          const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
          sum += density(s * std::cos(phi) * x_ + s * std::sin(phi) * y_ + c * z_);
        }
      return sum * dc * dphi / (k * k);
    };
    for (int row = 0; row < rows_; ++row)
      for (int column = 0; column < columns_; ++column) {
        const double coarse = cell_integral(row, column, 4);
        const double fine = cell_integral(row, column, 8);
        double value = fine;
        if (std::fabs(coarse - fine) > 1e-4 * std::max(fine, 1e-300) + 1e-12)
          value = cell_integral(row, column, 48);
        out[row * columns_ + column] = value;
      }
    return out;
  }

 private:
  DirectionCap cap_;
  int rows_, columns_;
  glm::dvec3 x_, y_, z_;
};

// Significance of one test of `count` in a file (Bonferroni): a correct sampler fails a
// whole file's chi-square tests with probability at most 1%.
inline double bonferroni_alpha(int count) {
  return 0.01 / count;
}

// The unit direction at polar angle theta and azimuth phi (degrees) about +z, the shading
// normal of the BSDF tests.
inline vec3 direction(double theta_degrees, double phi_degrees) {
  const double t = theta_degrees * std::numbers::pi / 180.0;
  const double p = phi_degrees * std::numbers::pi / 180.0;
  return vec3(static_cast<float>(std::sin(t) * std::cos(p)),
              static_cast<float>(std::sin(t) * std::sin(p)), static_cast<float>(std::cos(t)));
}

}  // namespace tessera::test
