#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/instance_accel.hpp"
#include "tessera/accel/triangle_accel.hpp"
#include "tessera/accel/wide_bvh.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/render/device_scene_source.hpp"
#include "tessera/render/primitive_arrays.hpp"
#include "tessera/render/render_variants.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/render/tile.hpp"
#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {

// A rendered tile: the beauty pass and the AOV planes the job asked for, each
// tile.width * tile.height RGBA floats. aovs[i] is empty unless bit i of the job's AOV
// mask is set (order of aov_names()).
struct TilePasses {
  std::vector<float> beauty;
  std::array<std::vector<float>, kAovCount> aovs;
};

struct TileAccumulation;

struct PrepareOptions {
  // Use the variant compiled with every feature instead of the smallest cover (tests and
  // benchmarks compare the two).
  bool all_features = false;
  // Meshes placed two or more times share one object-space structure (two-level); false
  // bakes every placement into world triangles (tests and benchmarks compare the two).
  bool instancing = true;
  // Scenes with two or more lights pick them by a light tree; false picks by power alone
  // (tests and benchmarks compare the two).
  bool light_tree = true;
};

// The render-ready scene of one job: float arrays per shape type, materials, lights, the
// BVH and the pipeline specialisation chosen for the scene's features. Built once per job
// and shared read-only by every tile and thread. This class holds the storage and renders
// tiles; each step of the build lives in the file of its concept (core/render/: material
// mapping, shape placement, mesh triangles, mesh sharing, pooled surfaces, the primitive
// list and light list, variant choice).
class PreparedScene {
 public:
  static std::shared_ptr<const PreparedScene> build(const SceneDescription& description,
                                                    const PrepareOptions& options = {});

  // Renders the beauty pass of one tile into `rgba` (tile.width * tile.height * 4 floats,
  // overwritten). AOVs, if the job asked for any, are computed but not returned.
  TileStats render_tile(const TileRect& tile, std::span<float> rgba) const;
  // Renders the beauty pass and every AOV the job asked for.
  TileStats render_tile(const TileRect& tile, TilePasses& passes) const;
  // Progressive refinement: `passes` hold this tile at `first` samples per pixel (what
  // render_tile or refine_tile left; ignored when `first` is 0); adds samples [first, end)
  // of the same sequence, so they then hold the image of `end` samples (equal, up to float
  // rounding, to rendering `end` at once). A job can so show passes of 1, 4, 16, 64 spp
  // without wasting any. Throws std::invalid_argument for first >= end, for planes of the
  // wrong size, and for first > 0 under adaptive sampling (a pixel's stopping state is not
  // kept between passes).
  TileStats refine_tile(const TileRect& tile, TilePasses& passes, std::uint32_t first,
                        std::uint32_t end) const;
  // Passes that add up bit for bit (refine_tile rescales its image between passes, so its
  // last pass differs from a single render by float rounding): adds samples
  // [state.samples_done, end) to `state` (tile_accumulation.hpp), each at its weight in a
  // render of settings().samples_per_pixel. A state with samples_done 0 is (re)started.
  // Throws std::invalid_argument for an end outside (samples_done, samples_per_pixel], for a
  // state of another tile or render, and under adaptive sampling.
  TileStats accumulate_tile(const TileRect& tile, TileAccumulation& state, std::uint32_t end) const;

  // The scene as a GPU backend uploads it (render/device_scene_source.hpp): built on first
  // use, then shared by every device and tile of the job. Thread-safe.
  const DeviceSceneSource& device_source() const;
  // Renders the beauty pass of one tile on the CPU through device_source().view: the binary
  // BVH walk, arrays and pipeline device code runs, so the device layout is checked against
  // render_tile on machines without a GPU. The source must be supported.
  TileStats render_tile_device_layout(const TileRect& tile, std::span<float> rgba) const;
  // The same with the job's AOV planes, as render_tile(tile, passes) lays them out.
  TileStats render_tile_device_layout(const TileRect& tile, TilePasses& passes) const;
  // The film of `passes` for samples from `first`: with `first` 0 every plane the job asks
  // for is sized to the tile and started (depth at +inf, the rest at 0) and the others
  // emptied; after that the planes must already hold the tile. The one place a tile's
  // planes are laid out, for the CPU's renders and a device's copies alike.
  FilmPlanes film_for(const TileRect& tile, TilePasses& passes, std::uint32_t first) const;

