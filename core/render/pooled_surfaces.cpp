#include "pooled_surfaces.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include "shape_placement.hpp"
#include "tessera/scene/spline_geometry.hpp"

namespace tessera {

namespace {

// Build errors were reported by validate_scene already; one here means a caller skipped it.
void require_built(const std::string& error) {
  if (!error.empty())
    throw std::invalid_argument(error + " (validate_scene rejects such scenes before rendering)");
}

std::string geometry_field(std::uint32_t source_index) {
  return "geometry[" + std::to_string(source_index) + "]";
}

}  // namespace

void place_patch(const SplinePatchDesc& desc, PooledSurfaceArrays& to, PrimitiveList& primitives) {
  SplinePatch patch;
  require_built(build_spline_patch(to_spline_patch_description(desc, true), to.patch_pool, patch,
                                   geometry_field(desc.source_index)));
  const auto index = static_cast<std::uint32_t>(to.patches.size());
  to.patches.push_back(patch);
  primitives.add(PrimitiveType::kSplinePatch, index, tessera::bounds(patch), desc.visible,
                 desc.material, 0.0f);
}

void place_trimmed_face(const TrimmedFaceDesc& desc, PooledSurfaceArrays& to,
                        PrimitiveList& primitives) {
  const std::string field = geometry_field(desc.source_index);
  const auto store = [&](auto& array, PrimitiveType type, const auto& surface) {
    using Surface = std::decay_t<decltype(surface)>;
    Trimmed<Surface> face;
    require_built(build_trimmed_face(surface, desc.loops, to.trim_pool, face, field));
    const auto index = static_cast<std::uint32_t>(array.size());
    array.push_back(make_instance(face, desc.transform));
    primitives.add(type, index, tessera::bounds(array.back()), desc.visible, desc.material, 0.0f);
  };
  std::visit(
      [&](const auto& surface_desc) {
        using D = std::decay_t<decltype(surface_desc)>;
        if constexpr (std::is_same_v<D, SplinePatchDesc>) {
          SplinePatchDesc object = surface_desc;
          object.material = desc.material;
          SplinePatch patch;
          require_built(build_spline_patch(to_spline_patch_description(object, false),
                                           to.patch_pool, patch, field + ".surface"));
          store(to.trimmed_patches, PrimitiveType::kTrimmedPatch, patch);
        } else {
          const auto surface = placed_surface(surface_desc, kObjectSpace, desc.material);
          using S = std::decay_t<decltype(surface)>;
          if constexpr (std::is_same_v<S, Plane>)
            store(to.trimmed_planes, PrimitiveType::kTrimmedPlane, surface);
          else if constexpr (std::is_same_v<S, Disk>)
            store(to.trimmed_disks, PrimitiveType::kTrimmedDisk, surface);
          else if constexpr (std::is_same_v<S, Quad>)
            store(to.trimmed_quads, PrimitiveType::kTrimmedQuad, surface);
          else if constexpr (std::is_same_v<S, Sphere>)
            store(to.trimmed_spheres, PrimitiveType::kTrimmedSphere, surface);
          else if constexpr (std::is_same_v<S, Cylinder>)
            store(to.trimmed_cylinders, PrimitiveType::kTrimmedCylinder, surface);
          else if constexpr (std::is_same_v<S, Cone>)
            store(to.trimmed_cones, PrimitiveType::kTrimmedCone, surface);
          else
            store(to.trimmed_tori, PrimitiveType::kTrimmedTorus, surface);
        }
      },
      desc.surface);
}

void bind_pools(PooledSurfaceArrays& surfaces) {
  for (auto& patch : surfaces.patches) bind_pieces(patch, surfaces.patch_pool.pieces.data());
  const auto bind_faces = [&](auto& faces) {
    for (auto& face : faces) bind_trim_region(face.shape.region, surfaces.trim_pool);
  };
  bind_faces(surfaces.trimmed_planes);
  bind_faces(surfaces.trimmed_disks);
  bind_faces(surfaces.trimmed_quads);
  bind_faces(surfaces.trimmed_spheres);
  bind_faces(surfaces.trimmed_cylinders);
  bind_faces(surfaces.trimmed_cones);
  bind_faces(surfaces.trimmed_tori);
  bind_faces(surfaces.trimmed_patches);
  for (auto& face : surfaces.trimmed_patches)
    bind_pieces(face.shape.surface, surfaces.patch_pool.pieces.data());
}

}  // namespace tessera
