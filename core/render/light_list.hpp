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
                            std::uint32_t primitive, float sampled_area);

// Appends every analytic light (SceneView::analytic_lights, `count` of them), after the
// emitting shapes. The environment and suns with an extent are visible (escaping rays find
// them); the deltas are not.
void add_analytic_lights(std::vector<LightSource>& lights, std::span<const AnalyticLight> analytic);

// Once every emitter is in: sorts the list by primitive reference (find_light searches it)
// and gives each light its pick probability, in proportion to its power, with the alias
// table that draws by it. Power is emitted flux (luminance): a two-sided emitting shape
// 2 pi L A; a point light 4 pi I; a spot 2 pi I (1 - (cos_inner + cos_outer) / 2); a distant
// light E pi R^2 and the environment pi 4 pi R^2 L_average, where R is `scene_radius`
// (lit_region_radius: what reaches the lit region from infinity). When the list has lights
// at infinity and bounded ones, those at infinity keep a share of the picks within
// [0.1, 0.9], as infinite_light_share, so neither side starves.
std::vector<AliasSlot> finish_light_list(std::vector<LightSource>& lights,
                                         std::span<const Material> materials,
                                         const SceneView& shapes, float scene_radius);

// The radius R of the region the lights at infinity are weighed over: the sphere around
// the bounded lights and the camera, where the light that matters is gathered. The bounds
// of all the geometry would let one huge shape decide: RayON's ground, a sphere of radius
// 1000, made a dim sky 13,000 times the power of a 64 m^2 panel, which was then sampled
// once in 13,000 picks. With no bounded light, `scene_radius` (R cancels between lights
// at infinity).
float lit_region_radius(const std::vector<LightSource>& lights, const SceneView& shapes,
                        const vec3& camera_position, float scene_radius);

// The share of the lights' power at infinity (distant lights, the environment: the list's
// tail from shapes.first_infinite_light), which pick_light gives them when it picks the
// others by the light tree; kept within [0.1, 0.9] so neither side starves.
float infinite_light_share(const std::vector<LightSource>& lights,
                           std::span<const Material> materials, const SceneView& shapes,
                           float scene_radius);

// The light tree over a finished list's bounded lights (those before
// shapes.first_infinite_light; light_tree.hpp), recording each one's path in it.
// Built as a binary tree split where the sum of power times bounds area of the two halves
// is least (the orientation-free form of Conty and Kulla's cost), in 12 bins per axis, then
// collapsed to four children per node. The binary depth stays under 64 because deep
// branches fall back to median splits, so the four-wide tree's stays within
// kLightTreeMaxDepth.
std::vector<LightTreeNode> build_light_tree(std::vector<LightSource>& lights,
                                            std::span<const Material> materials,
                                            const SceneView& shapes);

}  // namespace tessera
