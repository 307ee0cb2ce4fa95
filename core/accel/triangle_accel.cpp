#include "tessera/accel/triangle_accel.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/accel/presplit.hpp"
#include "tessera/accel/sbvh.hpp"
#include "triangle_kernels.hpp"

#if TESSERA_HAVE_SIMD_KERNELS
#include <cpuid.h>
#endif

namespace tessera {

std::string_view accel_kind_name(AccelKind kind) {
  switch (kind) {
    case AccelKind::kAuto:
      return "auto";
    case AccelKind::kBvh:
      return "bvh";
    case AccelKind::kWide:
      return "wide";
    case AccelKind::kOctree:
      return "octree";
    case AccelKind::kBrute:
      return "brute";
  }
  return "unknown";
}

std::optional<AccelKind> parse_accel_kind(std::string_view name) {
  for (AccelKind kind :
       {AccelKind::kAuto, AccelKind::kBvh, AccelKind::kWide, AccelKind::kOctree, AccelKind::kBrute})
    if (accel_kind_name(kind) == name) return kind;
  return std::nullopt;
}

std::string_view kernel_isa_name(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kSse2:
      return "sse2";
    case KernelIsa::kAvx2:
      return "avx2";
    case KernelIsa::kAvx512:
      return "avx512";
  }
  return "unknown";
}

std::optional<KernelIsa> parse_kernel_isa(std::string_view name) {
  for (KernelIsa isa : {KernelIsa::kSse2, KernelIsa::kAvx2, KernelIsa::kAvx512})
    if (kernel_isa_name(isa) == name) return isa;
  return std::nullopt;
}

bool cpu_supports_kernels(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kSse2:
      return TESSERA_HAVE_SIMD_KERNELS != 0;
    case KernelIsa::kAvx2:
      return accel_detail::cpu_has_avx2();
    case KernelIsa::kAvx512:
      return accel_detail::cpu_has_avx512();
  }
  return false;
}

bool avx512_lowers_clock(std::string_view vendor, unsigned family, unsigned model) {
  return vendor == "GenuineIntel" && family == 6 && (model == 85 || model == 87 || model == 133);
}

KernelIsa preferred_kernel_isa() {
  static const KernelIsa preferred = [] {
#if TESSERA_HAVE_SIMD_KERNELS
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (__get_cpuid(0, &eax, &ebx, &ecx, &edx) == 0) return KernelIsa::kAvx512;
    char vendor[12];
    std::memcpy(vendor, &ebx, 4);
    std::memcpy(vendor + 4, &edx, 4);
    std::memcpy(vendor + 8, &ecx, 4);
    if (__get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0) return KernelIsa::kAvx512;
    // Family and model with their extended fields (Intel's SDM, CPUID leaf 1).
    const unsigned base_family = (eax >> 8) & 0xfU;
    const unsigned family = base_family == 0xfU ? base_family + ((eax >> 20) & 0xffU) : base_family;
    const unsigned model = base_family == 0x6U || base_family == 0xfU
                               ? ((eax >> 4) & 0xfU) | (((eax >> 16) & 0xfU) << 4)
                               : (eax >> 4) & 0xfU;
    if (avx512_lowers_clock(std::string_view(vendor, 12), family, model)) {
      spdlog::info(
          "triangle kernels: AVX2 preferred over AVX-512 on this processor (family {}, "
          "model {}: 512-bit instructions lower its clock)",
          family, model);
      return KernelIsa::kAvx2;
    }
#endif
    return KernelIsa::kAvx512;
  }();
  return preferred;
}

AccelKind choose_accel_kind(std::size_t triangle_count) {
  return triangle_count <= kBruteForceMaxTriangles ? AccelKind::kBrute : AccelKind::kWide;
}

float choose_spatial_split_budget(std::size_t triangle_count, float presplit_budget) {
  if (presplit_budget > 0.0f || triangle_count > kAutoSpatialSplitMaxTriangles) return 0.0f;
  return kAutoSpatialSplitBudget;
}

float choose_presplit_budget(double fill_ratio, std::size_t triangle_count) {
  const double threshold = triangle_count <= kAutoSpatialSplitMaxTriangles
                               ? kAutoPresplitMinFillRatio
                               : kAutoPresplitMinFillRatioWithoutSpatialSplits;
  if (!(fill_ratio >= threshold)) return 0.0f;  // NaN too
  return static_cast<float>(std::fmin(fill_ratio / kAutoPresplitFillRatioPerReference,
                                      static_cast<double>(kAutoPresplitMaxBudget)));
}

