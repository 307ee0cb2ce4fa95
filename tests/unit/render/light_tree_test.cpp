// The four-wide light tree (render/light_tree.hpp, built by core/render/light_list.cpp) over
// scenes with many emitters: the pick probabilities sum to one where every light is above
// the horizon (and the rest are lost picks, counted as such), every
// pick's pmf is the pmf light_pick_pmf gives its light (bit for bit, as MIS needs), picks
// follow those probabilities (chi-square), the SSE and scalar importances agree, and the
// tree stays within its path bits when every light sits at one point.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <random>
#include <vector>

#include "chi2.hpp"
#include "tessera/render/light_sampling.hpp"
#include "tessera/render/prepared_scene.hpp"

namespace tessera {
namespace {

using glm::dvec3;

// A floor under `count` small emissive triangles of uneven power, scattered in a slab
// above it (or all at one point when `coincident`).
SceneDescription many_triangle_lights(int count, bool coincident, std::uint64_t seed) {
  SceneDescription scene;
  MaterialDesc white;
  white.name = "white";
  scene.materials.push_back(white);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TriangleMeshDesc mesh;
  for (int i = 0; i < count; ++i) {
    MaterialDesc lamp;
    lamp.name = "lamp" + std::to_string(i);
    lamp.type = MaterialType::kLight;
    lamp.emission = dvec3(0.5 + 20.0 * u(rng) * u(rng));
    scene.materials.push_back(lamp);
    const dvec3 at = coincident ? dvec3(0.0, 2.0, 0.0)
                                : dvec3(8.0 * u(rng) - 4.0, 1.0 + 2.0 * u(rng), 8.0 * u(rng) - 4.0);
    TriangleMeshDesc tri;
    tri.positions = {at, at + dvec3(0.05, 0.0, 0.0), at + dvec3(0.0, 0.01, 0.05)};
    tri.indices = {0, 1, 2};
    tri.material = static_cast<std::uint32_t>(scene.materials.size() - 1);
    scene.meshes.push_back(tri);
  }
  scene.quads.push_back(
      QuadDesc{.corner = {-5, 0, -5}, .u = {10, 0, 0}, .v = {0, 0, 10}, .material = 0});
  return scene;
}

struct Probe {
  vec3 p, n;
  // Every light is above the surface's horizon, so a pick never ends at a node whose
  // children all lie below it and the probabilities sum to one. Elsewhere a pick can
  // descend into a child whose bounds straddle the horizon and find nothing under it:
  // that sample is lost (no light, pmf 0), which costs variance but not bias, since a
  // light with pmf 0 is one the point cannot see.
  bool all_above = true;
};

std::vector<Probe> probes() {
  return {{vec3(0.3f, 0.0f, -0.2f), vec3(0, 1, 0)},
          {vec3(-3.9f, 0.0f, 3.9f), vec3(0, 1, 0)},
          {vec3(0.0f, 2.0f, 0.0f), vec3(0, 1, 0), false},  // inside the slab, facing up
          {vec3(1.0f, 1.5f, 1.0f), glm::normalize(vec3(1, -1, 0.5f)), false},
          {vec3(6.0f, 2.0f, 0.0f), vec3(-1, 0, 0)}};
}

// A point within `scale` units of the lights' slab, facing a random direction.
Probe random_receiver(std::mt19937& rng, float scale) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const vec3 p(scale * u(rng), 2.0f + scale * u(rng), scale * u(rng));
  vec3 n(u(rng), u(rng), u(rng));
  if (glm::dot(n, n) < 1e-4f) n = vec3(0, 1, 0);
  return {p, glm::normalize(n), false};
}

TEST(LightTree, PickProbabilitiesSumToOneAndMatchEachPick) {
  const auto prepared = PreparedScene::build(many_triangle_lights(700, false, 11));
  const SceneView view = prepared->view();
  ASSERT_EQ(view.light_count, 700u);
  ASSERT_NE(view.light_tree, nullptr);
  std::uint32_t deepest = 0;
  for (std::uint32_t i = 0; i < view.light_count; ++i)
    deepest = std::max(deepest, view.lights[i].tree_depth);
  // 700 lights need at least five four-wide levels, and a binned split keeps it shallow.
  EXPECT_GE(deepest, 5u);
  EXPECT_LE(deepest, 12u);
  for (const Probe& probe : probes()) {
    double sum = 0.0;
    for (std::uint32_t i = 0; i < view.light_count; ++i)
      sum += light_pick_pmf(view, probe.p, probe.n, i);
    if (probe.all_above)
      EXPECT_NEAR(sum, 1.0, 1e-4);
    else
      EXPECT_LE(sum, 1.0 + 1e-4);
    test::UniformFloats u(5);
    int mismatch = 0;
    for (int i = 0; i < 20000; ++i) {
      const LightPick pick = pick_light(view, probe.p, probe.n, u());
      if (probe.all_above) {
        ASSERT_GT(pick.pmf, 0.0f);
      }
      if (!(pick.pmf > 0.0f)) continue;
      // Bit for bit: MIS weights an emitter hit with light_pick_pmf and the light sample
      // with the pick's pmf; any difference biases the image.
      if (pick.pmf != light_pick_pmf(view, probe.p, probe.n, pick.index)) ++mismatch;
    }
    EXPECT_EQ(mismatch, 0);
  }
}

TEST(LightTree, PicksFollowTheirProbabilities) {
  const auto prepared = PreparedScene::build(many_triangle_lights(200, false, 12));
  const SceneView view = prepared->view();
  const std::vector<Probe> points = probes();
  constexpr int kPicks = 400000;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Probe& probe = points[k];
    // One cell per light and a last one for picks that find no light.
    std::vector<double> expected(view.light_count + 1), observed(view.light_count + 1, 0.0);
    double sum = 0.0;
    for (std::uint32_t i = 0; i < view.light_count; ++i) {
      const double pmf = light_pick_pmf(view, probe.p, probe.n, i);
      sum += pmf;
      expected[i] = kPicks * pmf;
    }
    expected[view.light_count] = kPicks * std::max(0.0, 1.0 - sum);
    test::UniformFloats u(100 + k);
    for (int i = 0; i < kPicks; ++i) {
      const LightPick pick = pick_light(view, probe.p, probe.n, u());
      observed[pick.pmf > 0.0f ? pick.index : view.light_count] += 1.0;
    }
    const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
    std::printf("[chi2] light tree picks, probe %zu  p = %.4g (%s)\n", k, chi2.p_value,
                chi2.summary.c_str());
    EXPECT_GT(chi2.p_value, test::bonferroni_alpha(static_cast<int>(points.size())))
        << chi2.summary;
  }
}

