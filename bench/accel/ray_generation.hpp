#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/geometry/triangle.hpp"

namespace tessera::bench {

// Primary rays through pixel centres of a pinhole camera that frames `bounds`: placed 2.5
// bounding-sphere radii from the centre in the fixed direction (0.3, -1, 0.25) with +z up
// (Blender's front view of Suzanne, slightly from the right and above), with the narrowest
// field of view that shows the whole box. Row-major, top row first.
std::vector<Ray> make_primary_rays(const Aabb& bounds, std::uint32_t width, std::uint32_t height);

// One cosine-distributed bounce ray per primary hit, about the geometric normal facing
// the incoming ray, starting at the hit point lifted off the surface by 1e-5 of the
// scene's radius. Misses make no ray. Deterministic: the direction depends only on the
// primary ray's index.
std::vector<Ray> make_diffuse_rays(std::span<const Ray> primary,
                                   std::span<const HitRecord> primary_hits,
                                   std::span<const Triangle> triangles, const Aabb& bounds);

}  // namespace tessera::bench
