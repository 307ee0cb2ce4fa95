#pragma once
// Host-side construction of SplinePatch: validation of the control grid, knots and weights,
// and conversion to rational Bézier pieces by knot insertion (once, when the scene is
// built). Not for the device: it allocates.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tessera/geometry/spline_patch.hpp"

namespace tessera {

// A bicubic patch as a scene describes it. Control point (i, j), i along u and j along v,
// is control_points[i * count_v + j]. Weights: empty for a non-rational B-spline, else one
// per control point, each > 0. Knot vectors: count + 4 non-decreasing values each (degree
// 3); the patch covers [knots[3], knots[count]] in each direction, which must not be empty.
// Clamped (end knots repeated 4 times) and unclamped vectors are both accepted.
struct SplinePatchDescription {
  int count_u = 0;
  int count_v = 0;
  std::vector<dvec3> control_points;
  std::vector<double> weights;
  std::vector<double> knots_u;
  std::vector<double> knots_v;
  std::uint32_t material = 0;
};

// Every patch's Bézier pieces, one flat array; a SplinePatch holds [first_piece,
// first_piece + piece_count). Growing the pool moves it: call bind_pieces on every patch
// after the last build (and after copying the pool to where the renderer reads it).
struct SplinePatchPool {
  std::vector<RationalBezierPatch> pieces;
};

inline void bind_pieces(SplinePatch& patch, const RationalBezierPatch* pool_data) {
  patch.pieces = pool_data + patch.first_piece;
}

namespace detail {

inline std::string validate_knots(const std::vector<double>& knots, int count,
                                  const std::string& field) {
  if (knots.size() != static_cast<std::size_t>(count) + 4)
    return field + ": must have " + std::to_string(count + 4) +
           " values (control points + 4 for degree 3), got " + std::to_string(knots.size());
  int multiplicity = 1;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) return field + "[" + std::to_string(i) + "]: must be finite";
    if (i == 0) continue;
    if (knots[i] < knots[i - 1])
      return field + "[" + std::to_string(i) + "]: must be non-decreasing, got " +
             std::to_string(knots[i]) + " after " + std::to_string(knots[i - 1]);
    multiplicity = knots[i] == knots[i - 1] ? multiplicity + 1 : 1;
    if (multiplicity > 4)
      return field + "[" + std::to_string(i) +
             "]: a knot value may repeat at most 4 times (degree + 1)";
  }
  if (!(knots[3] < knots[static_cast<std::size_t>(count)]))
    return field + ": the parameter domain [knots[3], knots[" + std::to_string(count) +
           "]] is empty";
  return {};
}

// Boehm's knot insertion of x into the curves running along the first index of an
// n x m homogeneous grid (element (i, j) at i * m + j).
inline void insert_knot(std::vector<glm::dvec4>& grid, int& n, int m, std::vector<double>& knots,
                        double x) {
  // A non-empty span [knots[k], knots[k + 1]] holding x, k in [3, n - 1]: the formula
  // needs only knots[k] <= x <= knots[k + 1] (every denominator is then positive).
  int k = 3;
  for (int i = 3; i <= n - 1; ++i)
    if (knots[i] < knots[i + 1] && knots[i] <= x && x <= knots[i + 1]) k = i;
  std::vector<glm::dvec4> out(static_cast<std::size_t>(n + 1) * m);
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j < m; ++j) {
      glm::dvec4 value;
      if (i <= k - 3) {
        value = grid[i * m + j];
      } else if (i >= k + 1) {
        value = grid[(i - 1) * m + j];
      } else {
        const double a = (x - knots[i]) / (knots[i + 3] - knots[i]);
        value = (1.0 - a) * grid[(i - 1) * m + j] + a * grid[i * m + j];
      }
      out[static_cast<std::size_t>(i) * m + j] = value;
    }
  }
  knots.insert(knots.begin() + k + 1, x);
  grid = std::move(out);
  ++n;
}

// Raises every distinct knot value of the domain to multiplicity 3 (the degree), after
// which the control points of each non-empty span are its Bézier points.
inline void saturate_knots(std::vector<glm::dvec4>& grid, int& n, int m,
                           std::vector<double>& knots) {
  const double start = knots[3], end = knots[static_cast<std::size_t>(n)];
  for (std::size_t i = 0; i < knots.size();) {
    const double x = knots[i];
    std::size_t multiplicity = 1;
    while (i + multiplicity < knots.size() && knots[i + multiplicity] == x) ++multiplicity;
    if (x >= start && x <= end && multiplicity < 3) {
      insert_knot(grid, n, m, knots, x);
      continue;  // re-count this value
    }
    i += multiplicity;
  }
}

inline std::vector<glm::dvec4> transpose(const std::vector<glm::dvec4>& grid, int n, int m) {
  std::vector<glm::dvec4> out(grid.size());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) out[static_cast<std::size_t>(j) * n + i] = grid[i * m + j];
  return out;
}

}  // namespace detail