namespace {

// The same admission rule as the SIMD kernels, for the scalar binary-BVH path.
bool is_traceable(const Ray& ray) {
  for (int axis = 0; axis < 3; ++axis)
    if (!std::isfinite(ray.origin[axis]) || !std::isfinite(ray.direction[axis])) return false;
  if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) return false;
  return ray.t_min <= ray.t_max;
}

// Per-ray data of the scalar path: the watertight test's shear is computed once per ray,
// not once per triangle.
struct ScalarTriangles {
  const Triangle* triangles;
  const std::uint32_t* references;  // null: hits name the triangle's index
  WatertightRay shear;

  bool operator()(std::uint32_t index, const Ray& ray, float t_max, HitRecord& hit) const {
    if (!intersect(triangles[index], ray, shear, t_max, hit, index)) return false;
    if (references != nullptr) hit.primitive = references[index];
    return true;
  }
};

const accel_detail::TriangleKernels* select_kernels(AccelKind kind, KernelIsa max_isa) {
#if TESSERA_HAVE_SIMD_KERNELS
  const bool brute = kind == AccelKind::kBrute;
  if (max_isa >= KernelIsa::kAvx512 && cpu_supports_kernels(KernelIsa::kAvx512))
    return brute ? &accel_detail::avx512::brute_kernels() : &accel_detail::avx512::wide_kernels();
  if (max_isa >= KernelIsa::kAvx2 && cpu_supports_kernels(KernelIsa::kAvx2))
    return brute ? &accel_detail::avx2::brute_kernels() : &accel_detail::avx2::wide_kernels();
  return brute ? &accel_detail::sse2::brute_kernels() : &accel_detail::sse2::wide_kernels();
#else
  (void)kind;
  (void)max_isa;
  return nullptr;
#endif
}

}  // namespace

