#pragma once
// A 2D piecewise-constant distribution over the unit square (rows x columns cells), sampled
// by inversion: a row from the marginal CDF, then a column from that row's conditional
// CDF, each continuous within its cell (pbrt's PiecewiseConstant2D). The tables are plain
// float arrays owned elsewhere, so a device can use them once uploaded. Every probability
// is taken as a difference of the stored CDF entries, by sample() and pdf() alike, so the
// two agree exactly.
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

struct PiecewiseConstant2D {
  const float* marginal_cdf = nullptr;     // rows + 1 entries, 0 first and 1 last
  const float* conditional_cdf = nullptr;  // rows x (columns + 1), each row 0 .. 1
  std::uint32_t rows = 0, columns = 0;

  // A point of the unit square (x along columns, y along rows), its density there and its
  // cell (row * columns + column: the point may round onto the cell's far edge, so callers
  // that look values up by cell use this, not the point).
  TESSERA_HD vec2 sample(float u1, float u2, float& pdf, std::uint32_t& cell_index) const {
    const std::uint32_t row = find(marginal_cdf, rows, u1);
    const float row_p = marginal_cdf[row + 1] - marginal_cdf[row];
    const float* cdf = conditional_cdf + static_cast<std::size_t>(row) * (columns + 1);
    const std::uint32_t column = find(cdf, columns, u2);
    const float column_p = cdf[column + 1] - cdf[column];
    pdf = row_p * column_p * static_cast<float>(rows) * static_cast<float>(columns);
    cell_index = row * columns + column;
    const float dy = row_p > 0.0f ? glm::clamp((u1 - marginal_cdf[row]) / row_p, 0.0f, 1.0f) : 0.5f;
    const float dx = column_p > 0.0f ? glm::clamp((u2 - cdf[column]) / column_p, 0.0f, 1.0f) : 0.5f;
    return vec2(
        glm::min((static_cast<float>(column) + dx) / static_cast<float>(columns), 0x1.fffffep-1f),
        glm::min((static_cast<float>(row) + dy) / static_cast<float>(rows), 0x1.fffffep-1f));
  }

  // The density of `point` (in the unit square) under sample().
  TESSERA_HD float pdf(const vec2& point) const {
    const std::uint32_t column = cell(point.x, columns), row = cell(point.y, rows);
    const float* cdf = conditional_cdf + static_cast<std::size_t>(row) * (columns + 1);
    return (marginal_cdf[row + 1] - marginal_cdf[row]) * (cdf[column + 1] - cdf[column]) *
           static_cast<float>(rows) * static_cast<float>(columns);
  }

  TESSERA_HD static std::uint32_t cell(float t, std::uint32_t count) {
    const float scaled = t * static_cast<float>(count);
    if (!(scaled > 0.0f)) return 0;
    return glm::min(static_cast<std::uint32_t>(scaled), count - 1);
  }

 private:
  // The cell i with cdf[i] <= u < cdf[i + 1] among `count`, skipping empty cells.
  TESSERA_HD static std::uint32_t find(const float* cdf, std::uint32_t count, float u) {
    std::uint32_t lo = 0, hi = count;  // cdf[lo] <= u, the answer is below hi
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (cdf[mid] <= u)
        lo = mid;
      else
        hi = mid;
    }
    return lo;
  }
};

}  // namespace tessera
