#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/accel/huge_page_allocator.hpp"
#include "tessera/geometry/aabb.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera {

// Pre-splitting (Karras and Aila, "Fast Parallel Construction of High-Quality Bounding Volume
// Hierarchies", HPG 2013, sec. 5): before the binned SAH build, the boxes of triangles that
// fill them poorly (long, thin or diagonal triangles) are cut into several smaller boxes, each
// bounding the part of the triangle inside it, and every piece becomes a reference to the same
// triangle. The tree then separates what a box around the whole triangle would have lumped
// together, as a spatial-split BVH does, at the cost of duplicate references; the traversal
// needs no change (a leaf tests the whole triangle; the all-hits query drops duplicates).
//
// `budget`: at most budget * triangles extra references (0: none). They go to the triangles
// whose box area most exceeds their own area, in proportion to the cube root of that excess
// (Karras and Aila's priority). Cuts are at planes of a power-of-two grid over `scene`
// (the coarsest grid plane crossing the piece's longest axis), so that pieces of neighbouring
// triangles line up with the top-level splits the SAH build will make.
//
// Appends to out_bounds / out_ids: one entry per piece, ids[i] repeated per piece; the piece
// boxes are conservative (rounded outwards) and lie within the triangle's own box.
void presplit_triangles(std::span<const Triangle> triangles, std::span<const std::uint32_t> ids,
                        std::span<const Aabb> bounds, const Aabb& scene, float budget,
                        HugePageVector<Aabb>& out_bounds, HugePageVector<std::uint32_t>& out_ids);

// How poorly a triangle set fills its boxes: the summed surface areas of the triangles'
// boxes over twice their summed areas (a box's surface counts both faces, and so does the
// factor 2). An evenly tessellated surface stays near 2-6 whatever its orientation; long thin
// diagonal triangles give hundreds. It estimates how many more triangles a ray enters the box
// of than it crosses, which is what pre-splitting cuts down. 0 for an empty set.
double box_fill_ratio(std::span<const Triangle> triangles, std::span<const std::uint32_t> ids,
                      std::span<const Aabb> bounds);

// The box of the part of `tri` inside `box` (empty Aabb when they do not meet), rounded
// outwards to float and clamped to `box`. Exposed for the tests.
Aabb clipped_triangle_bounds(const Triangle& tri, const Aabb& box);

}  // namespace tessera
