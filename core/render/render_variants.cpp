#include "tessera/render/render_variants.hpp"

#include <stdexcept>
#include <vector>

#include "variants/tile_loop.hpp"

namespace tessera {

namespace variants {
template <>
std::array<RenderVariant, 8> path_variants<kShapeTriangle>();
template <>
std::array<RenderVariant, 8> path_variants<kShapeSphere | kShapeQuad>();
template <>
std::array<RenderVariant, 8> path_variants<kCommonShapes>();
template <>
std::array<RenderVariant, 8> path_variants<kAllShapes>();
template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kShapeTriangle>();
template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kShapeSphere | kShapeQuad>();
template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kCommonShapes>();
template <>
std::array<RenderVariant, kPreviewVariantCount> preview_variants<kAllShapes>();
}  // namespace variants

namespace {

std::vector<RenderVariant> collect_variants() {
  std::vector<RenderVariant> all;
  const auto append = [&](const auto& list) { all.insert(all.end(), list.begin(), list.end()); };
  // Shape classes smallest first, so a first-fit search finds the smallest cover.
  append(variants::path_variants<kShapeTriangle>());
  append(variants::path_variants<kShapeSphere | kShapeQuad>());
  append(variants::path_variants<kCommonShapes>());
  append(variants::path_variants<kAllShapes>());
  append(variants::preview_variants<kShapeTriangle>());
  append(variants::preview_variants<kShapeSphere | kShapeQuad>());
  append(variants::preview_variants<kCommonShapes>());
  append(variants::preview_variants<kAllShapes>());
  return all;
}

}  // namespace

std::span<const RenderVariant> compiled_render_variants() {
  static const std::vector<RenderVariant> variants = collect_variants();
  return variants;
}

const RenderVariant& select_render_variant(IntegratorKind integrator,
                                           const PipelineFeatures& required) {
  for (const RenderVariant& v : compiled_render_variants())
    if (v.integrator == integrator && v.features.covers(required)) return v;
  return all_features_variant(integrator);
}

const RenderVariant& all_features_variant(IntegratorKind integrator) {
  const RenderVariant* widest = nullptr;
  for (const RenderVariant& v : compiled_render_variants())
    if (v.integrator == integrator && (widest == nullptr || v.features.covers(widest->features)))
      widest = &v;
  if (widest == nullptr) throw std::logic_error("no compiled variant for integrator");
  return *widest;
}

}  // namespace tessera
