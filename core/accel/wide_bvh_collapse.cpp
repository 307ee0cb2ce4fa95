#include <algorithm>
#include <array>

#include "tessera/accel/wide_bvh.hpp"

namespace tessera {

void WideBvhNode::clear() {
  for (std::uint32_t slot = 0; slot < kWideBvhWidth; ++slot) {
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis][slot] = kInfinity;
      bounds[2 * axis + 1][slot] = -kInfinity;
    }
    children[slot] = kWideEmptyChild;
    unused[slot] = 0;
  }
}

void WideBvhNode::set_child(std::uint32_t slot, const vec3& lower, const vec3& upper,
                            std::uint32_t child) {
  for (int axis = 0; axis < 3; ++axis) {
    bounds[2 * axis][slot] = lower[axis];
    bounds[2 * axis + 1][slot] = upper[axis];
  }
  children[slot] = child;
}

namespace {

class Collapser {
 public:
  Collapser(const Bvh& binary, const WideLeafEncoder& encode_leaf, std::uint32_t merge_limit,
            WideBvh& out)
      : binary_(binary), encode_leaf_(encode_leaf), merge_limit_(merge_limit), out_(out) {}

  void run() {
    if (binary_.nodes.empty()) return;
    if (merge_limit_ > 0) {
      first_.resize(binary_.nodes.size());
      count_.resize(binary_.nodes.size());
      measure(0);
    }
    out_.nodes.reserve(binary_.nodes.size() / 4 + 1);
    const BvhNode& root = binary_.nodes[0];
    if (root.is_leaf()) {
      // A single leaf still gets a root node, so traversal always starts at an interior node.
      out_.nodes.emplace_back().clear();
      out_.nodes[0].set_child(0, root.lower, root.upper, encode_leaf_(root.offset, root.count));
      out_.depth = 1;
      return;
    }
    out_.nodes.emplace_back().clear();
    emit(0, 0, 1);
  }

 private:
  float area(std::uint32_t index) const {
    const BvhNode& n = binary_.nodes[index];
    return Aabb{n.lower, n.upper}.surface_area();
  }

  // Fills the already allocated wide node `wide_index` from binary node `binary_index`.
  // Memory order: a node's leaf children get their triangle blocks together, and its
  // interior children are allocated side by side before any of them is filled, so the
  // siblings a ray visits one after the other lie next to each other.
  void emit(std::uint32_t binary_index, std::uint32_t wide_index, std::uint32_t depth) {
    out_.depth = std::max(out_.depth, depth);
    std::array<std::uint32_t, kWideBvhWidth> members{};
    std::uint32_t member_count = 0;
    members[member_count++] = binary_index + 1;
    members[member_count++] = binary_.nodes[binary_index].offset;
    while (member_count < kWideBvhWidth) {
      int widest = -1;
      float widest_area = -1.0f;
      for (std::uint32_t m = 0; m < member_count; ++m) {
        if (binary_.nodes[members[m]].is_leaf()) continue;
        const float a = area(members[m]);
        if (a > widest_area) {
          widest_area = a;
          widest = static_cast<int>(m);
        }
      }
      if (widest < 0) break;
      const std::uint32_t opened = members[widest];
      members[widest] = opened + 1;
      members[member_count++] = binary_.nodes[opened].offset;
    }

    std::array<bool, kWideBvhWidth> interior{};
    for (std::uint32_t m = 0; m < member_count; ++m) {
      const BvhNode& child = binary_.nodes[members[m]];
      std::uint32_t word;
      if (child.is_leaf()) {
        word = encode_leaf_(child.offset, child.count);
      } else if (merge_limit_ > 0 && count_[members[m]] <= merge_limit_) {
        word = encode_leaf_(first_[members[m]], count_[members[m]]);
      } else {
        interior[m] = true;
        word = static_cast<std::uint32_t>(out_.nodes.size());
        out_.nodes.emplace_back().clear();
      }
      out_.nodes[wide_index].set_child(m, child.lower, child.upper, word);
    }
    for (std::uint32_t m = 0; m < member_count; ++m)
      if (interior[m]) emit(members[m], out_.nodes[wide_index].children[m], depth + 1);
  }

  // Primitive range of each binary subtree (depth-first order keeps it contiguous).
  void measure(std::uint32_t index) {
    const BvhNode& node = binary_.nodes[index];
    if (node.is_leaf()) {
      first_[index] = node.offset;
      count_[index] = node.count;
      return;
    }
    measure(index + 1);
    measure(node.offset);
    first_[index] = first_[index + 1];
    count_[index] = count_[index + 1] + count_[node.offset];
  }

  const Bvh& binary_;
  const WideLeafEncoder& encode_leaf_;
  std::uint32_t merge_limit_;
  WideBvh& out_;
  std::vector<std::uint32_t> first_, count_;
};

}  // namespace

WideBvh collapse_to_wide(const Bvh& binary, const WideLeafEncoder& encode_leaf,
                         std::uint32_t merge_limit) {
  WideBvh wide;
  Collapser(binary, encode_leaf, merge_limit, wide).run();
  return wide;
}

}  // namespace tessera
