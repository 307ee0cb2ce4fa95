#pragma once
#include <cmath>
#include <cstdint>

#include "tessera/math/orient2d.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

using dvec2 = glm::dvec2;

// One closed uv polyline of a trimmed face: points [first_point, first_point + count) of
// the face's point pool, the last joined back to the first. Stored unwrapped across a
// periodic direction (consecutive points less than half a period apart; see
// build_trimmed_face), so it may reach outside [0, 1).
struct TrimLoop {
  std::uint32_t first_point;
  std::uint32_t point_count;
  dvec2 lower, upper;  // box of the points, a quick reject before the edge loop
};

// Where a point lies relative to one loop.
enum class LoopSide { kOutside, kInside, kOnBoundary };

// Winding number of the loop around p with the exact orientation predicate (the crossing
// rule of Sunday 2001 / Hormann and Agathos 2001: an edge counts when it crosses p's
// horizontal line upwards with p on its left, or downwards with p on its right; the
// half-open rule on y counts a vertex on that line exactly once). A point exactly on an
// edge or vertex (orientation exactly 0 inside the edge's box) is reported as on the
// boundary instead, so the caller decides how closed faces are.
TESSERA_HD TESSERA_INLINE LoopSide loop_side(const dvec2* points, const TrimLoop& loop,
                                             const dvec2& p) {
  if (p.x < loop.lower.x || p.x > loop.upper.x || p.y < loop.lower.y || p.y > loop.upper.y)
    return LoopSide::kOutside;
  const dvec2* v = points + loop.first_point;
  const std::uint32_t n = loop.point_count;
  int winding = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const dvec2& a = v[i];
    const dvec2& b = v[i + 1 == n ? 0 : i + 1];
    const bool a_below = a.y <= p.y, b_below = b.y <= p.y;
    const bool in_y_range = (a.y <= p.y) != (b.y <= p.y) || a.y == p.y || b.y == p.y;
    if (!in_y_range) continue;
    const double side = orient2d(a.x, a.y, b.x, b.y, p.x, p.y);
    if (side == 0.0 && p.x >= glm::min(a.x, b.x) && p.x <= glm::max(a.x, b.x) &&
        p.y >= glm::min(a.y, b.y) && p.y <= glm::max(a.y, b.y))
      return LoopSide::kOnBoundary;
    if (a_below && !b_below && side > 0.0) ++winding;
    if (!a_below && b_below && side < 0.0) --winding;
  }
  return winding != 0 ? LoopSide::kInside : LoopSide::kOutside;
}

// Which uv directions of a surface wrap with period 1 (u = angle / 2 pi and the like).
struct UvPeriodicity {
  bool u = false;
  bool v = false;
};

// The trimming of a face: loop 0 is the outer boundary, the others are holes; all point
// into one pool of points (plain pointers, no allocation per ray; see trimmed_face.hpp).
struct TrimRegion {
  const dvec2* points;    // the pool's points (rebind after a copy/upload)
  const TrimLoop* loops;  // the pool's loops
  std::uint32_t first_loop;
  std::uint32_t loop_count;  // >= 1
  UvPeriodicity periodic;
};

// Whether the closed face contains uv: inside (or on) the outer loop and not strictly
// inside a hole (a hole's boundary belongs to the face). Loop orientation does not matter.
// On a periodic direction a loop stands for all its copies one period apart, so the point
// is tested at its value and one period to each side: loops unwrapped across the seam
// (e.g. u from 0.9 to 1.1) then hold hits at u = 0.05, and such a hole cuts them out of
// an outer loop that spans [0, 1].
TESSERA_HD TESSERA_INLINE bool face_contains(const TrimRegion& region, const dvec2& uv) {
  const TrimLoop* loops = region.loops + region.first_loop;
  const int u_shifts = region.periodic.u ? 1 : 0, v_shifts = region.periodic.v ? 1 : 0;
  bool in_outer = false;
  for (int du = -u_shifts; du <= u_shifts && !in_outer; ++du)
    for (int dv = -v_shifts; dv <= v_shifts && !in_outer; ++dv)
      in_outer = loop_side(region.points, loops[0], uv + dvec2(du, dv)) != LoopSide::kOutside;
  if (!in_outer) return false;
  for (std::uint32_t k = 1; k < region.loop_count; ++k)
    for (int du = -u_shifts; du <= u_shifts; ++du)
      for (int dv = -v_shifts; dv <= v_shifts; ++dv)
        if (loop_side(region.points, loops[k], uv + dvec2(du, dv)) == LoopSide::kInside)
          return false;
  return true;
}

}  // namespace tessera
