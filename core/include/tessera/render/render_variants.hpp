#pragma once
#include <array>
#include <span>

#include "tessera/render/film.hpp"
#include "tessera/render/pipeline_features.hpp"
#include "tessera/render/scene_data.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

struct TileStats {
  std::uint64_t rays = 0;
};

using RenderTileFunction = TileStats (*)(const SceneView&, const RenderSettings&, const TileRect&,
                                         const FilmPlanes&);

// One compiled pipeline specialisation and the features it was compiled with.
struct RenderVariant {
  IntegratorKind integrator;
  PipelineFeatures features;
  RenderTileFunction render;
};

// Every specialisation compiled into the library, smallest feature sets first within each
// integrator. The path tracer has 24 (3 shape classes x lights x specular x AOVs); the
// preview integrators vary only by shape class (3 each).
std::span<const RenderVariant> compiled_render_variants();

// The smallest compiled variant of `integrator` whose features cover `required`.
const RenderVariant& select_render_variant(IntegratorKind integrator,
                                           const PipelineFeatures& required);

// The variant of `integrator` compiled with every feature on (for tests and benchmarks).
const RenderVariant& all_features_variant(IntegratorKind integrator);

}  // namespace tessera
