#pragma once
#include <span>

#include "tessera/accel/bvh.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera {

// build_bvh over a triangle mesh's triangles but its degenerate ones (is_degenerate, which
// no ray hits), each referenced by its index: the device walks' benchmark and tracer
// (tessera-bench device-walk, gpu::MeshRayTracer) build their trees with it.
Bvh build_triangle_bvh(std::span<const Triangle> triangles, const BvhBuildOptions& options = {});

}  // namespace tessera
