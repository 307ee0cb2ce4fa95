#pragma once
// The geometry library's inputs made from scene descriptions: the patch a SplinePatchDesc
// describes (default knots filled in, the transform baked in when asked) and the uv
// periodicity the trimming loops of a TrimmedFaceDesc are unwrapped with.
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trim_loops.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// `placed`: map the control points by desc.transform (exact for any affine map, since
// B-splines and NURBS are affine invariant); otherwise leave them in object space.
SplinePatchDescription to_spline_patch_description(const SplinePatchDesc& desc, bool placed);

// Which uv directions of the surface wrap (u for sphere, disk, cylinder and cone; u and v
// for the torus), as build_trim_region needs it.
UvPeriodicity trimmed_surface_periodicity(const TrimmedSurfaceDesc& surface);

}  // namespace tessera
