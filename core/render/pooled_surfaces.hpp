#pragma once
// Spline patches and trimmed faces: shapes whose data (Bézier pieces, trim loops) lives in
// pools shared by the whole scene. Each shape holds plain pointers into its pool, so the
// pointers are bound only once every shape is built and the pools have their final size.
#include <vector>

#include "primitive_list.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

// The scene's storage for pooled shapes (PreparedScene owns it), one array per type.
struct PooledSurfaceArrays {
  SplinePatchPool& patch_pool;
  TrimPool& trim_pool;
  std::vector<SplinePatch>& patches;
  std::vector<Instance<Trimmed<Plane>>>& trimmed_planes;
  std::vector<Instance<Trimmed<Disk>>>& trimmed_disks;
  std::vector<Instance<Trimmed<Quad>>>& trimmed_quads;
  std::vector<Instance<Trimmed<Sphere>>>& trimmed_spheres;
  std::vector<Instance<Trimmed<Cylinder>>>& trimmed_cylinders;
  std::vector<Instance<Trimmed<Cone>>>& trimmed_cones;
  std::vector<Instance<Trimmed<Torus>>>& trimmed_tori;
  std::vector<Instance<Trimmed<SplinePatch>>>& trimmed_patches;
};

// A patch, its transform baked into the control points (exact: B-splines are affine
// invariant), so it is stored as it stands in the world.
void place_patch(const SplinePatchDesc& desc, PooledSurfaceArrays& to, PrimitiveList& primitives);

// A trimmed face: always an instance of the trimmed surface in its own space (identity when
// untransformed), since the trim loops are in the surface's own uv.
void place_trimmed_face(const TrimmedFaceDesc& desc, PooledSurfaceArrays& to,
                        PrimitiveList& primitives);

// Points every pooled shape at where its data ended up; call after the last place_*.
void bind_pools(PooledSurfaceArrays& surfaces);

}  // namespace tessera