TriangleAccel TriangleAccel::build(std::span<const Triangle> triangles,
                                   const AccelBuildOptions& options,
                                   std::span<const std::uint32_t> references) {
  const auto start = std::chrono::steady_clock::now();
  if (triangles.size() > (std::size_t{kWideMaxLeafFirst} + 1) * 4)
    throw std::invalid_argument("TriangleAccel: too many triangles (" +
                                std::to_string(triangles.size()) + ")");
  if (!references.empty() && references.size() != triangles.size())
    throw std::invalid_argument("TriangleAccel: " + std::to_string(references.size()) +
                                " references for " + std::to_string(triangles.size()) +
                                " triangles");
  TriangleAccel accel;
  AccelKind kind =
      options.kind == AccelKind::kAuto ? choose_accel_kind(triangles.size()) : options.kind;
  if (!TESSERA_HAVE_SIMD_KERNELS) kind = AccelKind::kBvh;

  // Degenerate triangles (zero or near-zero area, non-finite vertices: see is_degenerate) are
  // dropped here, once per build, rather than tested per ray: the SIMD kernels never see
  // them and their hot loop stays as it was. tessera::intersect rejects them as well, so the
  // structures still agree with the scalar test hit for hit. `bounds[i]` belongs to `ids[i]`.
  std::vector<Aabb> bounds;
  std::vector<std::uint32_t> ids;
  bounds.reserve(triangles.size());
  ids.reserve(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (is_degenerate(triangles[i])) continue;
    bounds.push_back(tessera::bounds(triangles[i]));
    ids.push_back(static_cast<std::uint32_t>(i));
    accel.bounds_.extend(bounds.back());
  }
  accel.stats_.degenerate = triangles.size() - ids.size();

  switch (kind) {
    case AccelKind::kAuto:
    case AccelKind::kBvh:
      kind = AccelKind::kBvh;
      accel.bvh_ = build_bvh(bounds, ids, options.bvh);
      accel.triangles_.assign(triangles.begin(), triangles.end());
      accel.references_.assign(references.begin(), references.end());
      accel.stats_.bytes = accel.bvh_.nodes.size() * sizeof(BvhNode) +
                           accel.bvh_.primitives.size() * 4 +
                           accel.triangles_.size() * sizeof(Triangle);
      accel.stats_.nodes = accel.bvh_.nodes.size();
      accel.stats_.depth = accel.bvh_.depth;
      accel.stats_.leaf_references = accel.bvh_.primitives.size();
      break;
    case AccelKind::kWide: {
      BvhBuildOptions wide = options.wide;
      wide.max_leaf_size = std::min(wide.max_leaf_size, kWideMaxLeafItems * 4);
      // Pre-splitting, asked for or chosen from how poorly the triangles fill their boxes:
      // several references (boxes) per poorly fitting triangle.
      accel.stats_.fill_ratio = box_fill_ratio(triangles, ids, bounds);
      accel.stats_.presplit_chosen = !options.presplit_budget.has_value();
      accel.stats_.presplit_budget = options.presplit_budget.value_or(
          choose_presplit_budget(accel.stats_.fill_ratio, ids.size()));
      // Spatial splits, given or chosen, replace pre-splitting.
      accel.stats_.spatial_split_chosen = !options.spatial_split_budget.has_value();
      accel.stats_.spatial_split_budget = options.spatial_split_budget.value_or(
          choose_spatial_split_budget(ids.size(), accel.stats_.presplit_budget));
      const bool spatial = accel.stats_.spatial_split_budget > 0.0f;
      if (spatial) accel.stats_.presplit_budget = 0.0f;
      const bool presplit = accel.stats_.presplit_budget > 0.0f;
      HugePageVector<Aabb> piece_bounds;
      HugePageVector<std::uint32_t> piece_ids;
      if (presplit)
        presplit_triangles(triangles, ids, bounds, accel.bounds_, accel.stats_.presplit_budget,
                           piece_bounds, piece_ids);
      const Bvh binary =
          spatial ? build_sbvh(
                        triangles, ids,
                        SpatialSplitOptions{
                            .bvh = wide, .max_extra_references = accel.stats_.spatial_split_budget})
          : presplit ? build_bvh(piece_bounds, piece_ids, wide)
                     : build_bvh(bounds, ids, wide);
      accel.blocks_.reserve(binary.primitives.size() / 3 + 1);
      std::vector<std::uint32_t> leaf_ids;
      accel.wide_ = collapse_to_wide(
          binary,
          [&](std::uint32_t offset, std::uint32_t count) {
            std::span<const std::uint32_t> leaf =
                std::span<const std::uint32_t>(binary.primitives).subspan(offset, count);
            if (presplit || spatial) {  // parts of one triangle can meet in a leaf: test it once
              leaf_ids.assign(leaf.begin(), leaf.end());
              std::sort(leaf_ids.begin(), leaf_ids.end());
              leaf_ids.erase(std::unique(leaf_ids.begin(), leaf_ids.end()), leaf_ids.end());
              leaf = leaf_ids;
            }
            const std::uint32_t first =
                append_triangle_blocks(triangles, leaf, accel.blocks_, references);
            if (first > kWideMaxLeafFirst)
              throw std::length_error("wide BVH: too many triangle references");
            return make_wide_leaf(first, static_cast<std::uint32_t>((leaf.size() + 3) / 4));
          },
          std::min(options.wide_merge_limit, kWideMaxLeafItems * 4));
      break;
    }
    case AccelKind::kOctree: {
      OctreeLimits limits = options.octree;
      limits.max_leaf_items = kWideMaxLeafItems * 4;
      std::vector<std::uint32_t> cell_ids;
      accel.wide_ = build_octree(bounds, limits, [&](std::span<const std::uint32_t> cell) {
        // The octree numbers the kept triangles; the blocks name them by their input index.
        cell_ids.clear();
        for (std::uint32_t index : cell) cell_ids.push_back(ids[index]);
        const std::uint32_t first =
            append_triangle_blocks(triangles, cell_ids, accel.blocks_, references);
        if (first > kWideMaxLeafFirst)
          throw std::length_error("octree: too many triangle references");
        return make_wide_leaf(first, static_cast<std::uint32_t>((cell.size() + 3) / 4));
      });
      break;
    }
    case AccelKind::kBrute:
      append_triangle_blocks(triangles, ids, accel.blocks_, references);
      break;
  }
  if (kind != AccelKind::kBvh) {
    // The traversal stack holds kWideStackSize entries, enough for trees of kMaxBvhDepth
    // levels; the builders guarantee that depth, and this keeps it so.
    if (accel.wide_.depth > kMaxBvhDepth)
      throw std::logic_error("TriangleAccel: tree deeper than the traversal stack allows");
    accel.kernels_ = select_kernels(kind, options.max_isa);
    if (!accel.wide_.nodes.empty()) {
      const WideBvhNode& root = accel.wide_.nodes[0];
      for (std::uint32_t axis = 0; axis < 3; ++axis) {
        // Empty slots hold (+inf, -inf), which min and max pass over.
        float lower = kInfinity, upper = -kInfinity;
        for (std::uint32_t slot = 0; slot < kWideBvhWidth; ++slot) {
          lower = std::min(lower, root.bounds[2 * axis][slot]);
          upper = std::max(upper, root.bounds[2 * axis + 1][slot]);
        }
        accel.root_box_[axis] = lower;
        accel.root_box_[4 + axis] = upper;
      }
      accel.root_box_[3] = accel.root_box_[2];
      accel.root_box_[7] = accel.root_box_[6];
    }
    accel.stats_.bytes = accel.wide_.bytes() + accel.blocks_.size() * sizeof(TriangleBlock4);
    accel.stats_.nodes = accel.wide_.nodes.size();
    accel.stats_.depth = accel.wide_.depth;
    accel.stats_.sah = wide_sah_cost(accel.wide_);
    accel.stats_.leaf_references = 0;
    for (const TriangleBlock4& block : accel.blocks_)
      for (std::uint32_t id : block.ids)
        accel.stats_.leaf_references += id != kInvalidIndex ? 1 : 0;
  }
  accel.stats_.kind = kind;
  accel.stats_.isa = accel.kernels_ != nullptr ? accel.kernels_->isa : "scalar";
  accel.stats_.triangles = triangles.size();
  accel.stats_.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::info(
      "triangle accel: {} ({}) for {} triangles{}{}{}: {:.3f} s, {:.1f} bytes/triangle, depth {}",
      accel_kind_name(kind), accel.stats_.isa, triangles.size(),
      options.kind == AccelKind::kAuto ? " (chosen by size)" : " (forced)",
      accel.stats_.degenerate == 0
          ? std::string()
          : fmt::format(", {} degenerate dropped", accel.stats_.degenerate),
      kind != AccelKind::kWide ? std::string()
      : accel.stats_.spatial_split_budget > 0.0f
          ? fmt::format(
                ", spatial splits (budget {:.3g}, {}; box fill ratio {:.1f}) to {} references",
                accel.stats_.spatial_split_budget,
                accel.stats_.spatial_split_chosen ? "chosen" : "given", accel.stats_.fill_ratio,
                accel.stats_.leaf_references)
      : accel.stats_.presplit_budget > 0.0f
          ? fmt::format(", pre-split (budget {:.3g}, {}; box fill ratio {:.1f}) to {} references",
                        accel.stats_.presplit_budget,
                        accel.stats_.presplit_chosen ? "chosen" : "given", accel.stats_.fill_ratio,
                        accel.stats_.leaf_references)
          : fmt::format(
                ", binned build, no spatial splits or pre-split ({}; box fill ratio {:.1f})",
                accel.stats_.presplit_chosen && accel.stats_.spatial_split_chosen ? "chosen"
                                                                                  : "given",
                accel.stats_.fill_ratio),
      accel.stats_.build_seconds,
      triangles.empty()
          ? 0.0
          : static_cast<double>(accel.stats_.bytes) / static_cast<double>(triangles.size()),
      accel.stats_.depth);
  return accel;
}

