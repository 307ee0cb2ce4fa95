#include <algorithm>

#include "tessera/accel/wide_bvh.hpp"

namespace tessera {

namespace {

struct SahWalk {
  const WideBvh& tree;
  WideSahCost cost{};

  // Sums the cost of the subtree under node `index`, whose box has surface area `area`.
  void node(std::uint32_t index, float area) {
    cost.nodes += area;
    const WideBvhNode& n = tree.nodes[index];
    for (std::uint32_t slot = 0; slot < kWideBvhWidth; ++slot) {
      const std::uint32_t child = n.children[slot];
      if (child == kWideEmptyChild) continue;
      const Aabb box{vec3(n.bounds[0][slot], n.bounds[2][slot], n.bounds[4][slot]),
                     vec3(n.bounds[1][slot], n.bounds[3][slot], n.bounds[5][slot])};
      const float child_area = box.surface_area();
      if (wide_is_leaf(child))
        cost.leaves += child_area * static_cast<float>(wide_leaf_count(child));
      else
        node(child, child_area);
    }
  }
};

}  // namespace

WideSahCost wide_sah_cost(const WideBvh& tree) {
  if (tree.nodes.empty()) return {};
  const WideBvhNode& root = tree.nodes[0];
  Aabb root_box;
  for (std::uint32_t slot = 0; slot < kWideBvhWidth; ++slot)
    if (root.children[slot] != kWideEmptyChild)
      root_box.extend(Aabb{vec3(root.bounds[0][slot], root.bounds[2][slot], root.bounds[4][slot]),
                           vec3(root.bounds[1][slot], root.bounds[3][slot], root.bounds[5][slot])});
  const float root_area = root_box.surface_area();
  if (!(root_area > 0.0f)) return {};
  SahWalk walk{tree};
  walk.node(0, root_area);
  return WideSahCost{walk.cost.nodes / root_area, walk.cost.leaves / root_area};
}

}  // namespace tessera