// What a pick leaves of its u (LightPick::reused_u), which a diffuse vertex's light sampler
// takes as its first coordinate: given the light, it must be uniform on [0, 1), or the point
// on the light would follow another density than the sampler's pdf says. Chi-square over
// (light, eighth of [0, 1)) cells, by the tree, by power alone (the alias table) and with
// lights at infinity; and by the tree, where each light's picks come from one interval of
// u, it must also keep u's order there, which keeps the light point stratified.
TEST(LightTree, WhatAPickLeavesOfItsUIsUniformForEachLight) {
  SceneDescription infinite = many_triangle_lights(40, false, 21);
  infinite.lights.push_back(LightDesc{.type = "sun",
                                      .direction = {0.2, -1, 0.1},
                                      .irradiance = 2.0,
                                      .angular_radius_degrees = 1.0});
  infinite.environment = EnvironmentDesc{.type = "gradient", .intensity = 0.5};
  struct Case {
    const char* name;
    std::shared_ptr<const PreparedScene> prepared;
  };
  const Case cases[] = {
      {"tree", PreparedScene::build(many_triangle_lights(200, false, 12))},
      {"power", PreparedScene::build(many_triangle_lights(60, false, 14), {.light_tree = false})},
      {"tree and infinite", PreparedScene::build(infinite)}};
  constexpr int kBins = 8, kPicks = 400000;
  const Probe probe = probes()[0];
  for (std::size_t c = 0; c < std::size(cases); ++c) {
    const SceneView view = cases[c].prepared->view();
    ASSERT_EQ(view.light_tree != nullptr, c != 1);
    const std::size_t cells = std::size_t{view.light_count} * kBins;
    std::vector<double> expected(cells), observed(cells, 0.0);
    for (std::uint32_t i = 0; i < view.light_count; ++i)
      for (int b = 0; b < kBins; ++b)
        expected[i * kBins + b] = kPicks * light_pick_pmf(view, probe.p, probe.n, i) / kBins;
    test::UniformFloats u(300 + c);
    int outside = 0;
    for (int k = 0; k < kPicks; ++k) {
      const LightPick pick = pick_light(view, probe.p, probe.n, u());
      ASSERT_GT(pick.pmf, 0.0f);
      if (!(pick.reused_u >= 0.0f && pick.reused_u < 1.0f)) {
        ++outside;
        continue;
      }
      observed[pick.index * kBins + static_cast<std::size_t>(pick.reused_u * kBins)] += 1.0;
    }
    EXPECT_EQ(outside, 0);
    const test::Chi2Result chi2 = test::pearson_chi2(observed, expected);
    std::printf("[chi2] u left by a pick, %-17s p = %.4g (%s)\n", cases[c].name, chi2.p_value,
                chi2.summary.c_str());
    EXPECT_GT(chi2.p_value, test::bonferroni_alpha(static_cast<int>(std::size(cases))))
        << cases[c].name << ": " << chi2.summary;
  }
  // Order: sweeping u upwards, each light's reused u never falls.
  const SceneView view = cases[0].prepared->view();
  std::vector<float> last(view.light_count, -1.0f);
  int fell = 0;
  for (int k = 0; k < 1 << 20; ++k) {
    const LightPick pick = pick_light(view, probe.p, probe.n, static_cast<float>(k) * 0x1p-20f);
    if (pick.reused_u < last[pick.index]) ++fell;
    last[pick.index] = pick.reused_u;
  }
  EXPECT_EQ(fell, 0);
}

