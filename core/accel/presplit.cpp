#include "tessera/accel/presplit.hpp"

#include <cmath>

namespace tessera {

namespace {

constexpr double kMaxSplitsPerTriangle = 64.0;

// A convex polygon in double: a triangle clipped by at most six planes has at most nine
// vertices.
struct Polygon {
  dvec3 v[9];
  int n = 0;
};

// Keeps the part of `in` with sign * (p[axis] - plane) >= 0 (Sutherland-Hodgman, one plane).
void clip(const Polygon& in, int axis, double plane, double sign, Polygon& out) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const dvec3& a = in.v[i];
    const dvec3& b = in.v[(i + 1) % in.n];
    const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
    if (da >= 0.0) out.v[out.n++] = a;
    if ((da < 0.0) != (db < 0.0)) {
      dvec3 p = a + (b - a) * (da / (da - db));
      p[axis] = plane;  // exactly on the plane, whatever the rounding of the interpolation
      out.v[out.n++] = p;
    }
  }
}

// Rounds a double bound to the float at or beyond it.
float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -kInfinity);
  return f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, kInfinity);
  return f;
}

// The split plane for the piece `box` along `axis`: the coarsest plane of a power-of-two grid
// over [origin, origin + extent] strictly inside the piece, so cuts of neighbouring triangles
// coincide (Karras and Aila); the piece's midpoint when no grid plane of 2^24 cells falls
// inside (a piece that thin is not worth aligning).
float split_plane(const Aabb& box, int axis, float origin, float extent) {
  const double lo = (static_cast<double>(box.lower[axis]) - origin) / extent;
  const double hi = (static_cast<double>(box.upper[axis]) - origin) / extent;
  for (int level = 1; level <= 24; ++level) {
    const double cells = std::ldexp(1.0, level);
    const double plane = (std::floor(lo * cells) + 1.0) / cells;
    if (plane < hi) {
      const auto world = static_cast<float>(origin + plane * extent);
      if (world > box.lower[axis] && world < box.upper[axis]) return world;
    }
  }
  return 0.5f * (box.lower[axis] + box.upper[axis]);
}

// Cuts the piece `box` of triangle `id` into splits + 1 pieces, sharing the remaining cuts
// between the two halves in proportion to their box areas.
void split_piece(const Triangle& tri, std::uint32_t id, const Aabb& box, int splits,
                 const Aabb& scene, std::vector<Aabb>& out_bounds,
                 std::vector<std::uint32_t>& out_ids) {
  const int axis = box.largest_axis();
  const float extent = scene.upper[axis] - scene.lower[axis];
  if (splits <= 0 || !(box.upper[axis] > box.lower[axis]) || !(extent > 0.0f)) {
    out_bounds.push_back(box);
    out_ids.push_back(id);
    return;
  }
  const float plane = split_plane(box, axis, scene.lower[axis], extent);
  Aabb left_region = box, right_region = box;
  left_region.upper[axis] = plane;
  right_region.lower[axis] = plane;
  const Aabb left = clipped_triangle_bounds(tri, left_region);
  const Aabb right = clipped_triangle_bounds(tri, right_region);
  if (left.empty() || right.empty()) {  // rounding left nothing on one side: keep the piece
    out_bounds.push_back(box);
    out_ids.push_back(id);
    return;
  }
  const float left_area = left.surface_area(), right_area = right.surface_area();
  const float total = left_area + right_area;
  const int rest = splits - 1;
  const int left_splits =
      total > 0.0f ? static_cast<int>(std::lround(static_cast<float>(rest) * left_area / total))
                   : rest / 2;
  split_piece(tri, id, left, left_splits, scene, out_bounds, out_ids);
  split_piece(tri, id, right, rest - left_splits, scene, out_bounds, out_ids);
}

}  // namespace

Aabb clipped_triangle_bounds(const Triangle& tri, const Aabb& box) {
  Polygon a, b;
  a.n = 3;
  a.v[0] = dvec3(tri.p0);
  a.v[1] = dvec3(tri.p1);
  a.v[2] = dvec3(tri.p2);
  for (int axis = 0; axis < 3; ++axis) {
    clip(a, axis, box.lower[axis], 1.0, b);
    clip(b, axis, box.upper[axis], -1.0, a);
  }
  Aabb result;
  if (a.n == 0) return result;
  dvec3 lo(kInfinity), hi(-kInfinity);
  for (int i = 0; i < a.n; ++i) {
    lo = glm::min(lo, a.v[i]);
    hi = glm::max(hi, a.v[i]);
  }
  for (int axis = 0; axis < 3; ++axis) {
    // Outwards, then inside the region: the region's planes are floats, so the clamp is
    // exact, and the part of the triangle in the region stays inside the result.
    result.lower[axis] = std::fmax(round_down(lo[axis]), box.lower[axis]);
    result.upper[axis] = std::fmin(round_up(hi[axis]), box.upper[axis]);
  }
  return result;
}

double box_fill_ratio(std::span<const Triangle> triangles, std::span<const std::uint32_t> ids,
                      std::span<const Aabb> bounds) {
  double box_area = 0.0, triangle_area = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    box_area += bounds[i].surface_area();
    triangle_area += 2.0 * static_cast<double>(surface_area(triangles[ids[i]]));
  }
  return triangle_area > 0.0 ? box_area / triangle_area : 0.0;
}

void presplit_triangles(std::span<const Triangle> triangles, std::span<const std::uint32_t> ids,
                        std::span<const Aabb> bounds, const Aabb& scene, float budget,
                        std::vector<Aabb>& out_bounds, std::vector<std::uint32_t>& out_ids) {
  // Priority: the cube root of the box area a triangle does not fill (Karras and Aila).
  std::vector<float> priority(ids.size());
  double total = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const float excess = bounds[i].surface_area() - 2.0f * surface_area(triangles[ids[i]]);
    priority[i] = excess > 0.0f && std::isfinite(excess) ? std::cbrt(excess) : 0.0f;
    total += priority[i];
  }
  const double extra = static_cast<double>(budget) * static_cast<double>(ids.size());
  // Splits per triangle: floor(scale * priority), at most kMaxSplitsPerTriangle, with the
  // largest scale whose total stays within the budget (Karras and Aila search it the same
  // way). A fixed scale of budget / total priority would round most shares of a small budget
  // down to nothing; the search hands the budget to the worst-fitting triangles instead.
  const auto splits_at = [&](double scale) {
    double sum = 0.0;
    for (const float p : priority) sum += std::fmin(std::floor(scale * p), kMaxSplitsPerTriangle);
    return sum;
  };
  double low = 0.0,
         high = total > 0.0 ? 2.0 * (extra + static_cast<double>(ids.size())) / total : 0.0;
  if (high > 0.0) {
    while (splits_at(high) <= extra && high < 1e30) high *= 2.0;  // the cap can hold it down
    for (int step = 0; step < 40; ++step) {
      const double middle = 0.5 * (low + high);
      (splits_at(middle) <= extra ? low : high) = middle;
    }
  }
  out_bounds.reserve(out_bounds.size() + ids.size() + static_cast<std::size_t>(extra) + 1);
  out_ids.reserve(out_ids.size() + ids.size() + static_cast<std::size_t>(extra) + 1);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto splits =
        static_cast<int>(std::fmin(std::floor(low * priority[i]), kMaxSplitsPerTriangle));
    split_piece(triangles[ids[i]], ids[i], bounds[i], splits, scene, out_bounds, out_ids);
  }
}

}  // namespace tessera
