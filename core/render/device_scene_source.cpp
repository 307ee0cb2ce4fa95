// PreparedScene::device_source: the job's scene as a GPU backend uploads it
// (tessera/render/device_scene_source.hpp), and the CPU render through it that tests the
// layout without a GPU.
#include <algorithm>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "tessera/render/baked_placements.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {

namespace {

// A buffer for `array` whose copy the view's field `kField` (a SceneShapes or SceneView
// member) points to.
template <auto kField, typename T>
DeviceBuffer buffer_for(const std::vector<T>& array) {
  DeviceBuffer b;
  b.host = array.data();
  b.bytes = array.size() * sizeof(T);
  b.assign = [](SceneView& view, const void* copy) { view.*kField = static_cast<const T*>(copy); };
  return b;
}

// The array of primitive type `kTag` the device copies: triangles from `triangles`, which is
// the scene's own or those with the baked placements after them.
template <PrimitiveType kTag>
const auto& device_array(const PrimitiveArrays& arrays, const std::vector<Triangle>& triangles) {
  if constexpr (kTag == PrimitiveType::kTriangle)
    return triangles;
  else
    return arrays.of<kTag>();
}

// One buffer per stored primitive type that has any.
template <typename... P>
void add_shape_buffers(scene_detail::PrimitiveList<P...>, const PrimitiveArrays& arrays,
                       const std::vector<Triangle>& triangles, std::vector<DeviceBuffer>& buffers) {
  const auto add = [&](auto primitive) {
    using Primitive = decltype(primitive);
    const auto& array = device_array<Primitive::tag>(arrays, triangles);
    if (!array.empty()) buffers.push_back(buffer_for<Primitive::array>(array));
  };
  (add(P{}), ...);
}

// Why the device path cannot render these arrays, or "" when it can: patches and trimmed
// faces point into host pools (Bézier pieces, trim loops), which are not uploaded.
template <typename... P>
std::string unsupported_shapes(scene_detail::PrimitiveList<P...>, const PrimitiveArrays& arrays) {
  bool host_pointers = false;
  const auto check = [&](auto primitive) {
    using Primitive = decltype(primitive);
    if constexpr ((Primitive::shape_bit & (kShapePatch | kShapeTrimmed)) != 0)
      host_pointers = host_pointers || !arrays.of<Primitive::tag>().empty();
  };
  (check(P{}), ...);
  return host_pointers ? "spline patches and trimmed faces point into host memory" : "";
}

}  // namespace