// The ends of u's range, where the branch-free slot count meets the running sums' edges:
// trees of 3 and 6 lights have nodes with empty slots at the end, and a pick at u = 0 or
// just below 1 must still find a light (never an empty slot), with the pmf light_pick_pmf
// gives it.
TEST(LightTree, PicksAtTheEndsOfURangeFindALight) {
  for (const int count : {3, 6, 300}) {
    const auto prepared = PreparedScene::build(many_triangle_lights(count, false, 31));
    const SceneView view = prepared->view();
    ASSERT_NE(view.light_tree, nullptr);
    for (const Probe& probe : probes()) {
      if (!probe.all_above) continue;
      for (const float u : {0.0f, 0x1.fffffep-1f, 0x1.fffffcp-1f}) {
        const LightPick pick = pick_light(view, probe.p, probe.n, u);
        ASSERT_GT(pick.pmf, 0.0f) << count << " lights, u " << u;
        ASSERT_LT(pick.index, view.light_count);
        EXPECT_EQ(pick.pmf, light_pick_pmf(view, probe.p, probe.n, pick.index));
        EXPECT_GE(pick.reused_u, 0.0f);
        EXPECT_LT(pick.reused_u, 1.0f);
      }
    }
  }
}

// Lights the receiving surface cannot see (all below its horizon) get no samples, and a
// point where no light can reach gets none at all.
TEST(LightTree, LightsBelowTheHorizonAreNeverPicked) {
  const auto prepared = PreparedScene::build(many_triangle_lights(300, false, 13));
  const SceneView view = prepared->view();
  // Facing down from above every light: nothing lights it.
  const vec3 above(0.0f, 10.0f, 0.0f), up(0.0f, 1.0f, 0.0f);
  EXPECT_EQ(pick_light(view, above, up, 0.5f).pmf, 0.0f);
  for (std::uint32_t i = 0; i < view.light_count; ++i)
    EXPECT_EQ(light_pick_pmf(view, above, up, i), 0.0f);
}

