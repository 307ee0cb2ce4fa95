#include "primitive_list.hpp"

#include <algorithm>

namespace tessera {

void PrimitiveList::add(PrimitiveType type, std::uint32_t index, const Aabb& box, bool visible,
                        std::uint32_t material, float light_area) {
  const std::uint32_t reference = make_primitive_ref(type, index);
  (visible ? boxes_ : hidden_boxes_).push_back(box);
  (visible ? references_ : hidden_references_).push_back(reference);
  add_if_sampled_emitter(lights_, materials_[material], reference, light_area);
}

std::vector<std::uint32_t> PrimitiveList::build_accelerators(
    std::span<const Triangle> triangles, const AccelBuildOptions& triangle_options,
    TriangleAccel& triangle_accel, Bvh& bvh, Bvh& hidden_bvh) {
  const auto is_triangle = [](std::uint32_t reference) {
    return primitive_type(reference) == PrimitiveType::kTriangle;
  };
  const auto triangle_count =
      static_cast<std::size_t>(std::count_if(references_.begin(), references_.end(), is_triangle));
  // Beside other shapes, a few triangles stay in their BVH: a second structure costs every
  // ray its own walk (ray setup, box tests, a block of four triangles at least: ~240
  // instructions for the single triangle of examples/scenes/shapes.yaml), more than the
  // triangles' lanes in the shape walk's box tests and the scalar test of those a ray does
  // reach. tessera::intersect gives the same hits as the SIMD kernels bit for bit, so only
  // the cost changes. Measured (callgrind, the Cornell box with a mesh sphere instead of its
  // spheres): 8 triangles -15% render instructions, 32 -32%, 128 -13%, 512 -10%, 2048 -9%.
  const bool other_shapes = triangle_count < references_.size();
  const bool triangles_apart = !other_shapes || triangle_count > kShapeBvhMaxTriangles;
  std::vector<Triangle> visible_triangles;
  std::vector<std::uint32_t> triangle_references;
  std::size_t kept = 0;  // the other shapes, compacted in place, order kept
  for (std::size_t i = 0; i < references_.size(); ++i) {
    if (triangles_apart && is_triangle(references_[i])) {
      visible_triangles.push_back(triangles[primitive_index(references_[i])]);
      triangle_references.push_back(references_[i]);
    } else {
      boxes_[kept] = boxes_[i];
      references_[kept++] = references_[i];
    }
  }
  boxes_.resize(kept);
  references_.resize(kept);
  if (!visible_triangles.empty())
    triangle_accel = TriangleAccel::build(visible_triangles, triangle_options, triangle_references);
  // One shape per leaf: a shape test (in double; ~140 instructions for a quad when this was
  // measured, before Quad::make precomputed its axes) costs far more than a box test, so a tight
  // box per shape pays even where the SAH's unit costs would share a leaf (measured: -9% render
  // instructions on a Cornell box of quads and spheres).
  BvhBuildOptions options;
  options.max_leaf_size = 1;
  bvh = build_bvh(boxes_, references_, options);
  // Hidden shapes are few (mostly lights), triangles among them tested by the scalar test.
  if (!hidden_references_.empty())
    hidden_bvh = build_bvh(hidden_boxes_, hidden_references_, options);
  return triangle_references;
}

}  // namespace tessera
