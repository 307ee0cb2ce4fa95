#pragma once
// Host-side construction of trim regions: validation of the uv loops and their unwrapping
// across the seam of periodic directions. Not for the device: it allocates.
#include <cmath>
#include <string>
#include <vector>

#include "tessera/geometry/trimmed_face.hpp"

namespace tessera {

// Every face's loops and points, two flat arrays. Growing the pool moves them: call
// bind_trim_region on every face after the last build (and after copying the pool to where
// the renderer reads it).
struct TrimPool {
  std::vector<dvec2> points;
  std::vector<TrimLoop> loops;
};

inline void bind_trim_region(TrimRegion& region, const TrimPool& pool) {
  region.points = pool.points.data();
  region.loops = pool.loops.data();
}

// Validates the loops (errors name `field`.loops[k][i] and the reason), unwraps them and
// appends them to the pool. loops[0] is the outer boundary, the others holes; each is a
// closed polyline of at least 3 uv points (the last joined back to the first). On a
// periodic direction consecutive points are taken the short way round (each step less
// than half a period), so a loop may cross the seam anywhere; a loop that goes all the way
// round (not closing after unwrapping) is refused: describe a band around a cylinder as
// one loop, e.g. (0, a) (0.5, a) (1, a) (1, b) (0.5, b) (0, b).
inline std::string build_trim_region(const std::vector<std::vector<dvec2>>& loops,
                                     UvPeriodicity periodic, TrimPool& pool, TrimRegion& out,
                                     const std::string& field = "trim") {
  if (loops.empty()) return field + ".loops: must hold at least the outer loop";
  std::vector<TrimLoop> built;
  std::vector<dvec2> points;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const std::string name = field + ".loops[" + std::to_string(k) + "]";
    const std::vector<dvec2>& loop = loops[k];
    if (loop.size() < 3)
      return name + ": must have at least 3 points, got " + std::to_string(loop.size());
    TrimLoop t{static_cast<std::uint32_t>(pool.points.size() + points.size()),
               static_cast<std::uint32_t>(loop.size()), dvec2(kInfinity), dvec2(-kInfinity)};
    dvec2 previous(0.0);
    double twice_area = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      dvec2 p = loop[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        return name + "[" + std::to_string(i) + "]: must be finite";
      if (i > 0) {
        // Shift by whole periods so the step from the previous point is the short one.
        // (A step of exactly half a period is kept as given.)
        if (periodic.u && std::fabs(p.x - previous.x) > 0.5) p.x -= std::round(p.x - previous.x);
        if (periodic.v && std::fabs(p.y - previous.y) > 0.5) p.y -= std::round(p.y - previous.y);
        twice_area += previous.x * p.y - p.x * previous.y;
      }
      points.push_back(p);
      t.lower = glm::min(t.lower, p);
      t.upper = glm::max(t.upper, p);
      previous = p;
    }
    const dvec2 first = points[t.first_point - pool.points.size()];
    const dvec2 gap = first - previous;
    if ((periodic.u && std::fabs(gap.x) > 0.5) || (periodic.v && std::fabs(gap.y) > 0.5))
      return name +
             ": goes all the way round a periodic direction (it does not close after "
             "unwrapping); describe a band as one loop through both edges";
    twice_area += previous.x * first.y - first.x * previous.y;
    if (k == 0 && !(std::fabs(twice_area) > 0.0))
      return name + ": the outer loop encloses no area (degenerate)";
    built.push_back(t);
  }
  out.first_loop = static_cast<std::uint32_t>(pool.loops.size());
  out.loop_count = static_cast<std::uint32_t>(built.size());
  out.periodic = periodic;
  pool.points.insert(pool.points.end(), points.begin(), points.end());
  pool.loops.insert(pool.loops.end(), built.begin(), built.end());
  bind_trim_region(out, pool);
  return {};
}

// A trimmed face of `surface` (any surface with uv_periodicity), built in one call.
template <typename Surface>
std::string build_trimmed_face(const Surface& surface, const std::vector<std::vector<dvec2>>& loops,
                               TrimPool& pool, Trimmed<Surface>& out,
                               const std::string& field = "face") {
  out.surface = surface;
  return build_trim_region(loops, uv_periodicity(surface), pool, out.region, field);
}

}  // namespace tessera