// The importance of `node`'s child k from (p, n), and whether the child is far, in double
// precision from the angles themselves (not the walk's rearranged formula). `margin` is how
// clearly the far test is decided: the smaller of its two comparisons' relative margins.
struct ReferenceSlot {
  double importance = 0.0;
  bool far = false;
  double margin = 0.0;
};

ReferenceSlot reference_slot(const LightTreeNode& node, std::uint32_t k, const vec3& p,
                             const vec3& n) {
  const double radius2 = node.radius2[k];
  const glm::dvec3 to =
      glm::dvec3(node.centre_x[k], node.centre_y[k], node.centre_z[k]) - glm::dvec3(p);
  const double d2 = glm::dot(to, to);
  ReferenceSlot r;
  r.margin = 1.0;  // inside its sphere: clearly not far
  double cos_bound = 1.0;
  if (d2 > radius2) {
    const double cos_n = glm::dot(glm::dvec3(n), to) / std::sqrt(d2);
    const double sin_n = std::sqrt(std::max(0.0, 1.0 - cos_n * cos_n));
    const double sin_u = std::sqrt(radius2 / d2), cos_u = std::sqrt(1.0 - radius2 / d2);
    if (cos_n < cos_u) cos_bound = cos_n * cos_u + sin_n * sin_u;
    // Far: small for its distance, and cos(theta_n + theta_u) at least 1/spread of
    // cos(theta_n - theta_u).
    const double near_cos = cos_n * cos_u + sin_n * sin_u;
    const double far_cos = cos_n * cos_u - sin_n * sin_u;
    const double distance_margin = d2 / (kLightTreeFarDistance2 * radius2) - 1.0;
    const double cosine_margin =
        (kLightTreeFarCosineSpread * far_cos - near_cos) / std::max(1e-30, std::abs(near_cos));
    r.far = distance_margin > 0.0 && cosine_margin >= 0.0;
    r.margin = std::min(std::abs(distance_margin), std::abs(cosine_margin));
  }
  r.importance = node.power[k] > 0.0f && cos_bound > 0.0
                     ? node.power[k] * cos_bound / std::max(d2, radius2)
                     : 0.0;
  return r;
}

TEST(LightTree, ImportancesAreTheSameOnEveryPath) {
  // The SSE path (host) against the formula from the angles.
  const auto prepared = PreparedScene::build(many_triangle_lights(64, false, 14));
  const SceneView view = prepared->view();
  const LightTreeNode& root = view.light_tree[0];
  for (const Probe& probe : probes()) {
    float importance[4];
    std::uint32_t far_slots = 0;
    light_tree_importance(root, probe.p, probe.n, importance, far_slots);
    for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) {
      const ReferenceSlot expected = reference_slot(root, k, probe.p, probe.n);
      EXPECT_NEAR(importance[k], expected.importance, 1e-4 * expected.importance + 1e-30)
          << "slot " << k;
      if (expected.margin > 1e-4) {
        EXPECT_EQ(((far_slots >> k) & 1u) != 0, expected.far) << "slot " << k;
      }
    }
  }
}

