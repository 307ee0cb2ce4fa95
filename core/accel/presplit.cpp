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
// vertices in exact arithmetic. The pieces of a pre-split carry theirs down the cuts
// (split_piece), and rounding could in principle let a clip add vertices where exact
// arithmetic adds none: a polygon of more than kMaxCarriedVertices is clipped afresh from its
// triangle, and a clip that would overflow the storage marks its output (kOverflow), whose
// piece then keeps the box it had.
constexpr int kMaxCarriedVertices = 9;
constexpr int kOverflow = -1;
struct Polygon {
  dvec3 v[2 * kMaxCarriedVertices];
  int n = 0;
};

// Keeps the part of `in` with sign * (p[axis] - plane) >= 0 (Sutherland-Hodgman, one plane).
void clip(const Polygon& in, int axis, double plane, double sign, Polygon& out) {
  out.n = 0;
  if (in.n == kOverflow) {
    out.n = kOverflow;
    return;
  }
  constexpr int kCapacity = 2 * kMaxCarriedVertices;
  for (int i = 0; i < in.n; ++i) {
    if (out.n + 2 > kCapacity) {
      out.n = kOverflow;
      return;
    }
    const dvec3& a = in.v[i];
    const dvec3& b = in.v[i + 1 < in.n ? i + 1 : 0];
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

// Where a chunk of triangles writes its pieces: its own stretch of the output, long enough
// for every cut to keep both sides.
struct PieceWriter {
  Aabb* bounds;
  std::uint32_t* ids;
  std::size_t count = 0;
  void add(const Aabb& box, std::uint32_t id) {
    bounds[count] = box;
    ids[count] = id;
    ++count;
  }
};

// The whole triangle as a polygon.
Polygon triangle_polygon(const Triangle& tri) {
  Polygon p;
  p.n = 3;
  p.v[0] = dvec3(tri.p0);
  p.v[1] = dvec3(tri.p1);
  p.v[2] = dvec3(tri.p2);
  return p;
}

// The triangle as a polygon, clipped to `box`.
Polygon clipped_polygon(const Triangle& tri, const Aabb& box) {
  Polygon a = triangle_polygon(tri), b;
  for (int axis = 0; axis < 3; ++axis) {
    clip(a, axis, box.lower[axis], 1.0, b);
    clip(b, axis, box.upper[axis], -1.0, a);
  }
  return a;
}

// The box of `polygon`, rounded outwards to float, then clamped to `region` (which holds it
// in exact arithmetic): the region's planes are floats, so the clamp is exact, and the part
// of the triangle in the region stays inside the result. Empty for an empty polygon.
Aabb polygon_bounds(const Polygon& polygon, const Aabb& region) {
  if (polygon.n == kOverflow) return region;  // holds the part, if not tightly
  Aabb result;
  if (polygon.n == 0) return result;
  dvec3 lo(kInfinity), hi(-kInfinity);
  for (int i = 0; i < polygon.n; ++i) {
    lo = glm::min(lo, polygon.v[i]);
    hi = glm::max(hi, polygon.v[i]);
  }
  for (int axis = 0; axis < 3; ++axis) {
    result.lower[axis] = std::fmax(round_down(lo[axis]), region.lower[axis]);
    result.upper[axis] = std::fmin(round_up(hi[axis]), region.upper[axis]);
  }
  return result;
}

// Cuts the piece `box` of triangle `id`, whose part of the triangle is `polygon`, into
// splits + 1 pieces, sharing the remaining cuts between the two halves in proportion to
// their box areas. Each cut clips the piece's polygon by its one plane instead of the whole
// triangle by the six planes of the half's box: the same part of the triangle in exact
// arithmetic, and a sixth of the clipping, which was most of the pre-split's own time on
// 288k long thin triangles cut into 1.44M pieces.
void split_piece(const Triangle& tri, std::uint32_t id, const Polygon& polygon, const Aabb& box,
                 int splits, const Aabb& scene, PieceWriter& out) {
  const int axis = box.largest_axis();
  const float extent = scene.upper[axis] - scene.lower[axis];
  if (splits <= 0 || !(box.upper[axis] > box.lower[axis]) || !(extent > 0.0f)) {
    out.add(box, id);
    return;
  }
  if (polygon.n > kMaxCarriedVertices || polygon.n == kOverflow) {
    const Polygon fresh = clipped_polygon(tri, box);
    if (fresh.n > kMaxCarriedVertices || fresh.n == kOverflow) return out.add(box, id);
    return split_piece(tri, id, fresh, box, splits, scene, out);
  }
  const float plane = split_plane(box, axis, scene.lower[axis], extent);
  Aabb left_region = box, right_region = box;
  left_region.upper[axis] = plane;
  right_region.lower[axis] = plane;
  Polygon left_polygon, right_polygon;
  clip(polygon, axis, plane, -1.0, left_polygon);
  clip(polygon, axis, plane, 1.0, right_polygon);
  const Aabb left = polygon_bounds(left_polygon, left_region);
  const Aabb right = polygon_bounds(right_polygon, right_region);
  if (left.empty() || right.empty()) {  // rounding left nothing on one side: keep the piece
    out.add(box, id);
    return;
  }
  const float left_area = left.surface_area(), right_area = right.surface_area();
  const float total = left_area + right_area;
  const int rest = splits - 1;
  const int left_splits =
      total > 0.0f ? static_cast<int>(std::lround(static_cast<float>(rest) * left_area / total))
                   : rest / 2;
  split_piece(tri, id, left_polygon, left, left_splits, scene, out);
  split_piece(tri, id, right_polygon, right, rest - left_splits, scene, out);
}

// The cuts a triangle of priority `priority` gets at scale `scale` (presplit_triangles).
int splits_for(double scale, float priority) {
  return static_cast<int>(std::fmin(std::floor(scale * priority), kMaxSplitsPerTriangle));
}

}  // namespace

Aabb clipped_triangle_bounds(const Triangle& tri, const Aabb& box) {
  return polygon_bounds(clipped_polygon(tri, box), box);
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
                        HugePageVector<Aabb>& out_bounds, HugePageVector<std::uint32_t>& out_ids) {
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
  // fixed chunks of triangles. Each chunk writes straight into its own stretch of the output,
  // sized for every cut keeping both sides, and the stretches are then closed up in chunk
  // order: the pieces come out in the order one loop would give them, whatever the thread
  // count. (Per-chunk vectors joined afterwards spent a third of the cuts' time faulting in
  // fresh pages, the output's huge pages take a fault per 2 MiB.)
  const std::size_t chunks = (ids.size() + kSplitChunk - 1) / kSplitChunk;
  std::vector<std::size_t> stretch(chunks + 1, out_ids.size());
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * kSplitChunk;
    const std::size_t end = std::min(ids.size(), begin + kSplitChunk);
    std::size_t most = 0;  // pieces, if every cut keeps both sides
    for (std::size_t i = begin; i < end; ++i)
      most += static_cast<std::size_t>(splits_for(low, priority[i])) + 1;
    stretch[chunk + 1] = most;
  });
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) stretch[chunk + 1] += stretch[chunk];
  out_bounds.resize(stretch[chunks]);
  out_ids.resize(stretch[chunks]);
  std::vector<std::size_t> written(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * kSplitChunk;
    const std::size_t end = std::min(ids.size(), begin + kSplitChunk);
    PieceWriter out{out_bounds.data() + stretch[chunk], out_ids.data() + stretch[chunk]};
    for (std::size_t i = begin; i < end; ++i) {
      const Triangle& tri = triangles[ids[i]];
      split_piece(tri, ids[i], triangle_polygon(tri), bounds[i], splits_for(low, priority[i]),
                  scene, out);
    }
    written[chunk] = out.count;
  });
  // Closing up moves every stretch towards the front, so in chunk order nothing is overwritten
  // before it has moved.
  std::size_t size = stretch[0];
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
    if (size != stretch[chunk]) {
      std::copy_n(out_bounds.begin() + static_cast<std::ptrdiff_t>(stretch[chunk]), written[chunk],
                  out_bounds.begin() + static_cast<std::ptrdiff_t>(size));
      std::copy_n(out_ids.begin() + static_cast<std::ptrdiff_t>(stretch[chunk]), written[chunk],
                  out_ids.begin() + static_cast<std::ptrdiff_t>(size));
    }
    size += written[chunk];
  }
  out_bounds.resize(size);
  out_ids.resize(size);
}

}  // namespace tessera
