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
enum class SyntheticMesh { kKnot, kScatter };

std::optional<SyntheticMesh> parse_synthetic_mesh(std::string_view name);
IndexedMesh make_synthetic_mesh(SyntheticMesh kind, std::size_t min_triangles);

}  // namespace tessera::bench
