#pragma once
#include <cstdint>
#include <span>

#include "tessera/accel/bvh.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera {

// Binary BVH over triangles with spatial splits (Stich, Friedrich and Dietrich 2009,
// "Spatial splits in bounding volume hierarchies"): where the best object split leaves its
// two children overlapping, the builder also tries cutting the node's box by a plane and
// sending each triangle that straddles it to both sides, each with the box of its part on
// that side, and keeps whichever split the surface-area heuristic prefers. A triangle can
// then be referenced from several leaves (its id repeated in Bvh::primitives), each box
// tighter than the whole triangle's. Long or large triangles across a mesh of small ones
// cost far fewer box and triangle tests that way; an evenly tessellated mesh gets few
// spatial splits.
struct SpatialSplitOptions {
  BvhBuildOptions bvh{};  // leaf size, block size, costs, bins, parallel
  // Spatial splits are tried only where the object split's children overlap by more than
  // this fraction of the root box's surface area (Stich et al.'s alpha, who use 1e-5).
  // Measured on the engine mesh (bench/accel/README.md): 1e-5 / 1e-4 / 1e-3 / 1e-2 built in
  // 0.96 / 0.62 / 0.34 / 0.18 s to trees of SAH cost 27.4 / 27.6 / 28.0 / 29.5 (34.6 without
  // spatial splits), 1e-3 keeping the build within twice Embree's high-quality build.
  float min_overlap = 1e-3f;
  // Below that, where the node's references fill their boxes poorly (their boxes' summed
  // surface areas over their doubled areas, as box_fill_ratio counts, at least
  // min_fill_ratio_deep) and the children overlap by more than min_overlap_of_node of the
  // node's own surface area (Embree's share for its spatial splits). The root's rule ties the
  // search to the scene's extent: a grass field 10-40 m across overlaps at the scale of a few
  // blades, far below 1e-3 of its root, and the splits this rule finds there (cutting only
  // the references that fill their boxes poorly) took three held-out fields from 0.92-0.99x
  // Embree's high-quality build to 0.98-1.07x, for builds 1.2-1.8x Embree's
  // (bench/accel/README.md). Evenly tessellated surfaces fill their boxes at 2-6 (the suite's
  // meshes 2.9-5.2): of 17 such meshes only three trees changed, by under 0.3% of their cost.
  float min_fill_ratio_deep = 8.0f;
  float min_overlap_of_node = 0.1f;
  // Nor in nodes of fewer references than this: a spatial search splits every reference at
  // every bin plane it crosses on all three axes, which near the leaves costs far more than
  // the few references it could separate save. Measured (2026-12-07, one thread): CGAL's
  // cheese, whose large faces cross many bins and overlap everywhere, built in 0.070 s with
  // the search in every node, 0.055 s from 32 references (SAH cost 28.435 -> 28.417) and
  // 0.046 s from 64 (28.472); engine's SAH cost 28.120 -> 28.204 (32) and 28.328 (64), whose
  // diffuse rays were 1-2% slower at 64; the other meshes within 0.3%.
  std::uint32_t min_spatial_references = 32;
  // Extra references allowed, per triangle: once used up, only object splits remain.
  float max_extra_references = 0.5f;
};

// `triangles[ids[i]]` is primitive i; leaves hold ids. Degenerate and non-finite triangles
// must have been dropped by the caller (as TriangleAccel does).
Bvh build_sbvh(std::span<const Triangle> triangles, std::span<const std::uint32_t> ids,
               const SpatialSplitOptions& options);

}  // namespace tessera