// The whole rule, against a walk written out here in double precision: down to the first
// far child each level weighs its children by importance, below it by power. From points
// near and far (up to 300 units) from 300 lights, facing random directions, every light's
// light_pick_pmf matches; lights whose path crosses a far test too close to call in float
// are skipped. The counts check that both kinds of level occur.
TEST(LightTree, BelowAFarChildLightsArePickedByPower) {
  const auto prepared = PreparedScene::build(many_triangle_lights(300, false, 19));
  const SceneView view = prepared->view();
  ASSERT_NE(view.light_tree, nullptr);
  std::mt19937 rng(23);
  std::uint32_t compared = 0, power_levels = 0, importance_levels = 0;
  for (int i = 0; i < 60; ++i) {
    const float scale = i < 40 ? 6.0f : 300.0f;
    const Probe receiver = random_receiver(rng, scale);
    const vec3 p = receiver.p, n = receiver.n;
    for (std::uint32_t light = 0; light < view.light_count; ++light) {
      double pmf = 1.0;
      bool far = false, clear = true;
      std::uint32_t at = 0, powers = 0, importances = 0;
      for (std::uint32_t level = 0; level < view.lights[light].tree_depth; ++level) {
        const LightTreeNode& node = view.light_tree[at];
        const auto slot = static_cast<std::uint32_t>(
            (view.lights[light].tree_path >> (kLightTreePathBits * level)) & 3u);
        double weight[4], total = 0.0;
        bool slot_far = false;
        for (std::uint32_t k = 0; k < LightTreeNode::kWidth; ++k) {
          if (far) {
            weight[k] = node.power[k];
          } else {
            const ReferenceSlot r = reference_slot(node, k, p, n);
            weight[k] = r.importance;
            if (k == slot) {
              slot_far = r.far;
              clear = clear && r.margin > 1e-3;
            }
          }
          total += weight[k];
        }
        (far ? powers : importances) += 1;
        pmf = total > 0.0 ? pmf * weight[slot] / total : 0.0;
        far = far || slot_far;
        at = node.child[slot];
      }
      if (!clear) continue;
      const double got = light_pick_pmf(view, p, n, light);
      EXPECT_NEAR(got, pmf, 2e-4 * pmf + 1e-12) << "light " << light << " from point " << i;
      ++compared;
      power_levels += powers;
      importance_levels += importances;
    }
  }
  EXPECT_GT(compared, 60u * 300u * 3 / 4);
  EXPECT_GT(power_levels, 10000u);
  EXPECT_GT(importance_levels, 10000u);
}

// The importance bound holds only if a node's sphere encloses every emitter below it: each
// corner of each light's box lies in the sphere of every slot on its root-to-leaf path
// (to the float rounding of the centre: a few units in the last place of its coordinates).
TEST(LightTree, EverySphereOnAPathEnclosesItsLight) {
  const auto prepared = PreparedScene::build(many_triangle_lights(300, false, 18));
  const SceneView view = prepared->view();
  ASSERT_NE(view.light_tree, nullptr);
  std::uint32_t checked = 0;
  for (std::uint32_t i = 0; i < view.light_count; ++i) {
    Aabb box;
    light_detail::with_emitter(view, view.lights[i], [&](const auto& shape) {
      box = bounds(shape);
      return true;
    });
    ASSERT_FALSE(box.empty()) << "light " << i;
    std::uint32_t at = 0;
    for (std::uint32_t level = 0; level < view.lights[i].tree_depth; ++level) {
      const auto slot = static_cast<std::uint32_t>(
          (view.lights[i].tree_path >> (kLightTreePathBits * level)) & 3u);
      const LightTreeNode& node = view.light_tree[at];
      const dvec3 centre(node.centre_x[slot], node.centre_y[slot], node.centre_z[slot]);
      const double rounding =
          4.0 *
          std::ldexp(std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)}), -23);
      for (int corner = 0; corner < 8; ++corner) {
        const dvec3 q((corner & 1) ? box.upper.x : box.lower.x,
                      (corner & 2) ? box.upper.y : box.lower.y,
                      (corner & 4) ? box.upper.z : box.lower.z);
        EXPECT_LE(glm::length(q - centre), std::sqrt(double{node.radius2[slot]}) + rounding)
            << "light " << i << " level " << level << " corner " << corner;
        ++checked;
      }
      at = node.child[slot];
    }
    EXPECT_EQ(at, view.lights[i].tree_depth == 0 ? 0u : (i | LightTreeNode::kLeaf));
  }
  EXPECT_GT(checked, 300u * 8u * 4u);
}

