#include "variant_choice.hpp"

namespace tessera {

PipelineFeatures required_pipeline_features(const SceneFeatures& features,
                                            IntegratorKind integrator) {
  const bool path = integrator == IntegratorKind::kPath;
  return PipelineFeatures{features.shapes, path && features.light_count > 0,
                          path && features.specular(), path && features.aovs != 0};
}

const RenderVariant& choose_render_variant(IntegratorKind integrator,
                                           const PipelineFeatures& required, bool all_features) {
  return all_features ? all_features_variant(integrator)
                      : select_render_variant(integrator, required);
}

}  // namespace tessera
