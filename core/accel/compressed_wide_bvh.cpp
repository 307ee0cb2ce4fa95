#include "tessera/accel/compressed_wide_bvh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "tessera/accel/wide_bvh.hpp"

namespace tessera {

namespace {

using compressed_detail::plane;
using compressed_detail::power_of_two;

struct Child {
  Aabb box;
  std::uint32_t word = kWideEmptyChild;  // the wide node's child word
};

// The smallest exponent whose 255 steps from `lower` reach `upper` once rounded as the walk
// rounds them.
int quantization_exponent(float lower, float upper) {
  const double extent = static_cast<double>(upper) - static_cast<double>(lower);
  int e = kCompressedMinExponent;
  if (extent > 0.0) e = std::max(e, static_cast<int>(std::ceil(std::log2(extent / 255.0))));
  while (e < kCompressedMaxExponent && plane(lower, power_of_two(e), 255) < upper) ++e;
  if (plane(lower, power_of_two(e), 255) < upper)
    throw std::range_error("compress_bvh: a box too large to quantise");
  return e;
}

// Steps from `origin` of the lower plane at or below `value`, and of the upper plane at or
// above it, as the walk rounds them.
std::uint8_t quantize_down(float origin, float scale, float value) {
  double q = std::floor((static_cast<double>(value) - origin) / scale);
  q = std::clamp(q, 0.0, 255.0);
  auto steps = static_cast<int>(q);
  while (steps > 0 && plane(origin, scale, static_cast<std::uint8_t>(steps)) > value) --steps;
  return static_cast<std::uint8_t>(steps);
}

std::uint8_t quantize_up(float origin, float scale, float value) {
  double q = std::ceil((static_cast<double>(value) - origin) / scale);
  q = std::clamp(q, 0.0, 255.0);
  auto steps = static_cast<int>(q);
  while (steps < 255 && plane(origin, scale, static_cast<std::uint8_t>(steps)) < value) ++steps;
  return static_cast<std::uint8_t>(steps);
}

// Assigns the children to slots so that slot s holds a child that comes early along the
// directions of octant s (negative on the axes whose bit is set): greedily, the pairs of
// smallest projection of the child's centre first. The walk visits slot octant ^ k at step k.
std::array<Child, 8> order_for_octants(const std::vector<Child>& children, const Aabb& box) {
  struct Pair {
    float cost;
    std::uint32_t child, slot;
  };
  std::vector<Pair> pairs;
  const vec3 centre = box.centroid();
  for (std::uint32_t c = 0; c < children.size(); ++c) {
    const vec3 offset = children[c].box.centroid() - centre;
    for (std::uint32_t s = 0; s < 8; ++s) {
      const vec3 direction((s & 1U) != 0 ? -1.0f : 1.0f, (s & 2U) != 0 ? -1.0f : 1.0f,
                           (s & 4U) != 0 ? -1.0f : 1.0f);
      pairs.push_back(Pair{glm::dot(offset, direction), c, s});
    }
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
  std::array<Child, 8> slots{};
  std::array<bool, 8> placed{}, taken{};
  for (const Pair& p : pairs) {
    if (placed[p.child] || taken[p.slot]) continue;
    slots[p.slot] = children[p.child];
    placed[p.child] = true;
    taken[p.slot] = true;
  }
  return slots;
}

class Compressor {
 public:
  Compressor(const Bvh& binary, const WideBvh& wide, CompressedWideBvh& out)
      : binary_(binary), wide_(wide), out_(out) {}

  void fill(std::uint32_t wide_index, std::uint32_t index) {
    const WideBvhNode& source = wide_.nodes[wide_index];
    std::vector<Child> children;
    Aabb box;
    for (std::uint32_t s = 0; s < kWideBvhWidth; ++s) {
      const std::uint32_t word = source.children[s];
      if (wide_is_leaf(word) && wide_leaf_count(word) == 0) continue;
      Child child;
      child.word = word;
      for (int axis = 0; axis < 3; ++axis) {
        child.box.lower[axis] = source.bounds[2 * axis][s];
        child.box.upper[axis] = source.bounds[2 * axis + 1][s];
      }
      box.extend(child.box);
      children.push_back(child);
    }
    const std::array<Child, 8> slots = order_for_octants(children, box);

    CompressedWideNode node{};
    for (int axis = 0; axis < 3; ++axis) {
      node.origin[axis] = box.lower[axis];
      node.exponent[axis] =
          static_cast<std::int8_t>(quantization_exponent(box.lower[axis], box.upper[axis]));
    }
    node.child_base = static_cast<std::uint32_t>(out_.nodes.size());
    node.primitive_base = static_cast<std::uint32_t>(out_.primitives.size());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> inner;  // (wide node, compressed node)
    std::uint32_t leaf_total = 0;
    for (std::uint32_t s = 0; s < 8; ++s) {
      const Child& child = slots[s];
      if (wide_is_leaf(child.word) && wide_leaf_count(child.word) == 0) {
        for (int axis = 0; axis < 3; ++axis) {  // never entered; the walk skips empty slots
          node.lower[axis][s] = 255;
          node.upper[axis][s] = 0;
        }
        continue;
      }
      for (int axis = 0; axis < 3; ++axis) {
        const float scale = power_of_two(node.exponent[axis]);
        node.lower[axis][s] = quantize_down(node.origin[axis], scale, child.box.lower[axis]);
        node.upper[axis][s] = quantize_up(node.origin[axis], scale, child.box.upper[axis]);
      }
      if (wide_is_leaf(child.word)) {
        const std::uint32_t first = wide_leaf_first(child.word);
        const std::uint32_t count = wide_leaf_count(child.word);
        node.leaf_count[s] = static_cast<std::uint8_t>(count);
        leaf_total += count;
        out_.primitives.insert(out_.primitives.end(), binary_.primitives.begin() + first,
                               binary_.primitives.begin() + first + count);
      } else {
        node.inner_mask = static_cast<std::uint8_t>(node.inner_mask | (1U << s));
        inner.emplace_back(child.word, node.child_base + static_cast<std::uint32_t>(inner.size()));
      }
    }
    if (leaf_total > 255)
      throw std::logic_error("compress_bvh: more than 255 primitives in leaves");
    out_.nodes.resize(out_.nodes.size() + inner.size());
    out_.nodes[index] = node;
    for (const auto& [wide_child, child_index] : inner) fill(wide_child, child_index);
  }

 private:
  const Bvh& binary_;
  const WideBvh& wide_;
  CompressedWideBvh& out_;
};

}  // namespace

CompressedWideBvh compress_bvh(const Bvh& binary) {
  CompressedWideBvh out;
  if (binary.nodes.empty()) return out;
  for (const BvhNode& node : binary.nodes) {
    if (node.is_leaf() && (node.offset > kWideMaxLeafFirst || node.count > kWideMaxLeafItems))
      return out;
    // Quantisation needs finite boxes; a shape without one keeps the binary walk.
    for (int axis = 0; axis < 3; ++axis)
      if (!std::isfinite(node.lower[axis]) || !std::isfinite(node.upper[axis])) return out;
  }
  const WideBvh wide = collapse_to_wide(binary, [](std::uint32_t offset, std::uint32_t count) {
    return make_wide_leaf(offset, count);
  });
  if (wide.nodes.empty() || wide.nodes.size() > kCompressedMaxNodes ||
      wide.depth > kCompressedMaxDepth)
    return out;
  out.nodes.resize(1);
  out.nodes.reserve(wide.nodes.size());
  out.primitives.reserve(binary.primitives.size());
  Compressor(binary, wide, out).fill(0, 0);
  out.depth = wide.depth;
  return out;
}

}  // namespace tessera