const DeviceSceneSource& PreparedScene::device_source() const {
  std::call_once(device_source_once_, [this] {
    auto source = std::make_unique<DeviceSceneSource>();
    if (settings_.integrator != IntegratorKind::kPath)
      source->unsupported = std::string("the device runs the path tracer, not the ") +
                            to_string(settings_.integrator) + " integrator";
    if (source->unsupported.empty())
      source->unsupported = unsupported_shapes(scene_detail::StoredPrimitives{}, arrays_);
    const std::vector<Triangle>& own_triangles = arrays_.of<PrimitiveType::kTriangle>();
    if (source->unsupported.empty() && !mesh_placements_.empty())
      source->unsupported = baked_placements_refusal(
          baked_placement_triangles(mesh_placements_, instanced_triangles_.size()),
          own_triangles.size());
    if (!source->unsupported.empty()) {  // nothing to upload: no BVH build
      device_source_ = std::move(source);
      return;
    }

    // One BVH over the shape BVH's primitives and the triangles kept apart from it.
    const SceneView host = view();
    SceneView& v = source->view;
    v = host;
    std::vector<std::uint32_t> references(bvh_.primitives.begin(), bvh_.primitives.end());
    references.insert(references.end(), simd_triangle_references_.begin(),
                      simd_triangle_references_.end());
    if (!mesh_placements_.empty()) {
      // The device has no instance level: every placement becomes triangles of its own,
      // after the scene's, and visible (placements of shared geometry are). Shared and
      // baked meshes store attributes alike (stores_triangle_attributes decides for all).
      const BakedPlacements baked =
          bake_placements(mesh_placements_, instanced_triangles_, instanced_attributes_);
      const bool stores_attributes = !baked.attributes.empty();
      if (stores_attributes ? triangle_attributes_.size() != own_triangles.size()
                            : !triangle_attributes_.empty())
        throw std::logic_error("device_source: shared and baked meshes store attributes unlike");
      source->triangles.reserve(own_triangles.size() + baked.triangles.size());
      source->triangles.assign(own_triangles.begin(), own_triangles.end());
      for (std::size_t i = 0; i < baked.triangles.size(); ++i)
        references.push_back(make_primitive_ref(
            PrimitiveType::kTriangle, static_cast<std::uint32_t>(source->triangles.size() + i)));
      source->triangles.insert(source->triangles.end(), baked.triangles.begin(),
                               baked.triangles.end());
      v.triangles = source->triangles.data();
      if (stores_attributes) {
        source->triangle_attributes.reserve(source->triangles.size());
        source->triangle_attributes.assign(triangle_attributes_.begin(),
                                           triangle_attributes_.end());
        source->triangle_attributes.insert(source->triangle_attributes.end(),
                                           baked.attributes.begin(), baked.attributes.end());
        v.triangle_attributes = source->triangle_attributes.data();
      }
    }
    const std::vector<Triangle>& triangles =
        mesh_placements_.empty() ? own_triangles : source->triangles;
    const std::vector<TriangleAttributes>& triangle_attributes =
        source->triangle_attributes.empty() ? triangle_attributes_ : source->triangle_attributes;
    std::vector<Aabb> boxes(references.size());
    for (std::size_t i = 0; i < references.size(); ++i)
      boxes[i] = scene_detail::dispatch<kAllShapes>(
          v, references[i], Aabb{}, [](const auto& shape) { return bounds(shape); });
    source->bvh = build_bvh(boxes, references);
    source->compressed = compress_bvh(source->bvh);

    v.bvh = source->bvh.view();  // no SIMD triangles, instance level or wide nodes
    if (!source->compressed.nodes.empty()) {
      v.bvh.compressed_nodes = source->compressed.nodes.data();
      v.bvh.compressed_primitives = source->compressed.primitives.data();
    }
    v.bvh.hidden_nodes = host.bvh.hidden_nodes;  // the hidden shapes' tree, as on the CPU
    v.bvh.hidden_primitives = host.bvh.hidden_primitives;
    v.bvh.hidden_node_count = host.bvh.hidden_node_count;
    v.instanced_triangles = nullptr;
    v.instanced_attributes = nullptr;
    v.mesh_placements = nullptr;
    v.mesh_placement_count = 0;

    std::vector<DeviceBuffer>& b = source->buffers;
    add_shape_buffers(scene_detail::StoredPrimitives{}, arrays_, triangles, b);
    const auto add = [&b](const DeviceBuffer& buffer) {
      if (buffer.bytes > 0) b.push_back(buffer);
    };
    add(buffer_for<&SceneView::triangle_attributes>(triangle_attributes));
    add(buffer_for<&SceneView::materials>(materials_));
    add(buffer_for<&SceneView::textures>(textures_));
    add(buffer_for<&SceneView::texels>(texels_));
    add(buffer_for<&SceneView::lights>(lights_));
    add(buffer_for<&SceneView::light_alias>(light_alias_));
    add(buffer_for<&SceneView::light_tree>(light_tree_));
    add(buffer_for<&SceneView::analytic_lights>(analytic_lights_));
    const auto sized = [](const void* host_data, std::size_t bytes,
                          void (*assign)(SceneView&, const void*)) {
      DeviceBuffer buffer;
      buffer.host = host_data;
      buffer.bytes = bytes;
      buffer.assign = assign;
      return buffer;
    };
    add(sized(source->bvh.nodes.data(), source->bvh.nodes.size() * sizeof(BvhNode),
              [](SceneView& view, const void* copy) {
                view.bvh.nodes = static_cast<const BvhNode*>(copy);
              }));
    add(sized(source->bvh.primitives.data(), source->bvh.primitives.size() * sizeof(std::uint32_t),
              [](SceneView& view, const void* copy) {
                view.bvh.primitives = static_cast<const std::uint32_t*>(copy);
              }));
    add(sized(source->compressed.nodes.data(),
              source->compressed.nodes.size() * sizeof(CompressedWideNode),
              [](SceneView& view, const void* copy) {
                view.bvh.compressed_nodes = static_cast<const CompressedWideNode*>(copy);
              }));
    add(sized(source->compressed.primitives.data(),
              source->compressed.primitives.size() * sizeof(std::uint32_t),
              [](SceneView& view, const void* copy) {
                view.bvh.compressed_primitives = static_cast<const std::uint32_t*>(copy);
              }));
    add(sized(hidden_bvh_.nodes.data(), hidden_bvh_.nodes.size() * sizeof(BvhNode),
              [](SceneView& view, const void* copy) {
                view.bvh.hidden_nodes = static_cast<const BvhNode*>(copy);
              }));
    add(sized(hidden_bvh_.primitives.data(), hidden_bvh_.primitives.size() * sizeof(std::uint32_t),
              [](SceneView& view, const void* copy) {
                view.bvh.hidden_primitives = static_cast<const std::uint32_t*>(copy);
              }));
    add(sized(environment_pixels_.data(), environment_pixels_.size() * sizeof(float),
              [](SceneView& view, const void* copy) {
                view.environment.image = static_cast<const float*>(copy);
              }));
    add(sized(environment_marginal_.data(), environment_marginal_.size() * sizeof(float),
              [](SceneView& view, const void* copy) {
                view.environment.distribution.marginal_cdf = static_cast<const float*>(copy);
              }));
    add(sized(environment_conditional_.data(), environment_conditional_.size() * sizeof(float),
              [](SceneView& view, const void* copy) {
                view.environment.distribution.conditional_cdf = static_cast<const float*>(copy);
              }));
    device_source_ = std::move(source);
  });
  return *device_source_;
}

TileStats PreparedScene::render_tile_device_layout(const TileRect& tile,
                                                   std::span<float> rgba) const {
  const DeviceSceneSource& source = device_source();
  if (!source.unsupported.empty())
    throw std::invalid_argument("render_tile_device_layout: " + source.unsupported);
  std::fill(rgba.begin(), rgba.end(), 0.0f);
  FilmPlanes film;
  film.beauty = rgba.data();
  // The variant the device kernel compiles (every feature on), not the scene's smallest.
  return all_features_variant(IntegratorKind::kPath).render(source.view, settings_, tile, film);
}

TileStats PreparedScene::render_tile_device_layout(const TileRect& tile, TilePasses& passes) const {
  const DeviceSceneSource& source = device_source();
  if (!source.unsupported.empty())
    throw std::invalid_argument("render_tile_device_layout: " + source.unsupported);
  const FilmPlanes film = film_for(tile, passes, 0);
  return all_features_variant(IntegratorKind::kPath).render(source.view, settings_, tile, film);
}

}  // namespace tessera
