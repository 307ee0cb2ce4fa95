#pragma once
// Which compiled pipeline specialisation a scene renders with (the compiled list itself is
// render_variants.hpp).
#include "tessera/render/pipeline_features.hpp"
#include "tessera/render/render_variants.hpp"
#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/scene_features.hpp"

namespace tessera {

// What a scene needs of its pipeline: its shapes, and for the path tracer direct lighting
// (when it has lights to sample), specular materials and AOVs. The preview integrators need
// none of the three (their variants fix what they use).
PipelineFeatures required_pipeline_features(const SceneFeatures& features,
                                            IntegratorKind integrator);

// The smallest variant of `integrator` covering `required`, or with `all_features` the one
// compiled with every feature (tests and benchmarks compare the two).
const RenderVariant& choose_render_variant(IntegratorKind integrator,
                                           const PipelineFeatures& required, bool all_features);

}  // namespace tessera
