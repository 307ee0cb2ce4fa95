#include "light_list.hpp"

#include "tessera/render/light_sampling.hpp"

#include <algorithm>
#include <limits>

namespace tessera {

void add_if_sampled_emitter(std::vector<LightSource>& lights, const Material& material,
                            std::uint32_t primitive, float sampled_area, bool visible) {
  // Cylinders and cones are sampled by area over both sides of their wall: hidden, no ray
  // stops at the near side, so the far side would light through it. A hidden one stays
  // out of the list (and unseen), as before they had samplers.
  const PrimitiveType type = primitive_type(primitive);
  if (!visible && (type == PrimitiveType::kCylinder || type == PrimitiveType::kCone)) return;
  if (material.emissive() && sampled_area > 0.0f)
    lights.push_back(LightSource{primitive, sampled_area, 0.0f, visible});
}

namespace {

Aabb light_bounds(const SceneView& shapes, const LightSource& light) {
  Aabb box;
  light_detail::with_emitter(shapes, light, [&](const auto& shape) {
    box = bounds(shape);
    return true;
  });
  return box;
}

std::uint32_t light_material(const SceneView& shapes, const LightSource& light) {
  std::uint32_t material = 0;
  light_detail::with_emitter(shapes, light, [&](const auto& shape) {
    material = shape.material;
    return true;
  });
  return material;
}

// Emitted luminance times area; an emitter whose luminance is zero (a pure colour cannot
// be) still lights the scene, so it keeps a small share.
double light_power(const vec3& e, float area) {
  const double luminance = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
  return std::max(luminance, 1e-3 * std::max({e.x, e.y, e.z})) * area;
}

struct TreeBuild {
  std::vector<LightSource>& lights;
  std::vector<Aabb> boxes;
  std::vector<double> power;
  std::vector<std::uint32_t> order;  // light indices, partitioned as the tree is built
  std::vector<LightTreeNode> nodes;

  // Builds the subtree over order[begin, end) at `depth` with path `path`; returns its index.
  std::uint32_t build(std::size_t begin, std::size_t end, std::uint32_t depth, std::uint64_t path) {
    const auto at = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    Aabb box, centroids;
    double total = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      box.extend(boxes[order[i]]);
      centroids.extend(boxes[order[i]].centroid());
      total += power[order[i]];
    }
    nodes[at].lower = box.lower;
    nodes[at].upper = box.upper;
    nodes[at].power = static_cast<float>(total);
    if (end - begin == 1) {
      const std::uint32_t light = order[begin];
      nodes[at].child_or_light = light | LightTreeNode::kLeaf;
      lights[light].tree_depth = depth;
      lights[light].tree_path = path;
      return at;
    }
    const std::size_t mid = split(begin, end, centroids, depth);
    build(begin, mid, depth + 1, path);
    const std::uint32_t right = build(mid, end, depth + 1, path | (std::uint64_t{1} << depth));
    nodes[at].child_or_light = right;
    return at;
  }

  std::size_t split(std::size_t begin, std::size_t end, const Aabb& centroids,
                    std::uint32_t depth) {
    const int axis = centroids.largest_axis();
    const float lo = centroids.lower[axis], extent = centroids.upper[axis] - lo;
    const auto first = order.begin() + static_cast<std::ptrdiff_t>(begin);
    const auto last = order.begin() + static_cast<std::ptrdiff_t>(end);
    const auto centre = [&](std::uint32_t i) { return boxes[i].centroid()[axis]; };
    if (depth < 32 && extent > 0.0f) {
      constexpr int kBins = 12;
      const auto bin_of = [&](std::uint32_t i) {
        return std::min(kBins - 1, static_cast<int>((centre(i) - lo) / extent * kBins));
      };
      Aabb bin_box[kBins];
      double bin_power[kBins] = {};
      std::size_t bin_count[kBins] = {};
      for (auto it = first; it != last; ++it) {
        const int b = bin_of(*it);
        bin_box[b].extend(boxes[*it]);
        bin_power[b] += power[*it];
        ++bin_count[b];
      }
      double best = std::numeric_limits<double>::infinity();
      int best_split = -1;
      for (int s = 1; s < kBins; ++s) {
        Aabb left, right;
        double pl = 0.0, pr = 0.0;
        std::size_t nl = 0, nr = 0;
        for (int b = 0; b < kBins; ++b) {
          (b < s ? left : right).extend(bin_box[b]);
          (b < s ? pl : pr) += bin_power[b];
          (b < s ? nl : nr) += bin_count[b];
        }
        if (nl == 0 || nr == 0) continue;
        const double cost = pl * left.surface_area() + pr * right.surface_area();
        if (cost < best) {
          best = cost;
          best_split = s;
        }
      }
      if (best_split > 0) {
        const auto cut =
            std::partition(first, last, [&](std::uint32_t i) { return bin_of(i) < best_split; });
        return static_cast<std::size_t>(cut - order.begin());
      }
    }
    // Every centroid in one place (or a deep branch): a median split keeps the depth
    // logarithmic.
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(first, order.begin() + static_cast<std::ptrdiff_t>(mid), last,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centre(a) < centre(b) || (centre(a) == centre(b) && a < b);
                     });
    return mid;
  }
};

}  // namespace

std::vector<LightTreeNode> build_light_tree(std::vector<LightSource>& lights,
                                            std::span<const Material> materials,
                                            const SceneView& shapes) {
  if (lights.empty()) return {};
  TreeBuild b{lights, {}, {}, {}, {}};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    b.boxes.push_back(light_bounds(shapes, lights[i]));
    b.power.push_back(
        light_power(materials[light_material(shapes, lights[i])].emission, lights[i].area));
    b.order.push_back(static_cast<std::uint32_t>(i));
  }
  b.nodes.reserve(2 * lights.size());
  b.build(0, lights.size(), 0, 0);
  return std::move(b.nodes);
}

std::vector<AliasSlot> finish_light_list(std::vector<LightSource>& lights,
                                         std::span<const Material> materials,
                                         const SceneView& shapes) {
  std::sort(lights.begin(), lights.end(),
            [](const LightSource& a, const LightSource& b) { return a.primitive < b.primitive; });
  std::vector<double> power(lights.size());
  double total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const vec3 e = materials[light_material(shapes, lights[i])].emission;
    power[i] = light_power(e, lights[i].area);
    total += power[i];
  }
  for (std::size_t i = 0; i < lights.size(); ++i)
    lights[i].pmf = total > 0.0 ? static_cast<float>(power[i] / total)
                                : 1.0f / static_cast<float>(lights.size());
  return build_alias_table(power);
}

}  // namespace tessera