bool TriangleAccel::closest(const Ray& ray, HitRecord& hit) const {
  if (kernels_ != nullptr) return kernels_->closest(view(), ray, hit);
  if (!is_traceable(ray)) return false;
  HitRecord found;
  found.t = ray.t_max;
  if (!traverse_bvh<false>(
          bvh_.view(), ray, found,
          ScalarTriangles{triangles_.data(), references_.empty() ? nullptr : references_.data(),
                          WatertightRay(ray.direction)}))
    return false;
  hit = found;
  return true;
}

bool TriangleAccel::occluded(const Ray& ray) const {
  if (kernels_ != nullptr) return kernels_->occluded(view(), ray);
  if (!is_traceable(ray)) return false;
  HitRecord found;
  found.t = ray.t_max;
  return traverse_bvh<true>(
      bvh_.view(), ray, found,
      ScalarTriangles{triangles_.data(), references_.empty() ? nullptr : references_.data(),
                      WatertightRay(ray.direction)});
}

std::uint32_t TriangleAccel::all_hits(const Ray& ray, HitRecord* hits,
                                      std::uint32_t capacity) const {
  if (kernels_ != nullptr) return kernels_->all_hits(view(), ray, hits, capacity);
  if (!is_traceable(ray)) return 0;
  return traverse_bvh_all(
      bvh_.view(), ray, hits, capacity,
      ScalarTriangles{triangles_.data(), references_.empty() ? nullptr : references_.data(),
                      WatertightRay(ray.direction)});
}

void TriangleAccel::closest(std::span<const Ray> rays, std::span<HitRecord> hits) const {
  if (hits.size() < rays.size())
    throw std::invalid_argument("TriangleAccel::closest: fewer hits than rays");
  if (kernels_ != nullptr)
    return kernels_->closest_batch(view(), rays.data(), hits.data(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    hits[i] = HitRecord{};
    closest(rays[i], hits[i]);
  }
}

void TriangleAccel::occluded(std::span<const Ray> rays, std::span<std::uint8_t> result) const {
  if (result.size() < rays.size())
    throw std::invalid_argument("TriangleAccel::occluded: fewer results than rays");
  if (kernels_ != nullptr)
    return kernels_->occluded_batch(view(), rays.data(), result.data(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) result[i] = occluded(rays[i]) ? 1 : 0;
}

}  // namespace tessera