// The host's SSE importances equal the portable ones (the device's) bit for bit, at every
// node of a 300-light tree, from points among, beside and far (up to 1e4 units) from the
// lights, facing random directions; the counts check that children narrowed by the cone
// and children below the horizon both occur. A pick and its pmf must agree on whichever
// processor renders.
TEST(LightTree, HostImportancesEqualThePortableOnes) {
  const auto prepared = PreparedScene::build(many_triangle_lights(300, false, 16));
  const SceneView view = prepared->view();
  ASSERT_NE(view.light_tree, nullptr);
  std::uint32_t nodes = 1;  // count the nodes: every interior child index is below the count
  for (std::uint32_t i = 0; i < nodes; ++i)
    for (std::uint32_t c : view.light_tree[i].child)
      if (!LightTreeNode::is_leaf(c) && c + 1 > nodes) nodes = c + 1;
  std::mt19937 rng(17);
  std::uint32_t compared = 0, narrowed = 0, unlit = 0, far = 0;
  for (int i = 0; i < 400; ++i) {
    const float scale = i < 300 ? 5.0f : 1e4f;
    const Probe receiver = random_receiver(rng, scale);
    const vec3 p = receiver.p, n = receiver.n;
    for (std::uint32_t at = 0; at < nodes; ++at) {
      float host[4], portable[4];
      std::uint32_t host_far = 0, portable_far = 0;
      light_tree_importance(view.light_tree[at], p, n, host, host_far);
      light_tree_importance_portable(view.light_tree[at], p, n, portable, portable_far);
      EXPECT_EQ(host_far, portable_far) << "node " << at;
      far += static_cast<std::uint32_t>(std::popcount(portable_far));
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(host[k]), std::bit_cast<std::uint32_t>(portable[k]))
            << "node " << at << " slot " << k << ": " << host[k] << " against " << portable[k];
        ++compared;
        // Narrowed by the cone: lit, yet below power / max(d2, r2).
        const LightTreeNode& node = view.light_tree[at];
        const vec3 to = vec3(node.centre_x[k], node.centre_y[k], node.centre_z[k]) - p;
        const float unbounded = node.power[k] / std::max(glm::dot(to, to), node.radius2[k]);
        if (portable[k] > 0.0f && portable[k] < 0.999f * unbounded) ++narrowed;
        if (node.power[k] > 0.0f && portable[k] == 0.0f) ++unlit;
      }
    }
  }
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(narrowed, 1000u);  // the cone's bound is exercised,
  EXPECT_GT(unlit, 1000u);     // and so are clusters below the horizon,
  EXPECT_GT(far, 1000u);       // and far ones, picked below by power
  EXPECT_LT(far, compared / 2);
}

// Every light at one point: the split search cannot separate them, median splits take
// over, and the tree still fits its 2-bit-per-level paths and picks every light evenly.
TEST(LightTree, CoincidentLightsStayWithinThePathBits) {
  const auto prepared = PreparedScene::build(many_triangle_lights(1000, true, 15));
  const SceneView view = prepared->view();
  ASSERT_NE(view.light_tree, nullptr);
  std::uint32_t deepest = 0;
  for (std::uint32_t i = 0; i < view.light_count; ++i)
    deepest = std::max(deepest, view.lights[i].tree_depth);
  EXPECT_LE(deepest, kLightTreeMaxDepth);
  const vec3 p(0.0f, 0.0f, 0.0f), n(0.0f, 1.0f, 0.0f);
  double sum = 0.0;
  for (std::uint32_t i = 0; i < view.light_count; ++i) sum += light_pick_pmf(view, p, n, i);
  EXPECT_NEAR(sum, 1.0, 1e-4);
}

}  // namespace
}  // namespace tessera
