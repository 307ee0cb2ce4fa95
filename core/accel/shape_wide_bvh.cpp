#include "tessera/accel/shape_wide_bvh.hpp"

namespace tessera {

WideBvh collapse_shape_bvh(const Bvh& binary) {
  if (binary.primitives.size() < kShapeWideMinPrimitives) return {};
  for (const BvhNode& node : binary.nodes)
    if (node.is_leaf() && (node.offset > kWideMaxLeafFirst || node.count > kWideMaxLeafItems))
      return {};
  // Binary leaves stay leaves (no merging): the shape tests are scalar, so a box test per
  // primitive, eight at a time, is cheaper than testing a merged leaf's primitives.
  return collapse_to_wide(binary, [](std::uint32_t offset, std::uint32_t count) {
    return make_wide_leaf(offset, count);
  });
}

}  // namespace tessera
