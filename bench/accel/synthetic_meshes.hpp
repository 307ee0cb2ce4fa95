#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

#include "mesh_files.hpp"

namespace tessera::bench {

// Deterministic large meshes for benchmarking besides Suzanne, each with at least
// `min_triangles` triangles:
//   knot    - a bumpy tube along a (3,7) torus knot: one long surface that passes close
//             to itself many times, so boxes of distant parts overlap.
//   scatter - many small icospheres at random places and sizes: separate objects with
//             empty space between them, overlapping at random.
//   tubes   - CAD-like: randomly oriented open cylinders (length 8, radius 0.15) whose sides
//             are, by default, single strips running the whole length (48 per tube, aspect
//             about 400:1), the long thin triangles a CAD tessellator emits; boxes of these
//             triangles are mostly empty.
//   uneven  - triangle sizes over five orders of magnitude: a ground square of two huge
//             triangles, a few large tilted walls, one dense bumpy sphere (half the
//             triangles) and small spheres whose radii spread over 2.5 orders of magnitude.
enum class SyntheticMesh { kKnot, kScatter, kTubes, kUneven };

// The tessellation of each tube: strips around it, rings of strips along it. Fewer strips
// and more rings make shorter, wider triangles that fill their boxes better; the pre-split
// threshold was measured over such a series (bench/accel/README.md).
struct TubeTessellation {
  std::uint32_t strips = 48;
  std::uint32_t rings = 1;
};

std::optional<SyntheticMesh> parse_synthetic_mesh(std::string_view name);
IndexedMesh make_synthetic_mesh(SyntheticMesh kind, std::size_t min_triangles,
                                TubeTessellation tubes = {});

}  // namespace tessera::bench
