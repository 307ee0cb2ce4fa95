#include "light_list.hpp"

#include "tessera/render/light_sampling.hpp"

#include <algorithm>
#include <limits>

namespace tessera {

void add_if_sampled_emitter(std::vector<LightSource>& lights, const Material& material,
                            std::uint32_t primitive, float sampled_area) {
  // Hidden or not, an emitting shape is hit by every ray but the camera's.
  if (material.emissive() && sampled_area > 0.0f)
    lights.push_back(LightSource{primitive, sampled_area, 0.0f, true});
}

namespace {

bool analytic(const LightSource& light) {
  return primitive_type(light.primitive) == PrimitiveType::kAnalyticLight;
}

Aabb light_bounds(const SceneView& shapes, const LightSource& light) {
  Aabb box;
  if (analytic(light)) {
    box.extend(shapes.analytic_lights[primitive_index(light.primitive)].position);
    return box;
  }
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

double luminance(const vec3& e) {
  const double y = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;
  // A pure colour whose luminance is zero still lights the scene: keep a small share.
  return std::max(y, 1e-3 * std::max({e.x, e.y, e.z}));
}

// Emitted flux (finish_light_list says how each kind's is found).
double light_power(const SceneView& shapes, std::span<const Material> materials,
                   const LightSource& light, float scene_radius) {
  constexpr double kPiD = 3.14159265358979323846;
  if (!analytic(light))
    return 2.0 * kPiD * luminance(materials[light_material(shapes, light)].emission) * light.area;
  const AnalyticLight& a = shapes.analytic_lights[primitive_index(light.primitive)];
  const double disk = kPiD * double(scene_radius) * scene_radius;
  switch (a.kind) {
    case AnalyticLightKind::kPoint:
      return 4.0 * kPiD * luminance(a.emission);
    case AnalyticLightKind::kSpot:
      return 2.0 * kPiD * luminance(a.emission) *
             (1.0 - 0.5 * (double(a.cos_inner) + double(a.cos_outer)));
    case AnalyticLightKind::kDistant:
      return luminance(a.emission) * disk;
    case AnalyticLightKind::kEnvironment:
      return 4.0 * kPiD * disk * luminance(shapes.environment.average_radiance());
  }
  return 0.0;
}

// The power pick_light weighs `light` by: 0 for lights sampled at every vertex.
double pick_power(const SceneView& shapes, std::span<const Material> materials,
                  const LightSource& light, float scene_radius) {
  return light.every_vertex ? 0.0 : light_power(shapes, materials, light, scene_radius);
}

// The binary tree the split search builds; collapse() turns it into the four-wide tree
// the renderer walks.
struct BinaryNode {
  Aabb box;
  double power = 0.0;
  std::uint32_t left = 0, right = 0;  // children, when not a leaf
  std::uint32_t light = 0;            // when a leaf
  bool leaf = false;
};

struct TreeBuild {
  std::vector<LightSource>& lights;
  std::vector<Aabb> boxes;
  std::vector<double> power;
  std::vector<std::uint32_t> order;  // light indices, partitioned as the tree is built
  std::vector<BinaryNode> binary;
  std::vector<LightTreeNode> nodes;

  // Builds the binary subtree over order[begin, end) at `depth`; returns its index.
  std::uint32_t build(std::size_t begin, std::size_t end, std::uint32_t depth) {
    const auto at = static_cast<std::uint32_t>(binary.size());
    binary.emplace_back();
    Aabb box, centroids;
    double total = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      box.extend(boxes[order[i]]);
      centroids.extend(boxes[order[i]].centroid());
      total += power[order[i]];
    }
    binary[at].box = box;
    binary[at].power = total;
    if (end - begin == 1) {
      binary[at].leaf = true;
      binary[at].light = order[begin];
      return at;
    }
    const std::size_t mid = split(begin, end, centroids, depth);
    const std::uint32_t left = build(begin, mid, depth + 1);
    const std::uint32_t right = build(mid, end, depth + 1);
    binary[at].left = left;
    binary[at].right = right;
    return at;
  }

  // The four-wide node standing for binary node `at` (not a leaf) at `depth` with path
  // `path`; returns its index.
  std::uint32_t collapse(std::uint32_t at, std::uint32_t depth, std::uint64_t path) {
    // Each interior child is opened into its two children (a leaf stays), so every step of
    // the walk covers two binary levels where it can and the tree is at most half as deep:
    // at most 32 levels, since the binary tree's stay under 64 (split()).
    std::uint32_t slots[LightTreeNode::kWidth] = {};
    std::uint32_t used = 0;
    for (const std::uint32_t c : {binary[at].left, binary[at].right}) {
      if (binary[c].leaf) {
        slots[used++] = c;
      } else {
        slots[used++] = binary[c].left;
        slots[used++] = binary[c].right;
      }
    }
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) {
      LightTreeNode& node = nodes[index];
      if (k >= used) {
        // An empty slot: no power, so it is never taken.
        node.centre_x[k] = node.centre_y[k] = node.centre_z[k] = node.radius2[k] = 0.0f;
        node.power[k] = 0.0f;
        node.child[k] = LightTreeNode::kLeaf;
        continue;
      }
      const BinaryNode& b = binary[slots[k]];
      // The box's circumscribed sphere.
      const vec3 centre = b.box.centroid(), half = 0.5f * b.box.extent();
      node.centre_x[k] = centre.x;
      node.centre_y[k] = centre.y;
      node.centre_z[k] = centre.z;
      node.radius2[k] = (half.x * half.x + half.y * half.y) + half.z * half.z;
      node.power[k] = static_cast<float>(b.power);
      const std::uint64_t child_path = path | (std::uint64_t{k} << (kLightTreePathBits * depth));
      if (b.leaf) {
        node.child[k] = b.light | LightTreeNode::kLeaf;
        lights[b.light].tree_depth = depth + 1;
        lights[b.light].tree_path = child_path;
      } else {
        const std::uint32_t child = collapse(slots[k], depth + 1, child_path);
        nodes[index].child[k] = child;  // `node` may have moved
      }
    }
    return index;
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
  const std::size_t bounded = std::min<std::size_t>(shapes.first_infinite_light, lights.size());
  if (bounded == 0) return {};
  TreeBuild b{lights, {}, {}, {}, {}, {}};
  for (std::size_t i = 0; i < bounded; ++i) {
    b.boxes.push_back(light_bounds(shapes, lights[i]));
    b.power.push_back(pick_power(shapes, materials, lights[i], 1.0f));
    b.order.push_back(static_cast<std::uint32_t>(i));
  }
  b.binary.reserve(2 * bounded);
  const std::uint32_t root = b.build(0, bounded, 0);
  b.nodes.reserve(bounded);
  b.collapse(root, 0, 0);
  return std::move(b.nodes);
}

void add_analytic_lights(std::vector<LightSource>& lights,
                         std::span<const AnalyticLight> analytic) {
  for (std::size_t i = 0; i < analytic.size(); ++i) {
    const AnalyticLight& a = analytic[i];
    const bool hit_by_rays = a.kind == AnalyticLightKind::kEnvironment || distant_with_extent(a);
    lights.push_back(LightSource{
        make_primitive_ref(PrimitiveType::kAnalyticLight, static_cast<std::uint32_t>(i)), 0.0f,
        0.0f, hit_by_rays});
  }
}

float infinite_light_share(const std::vector<LightSource>& lights,
                           std::span<const Material> materials, const SceneView& shapes,
                           float scene_radius) {
  double infinite = 0.0, total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const double power = pick_power(shapes, materials, lights[i], scene_radius);
    total += power;
    if (i >= shapes.first_infinite_light) infinite += power;
  }
  if (!(total > 0.0)) return 0.5f;
  if (infinite == total) return 1.0f;  // the tree holds nothing left to pick
  if (infinite == 0.0) return 0.0f;
  return static_cast<float>(std::clamp(infinite / total, 0.1, 0.9));
}

float lit_region_radius(const std::vector<LightSource>& lights, const SceneView& shapes,
                        const vec3& camera_position, float scene_radius) {
  Aabb region;
  for (const LightSource& light : lights) {
    if (analytic(light)) {
      const AnalyticLight& a = shapes.analytic_lights[primitive_index(light.primitive)];
      if (a.kind == AnalyticLightKind::kPoint || a.kind == AnalyticLightKind::kSpot)
        region.extend(a.position);
    } else {
      region.extend(light_bounds(shapes, light));
    }
  }
  if (region.empty()) return scene_radius;
  region.extend(camera_position);
  return glm::max(1e-3f, 0.5f * glm::length(region.upper - region.lower));
}

std::vector<AliasSlot> finish_light_list(std::vector<LightSource>& lights,
                                         std::span<const Material> materials,
                                         const SceneView& shapes, float scene_radius) {
  std::sort(lights.begin(), lights.end(),
            [](const LightSource& a, const LightSource& b) { return a.primitive < b.primitive; });
  // A few delta lights are sampled at every vertex: a shadow ray each, and no pick noise
  // between them and the other lights (a floor under a point light, a sun and a sky had 3x
  // Cycles' noise per sample from the pick alone).
  // Delta lights are the ones no ray can hit (add_analytic_lights).
  const auto delta = [](const LightSource& light) { return !light.hit_by_rays; };
  if (static_cast<std::size_t>(std::count_if(lights.begin(), lights.end(), delta)) <=
      kMaxEveryVertexLights)
    for (LightSource& light : lights) light.every_vertex = delta(light);
  std::vector<double> power(lights.size());
  double total = 0.0, infinite = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    power[i] = pick_power(shapes, materials, lights[i], scene_radius);
    total += power[i];
    if (i >= shapes.first_infinite_light) infinite += power[i];
  }
  // Lights at infinity beside bounded ones: their share kept within [0.1, 0.9].
  const double bounded = total - infinite;
  if (infinite > 0.0 && bounded > 0.0) {
    const double share = std::clamp(infinite / total, 0.1, 0.9);
    const double scale = share / (1.0 - share) * bounded / infinite;
    for (std::size_t i = shapes.first_infinite_light; i < lights.size(); ++i) power[i] *= scale;
    total = bounded / (1.0 - share);
  }
  for (std::size_t i = 0; i < lights.size(); ++i)
    lights[i].pmf = lights[i].every_vertex ? 0.0f
                    : total > 0.0          ? static_cast<float>(power[i] / total)
                                           : 1.0f / static_cast<float>(lights.size());
  return build_alias_table(power);
}

}  // namespace tessera