// The largest ratio between a NURBS patch's largest and smallest weight. Extreme weights
// (1e-300 next to 1e300) pinch the surface into control points the flatness bound cannot
// see, so the intersector subdivides to its depth limit on every ray (4000x slower);
// circles and conics need ratios near 1 (1/sqrt 2), and 1e6 leaves any modelled shape room.
inline constexpr double kMaxWeightRatio = 1e6;

// Validates `description` (errors name `field`'s sub-field and the reason), appends its
// Bézier pieces to the pool and fills `out` (its pieces pointer bound to the pool as it is
// now). Returns an empty string on success.
inline std::string build_spline_patch(const SplinePatchDescription& description,
                                      SplinePatchPool& pool, SplinePatch& out,
                                      const std::string& field = "patch") {
  const int nu = description.count_u, nv = description.count_v;
  if (nu < 4) return field + ".count_u: must be at least 4 (bicubic), got " + std::to_string(nu);
  if (nv < 4) return field + ".count_v: must be at least 4 (bicubic), got " + std::to_string(nv);
  const std::size_t count = static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv);
  if (description.control_points.size() != count)
    return field + ".control_points: must have count_u * count_v = " + std::to_string(count) +
           " points, got " + std::to_string(description.control_points.size());
  if (!description.weights.empty() && description.weights.size() != count)
    return field + ".weights: must be empty or have " + std::to_string(count) + " values, got " +
           std::to_string(description.weights.size());
  std::vector<glm::dvec4> grid(count);
  for (std::size_t i = 0; i < count; ++i) {
    const dvec3& p = description.control_points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return field + ".control_points[" + std::to_string(i) + "]: must be finite";
    const double w = description.weights.empty() ? 1.0 : description.weights[i];
    if (!(w > 0.0) || !std::isfinite(w))
      return field + ".weights[" + std::to_string(i) + "]: must be finite and > 0, got " +
             std::to_string(w);
    grid[i] = glm::dvec4(p * w, w);
  }
  if (!description.weights.empty()) {
    const auto [smallest, largest] =
        std::minmax_element(description.weights.begin(), description.weights.end());
    if (*largest > *smallest * kMaxWeightRatio)
      return field + ".weights: the largest (" + std::to_string(*largest) + ") must be at most " +
             std::to_string(kMaxWeightRatio) + " times the smallest (" + std::to_string(*smallest) +
             ")";
  }
  std::string error = detail::validate_knots(description.knots_u, nu, field + ".knots_u");
  if (error.empty()) error = detail::validate_knots(description.knots_v, nv, field + ".knots_v");
  if (!error.empty()) return error;

  const double u_start = description.knots_u[3], u_end = description.knots_u[nu];
  const double v_start = description.knots_v[3], v_end = description.knots_v[nv];
  std::vector<double> ku = description.knots_u, kv = description.knots_v;
  int n = nu, m = nv;
  detail::saturate_knots(grid, n, m, ku);
  grid = detail::transpose(grid, n, m);
  detail::saturate_knots(grid, m, n, kv);
  grid = detail::transpose(grid, m, n);

  out = SplinePatch{};
  out.first_piece = static_cast<std::uint32_t>(pool.pieces.size());
  out.u0 = u_start;
  out.u1 = u_end;
  out.v0 = v_start;
  out.v1 = v_end;
  out.material = description.material;
  dvec3 lower(kInfinity), upper(-kInfinity);
  for (int a = 3; a < n; ++a) {
    if (!(ku[a] < ku[a + 1]) || ku[a] < u_start || ku[a + 1] > u_end) continue;
    for (int b = 3; b < m; ++b) {
      if (!(kv[b] < kv[b + 1]) || kv[b] < v_start || kv[b + 1] > v_end) continue;
      RationalBezierPatch piece{};
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          const glm::dvec4& h = grid[static_cast<std::size_t>(a - 3 + i) * m + (b - 3 + j)];
          piece.weight[i][j] = h.w;
          piece.point[i][j] = dvec3(h) / h.w;
          lower = glm::min(lower, piece.point[i][j]);
          upper = glm::max(upper, piece.point[i][j]);
        }
      }
      piece.u0 = ku[a];
      piece.u1 = ku[a + 1];
      piece.v0 = kv[b];
      piece.v1 = kv[b + 1];
      flatness_levels(piece);
      control_box(piece, piece.lower, piece.upper);
      pool.pieces.push_back(piece);
    }
  }
  out.piece_count = static_cast<std::uint32_t>(pool.pieces.size()) - out.first_piece;
  out.size = glm::length(upper - lower);
  out.box = conservative_aabb(lower, upper);
  bind_pieces(out, pool.pieces.data());
  return {};
}

}  // namespace tessera
