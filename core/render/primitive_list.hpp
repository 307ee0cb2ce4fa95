#pragma once
// The primitives a scene build has stored, gathered for the acceleration structures and the
// light list: each shape goes into its type's flat array and is recorded here by its tagged
// reference, in build order (which the BVH build and the light list keep).
#include <cstdint>
#include <span>
#include <vector>

#include "light_list.hpp"
#include "tessera/accel/bvh.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "tessera/render/scene_data.hpp"

namespace tessera {

class PrimitiveList {
 public:
  // `materials` and `lights` belong to the scene being built and outlive the list.
  PrimitiveList(std::span<const Material> materials, std::vector<LightSource>& lights)
      : materials_(materials), lights_(lights) {}

  // Records element `index` of `type`'s array: for the acceleration structures (the tree
  // of hidden shapes when it is not visible to camera rays), for the light list when it
  // emits with a sampled area (`light_area` > 0).
  void add(PrimitiveType type, std::uint32_t index, const Aabb& box, bool visible,
           std::uint32_t material, float light_area);

  // Appends `shape` to `array`, the flat array of `type`, and records it.
  template <typename Shape>
  void store(std::vector<Shape>& array, PrimitiveType type, const Shape& shape, bool visible,
             std::uint32_t material) {
    const auto index = static_cast<std::uint32_t>(array.size());
    array.push_back(shape);
    add(type, index, tessera::bounds(shape), visible, material, sampled_light_area(type, shape));
  }

  // Builds the structures over the visible primitives. Triangles (their references index
  // `triangles`) go to the SIMD structure the CPU traces them with (accel/triangle_accel.hpp),
  // every other shape to the BVH; BvhView::triangles joins the two for BvhTracer. Up to
  // kShapeBvhMaxTriangles triangles beside other shapes stay in the BVH instead (no SIMD
  // structure). Shapes hidden from camera rays go, triangles too, into `hidden_bvh`, left
  // empty when there are none. Once, after the last shape is stored: it reorders the list.
  // Returns the references of the triangles put into the SIMD structure (a GPU upload puts
  // them into its own BVH: render/device_scene_source.hpp). `triangle_options`: how the SIMD
  // structure is built (render/accel_builder.hpp).
  std::vector<std::uint32_t> build_accelerators(std::span<const Triangle> triangles,
                                                const AccelBuildOptions& triangle_options,
                                                TriangleAccel& triangle_accel, Bvh& bvh,
                                                Bvh& hidden_bvh);

  // The bounds of every bounded primitive, hidden or not (planes are not among them).
  Aabb bounds() const {
    Aabb box;
    for (const Aabb& b : boxes_) box.extend(b);
    for (const Aabb& b : hidden_boxes_) box.extend(b);
    return box;
  }

 private:
  std::span<const Material> materials_;
  std::vector<LightSource>& lights_;
  std::vector<Aabb> boxes_;                // of the visible primitives
  std::vector<std::uint32_t> references_;  // tagged, parallel to boxes_
  std::vector<Aabb> hidden_boxes_;         // of the primitives hidden from camera rays
  std::vector<std::uint32_t> hidden_references_;
};

}  // namespace tessera
