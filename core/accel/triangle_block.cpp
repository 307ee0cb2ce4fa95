#include "tessera/accel/triangle_block.hpp"

#include <limits>

namespace tessera {

std::uint32_t append_triangle_blocks(std::span<const Triangle> triangles,
                                     std::span<const std::uint32_t> ids,
                                     HugePageVector<TriangleBlock4>& blocks,
                                     std::span<const std::uint32_t> references) {
  const auto first = static_cast<std::uint32_t>(blocks.size());
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t start = 0; start < ids.size(); start += 4) {
    TriangleBlock4& block = blocks.emplace_back();
    for (std::size_t lane = 0; lane < 4; ++lane) {
      const bool used = start + lane < ids.size();
      const std::uint32_t id = used ? ids[start + lane] : kInvalidIndex;
      block.ids[lane] = used && !references.empty() ? references[id] : id;
      const Triangle* tri = used ? &triangles[ids[start + lane]] : nullptr;
      for (int axis = 0; axis < 3; ++axis) {
        block.vertices[0][axis][lane] = used ? tri->p0[axis] : kNaN;
        block.vertices[1][axis][lane] = used ? tri->p1[axis] : kNaN;
        block.vertices[2][axis][lane] = used ? tri->p2[axis] : kNaN;
      }
    }
  }
  return first;
}

}  // namespace tessera
