#pragma once
// The light list (SceneView::lights): the emitters next-event estimation samples. Which
// emitters are in it, and in what order, decides the image, so the rule lives in one place.
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/math/alias_table.hpp"

#include "tessera/render/material.hpp"
#include "tessera/render/scene_data.hpp"

namespace tessera {

// The area by which next-event estimation samples `shape` of `type` when it emits: its
// surface area where the type has an area sampler (has_light_sampler), 0 otherwise (such
// emitters count only when a scattered ray hits them).
template <typename Shape>
float sampled_light_area(PrimitiveType type, const Shape& shape) {
  return has_light_sampler(type) ? surface_area(shape) : 0.0f;
}

// Appends `primitive` (a tagged reference) to `lights` when its material emits and it has a
// sampled area; hidden emitters count too, since they light the scene unseen.
void add_if_sampled_emitter(std::vector<LightSource>& lights, const Material& material,
                            std::uint32_t primitive, float sampled_area, bool visible);

// Once every emitter is in: sorts the list by primitive reference (find_light searches it)
// and gives each light its pick probability, in proportion to its power (emitted radiance's
// luminance times area), with the alias table that draws by it.
std::vector<AliasSlot> finish_light_list(std::vector<LightSource>& lights,
                                         std::span<const Material> materials,
                                         const SceneView& shapes);

// The light tree over a finished list (light_tree.hpp), recording each light's path in it.
// Split where the sum of power times bounds area of the two halves is least (the
// orientation-free form of Conty and Kulla's cost), in 12 bins per axis; depth stays under
// 64 because deep branches fall back to median splits.
std::vector<LightTreeNode> build_light_tree(std::vector<LightSource>& lights,
                                            std::span<const Material> materials,
                                            const SceneView& shapes);

}  // namespace tessera