  // The specialisation this scene renders with, and what the scene needed.
  const RenderVariant& variant() const { return *variant_; }
  const PipelineFeatures& required_features() const { return required_; }

  const RenderSettings& settings() const { return settings_; }
  const SceneFeatures& features() const { return features_; }
  SceneView view() const;
  double build_seconds() const { return build_seconds_; }
  std::uint32_t bvh_depth() const { return bvh_.depth; }
  // Bytes of triangle storage: triangles, their attributes and acceleration structures,
  // baked and shared (the scene description's own copy is not counted).
  std::size_t triangle_bytes() const;
  // Placements of shared mesh geometry and the geometries they share (0 when every mesh
  // was baked).
  std::size_t shared_mesh_placements() const { return mesh_placements_.size(); }
  std::size_t shared_mesh_geometries() const { return shared_meshes_.size(); }
  // How the triangle structures were built (RenderSettings::accel_builder): the world one
  // and each shared geometry's.
  const AccelStats& triangle_accel_stats() const { return triangle_accel_.stats(); }
  const AccelStats& shared_mesh_accel_stats(std::size_t geometry) const {
    return shared_meshes_.at(geometry).stats();
  }

 private:
  PreparedScene() = default;

  // One flat array per stored primitive type (planes: visible ones only, outside the BVH).
  PrimitiveArrays arrays_;
  std::vector<TriangleAttributes> triangle_attributes_;  // empty unless a mesh has normals/uvs
  // Patches and trimmed faces hold plain pointers into these pools, bound once every shape
  // is built (the scene lives on the heap and never moves afterwards).
  SplinePatchPool patch_pool_;
  TrimPool trim_pool_;
  std::vector<Material> materials_;
  std::vector<Texture> textures_;  // their pyramids in texels_ (render/texture_pool.hpp)
  std::vector<vec3> texels_;
  std::vector<LightSource> lights_;
  std::vector<AliasSlot> light_alias_;  // pick_light's table over lights_
  std::uint32_t every_vertex_lights_[kMaxEveryVertexLights] = {};  // SceneView's
  std::uint32_t every_vertex_count_ = 0;
  std::vector<LightTreeNode> light_tree_;  // empty: pick_light uses the alias table
  Bvh bvh_;                                // every visible bounded shape but triangles
  TriangleAccel triangle_accel_;           // visible triangles, named by their tagged references
  std::vector<std::uint32_t> simd_triangle_references_;  // those triangles' references
  Bvh hidden_bvh_;  // shapes hidden from camera rays, triangles too (BvhView::hidden_nodes)
  std::uint32_t hidden_plane_count_ = 0;  // SceneShapes::hidden_plane_count
  // bvh_ in eight-wide nodes: what the CPU walks (accel/shape_wide_bvh.hpp).
  WideBvh shape_wide_bvh_;
  // Shared mesh geometry: object-space triangles (and attributes when stored) of every
  // geometry back to back, one structure per geometry, the placements and their top level.
  std::vector<Triangle> instanced_triangles_;
  std::vector<TriangleAttributes> instanced_attributes_;
  std::vector<TriangleAccel> shared_meshes_;  // sized before instance_accel_ points into it
  std::vector<MeshPlacement> mesh_placements_;
  InstanceAccel instance_accel_;
  Camera camera_{};
  vec3 background_{0.0f};
  // Lights that are not shapes and the environment (SceneView says how they are laid out).
  std::vector<AnalyticLight> analytic_lights_;
  Environment environment_;
  // An image environment's pixels and sampling tables (environment_ points into them).
  std::vector<float> environment_pixels_, environment_marginal_, environment_conditional_;
  std::uint32_t first_analytic_light_ = 0;
  std::uint32_t first_infinite_light_ = 0;
  std::uint32_t environment_light_ = 0;
  float infinite_pick_ = 0.0f;
  float spawn_scale_ = 1.0f;  // SceneView::spawn_scale
  RenderSettings settings_;
  SceneFeatures features_;
  PipelineFeatures required_;
  const RenderVariant* variant_ = nullptr;
  double build_seconds_ = 0.0;
  mutable std::once_flag device_source_once_;
  mutable std::unique_ptr<DeviceSceneSource> device_source_;
};

}  // namespace tessera
