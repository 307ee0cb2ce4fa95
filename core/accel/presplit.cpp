#include "tessera/accel/presplit.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tessera {

namespace {

constexpr double kMaxSplitsPerTriangle = 64.0;
// Triangles per task of the budget search and of the cuts.
constexpr std::size_t kSearchGrain = 16384;
constexpr std::size_t kSplitChunk = 2048;

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

// The cuts a triangle of priority `priority` gets at scale `scale` (presplit_triangles).
int splits_for(double scale, float priority) {
  return static_cast<int>(std::fmin(std::floor(scale * priority), kMaxSplitsPerTriangle));
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
  // The sum is of whole numbers, exact in any order, so the parallel reduction gives the
  // same budget search (and the same pieces) for any thread count.
  const auto splits_at = [&](double scale) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, priority.size(), kSearchGrain), std::uint64_t{0},
        [&](const tbb::blocked_range<std::size_t>& r, std::uint64_t sum) {
          for (std::size_t i = r.begin(); i < r.end(); ++i)
            sum += static_cast<std::uint64_t>(splits_for(scale, priority[i]));
          return sum;
        },
        [](std::uint64_t a, std::uint64_t b) { return a + b; });
  };
  const auto fits = [&](double scale) { return static_cast<double>(splits_at(scale)) <= extra; };
  double low = 0.0,
         high = total > 0.0 ? 2.0 * (extra + static_cast<double>(ids.size())) / total : 0.0;
  if (high > 0.0) {
    while (fits(high) && high < 1e30) high *= 2.0;  // the cap can hold it down
    for (int step = 0; step < 40; ++step) {
      const double middle = 0.5 * (low + high);
      (fits(middle) ? low : high) = middle;
    }
  }
  // The cuts (double-precision clipping, most of the pre-split's time) run in parallel over
  // fixed chunks of triangles, each into its own lists, joined in chunk order: the pieces
  // come out in the order one loop would give them, whatever the thread count.
  const std::size_t chunks = (ids.size() + kSplitChunk - 1) / kSplitChunk;
  std::vector<std::vector<Aabb>> chunk_bounds(chunks);
  std::vector<std::vector<std::uint32_t>> chunk_ids(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * kSplitChunk;
    const std::size_t end = std::min(ids.size(), begin + kSplitChunk);
    int splits[kSplitChunk];
    std::size_t most = 0;  // pieces, if every cut keeps both sides
    for (std::size_t i = begin; i < end; ++i) {
      splits[i - begin] = splits_for(low, priority[i]);
      most += static_cast<std::size_t>(splits[i - begin]) + 1;
    }
    chunk_bounds[chunk].reserve(most);
    chunk_ids[chunk].reserve(most);
    for (std::size_t i = begin; i < end; ++i)
      split_piece(triangles[ids[i]], ids[i], bounds[i], splits[i - begin], scene,
                  chunk_bounds[chunk], chunk_ids[chunk]);
  });
  std::size_t pieces = 0;
  for (const auto& chunk : chunk_ids) pieces += chunk.size();
  out_bounds.reserve(out_bounds.size() + pieces);
  out_ids.reserve(out_ids.size() + pieces);
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
    out_bounds.insert(out_bounds.end(), chunk_bounds[chunk].begin(), chunk_bounds[chunk].end());
    out_ids.insert(out_ids.end(), chunk_ids[chunk].begin(), chunk_ids[chunk].end());
  }
}

}  // namespace tessera
