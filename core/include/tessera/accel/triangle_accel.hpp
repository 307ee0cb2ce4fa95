#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/octree.hpp"
#include "tessera/accel/triangle_block.hpp"
#include "tessera/accel/wide_bvh.hpp"

namespace tessera {

// The acceleration structures a triangle set can be traced with.
//   bvh    - the binary BVH in its flattened GPU layout, walked one box at a time (scalar)
//   wide   - the BVH collapsed to eight-wide nodes, SIMD box and triangle tests (SSE2/AVX2)
//   octree - a spatial octree over the scene's bounding cube, triangles referenced by every
//            cell they overlap; same SIMD node and triangle tests as `wide`
//   brute  - every triangle block against every ray: for scenes of a few triangles
enum class AccelKind : std::uint8_t { kAuto, kBvh, kWide, kOctree, kBrute };

std::string_view accel_kind_name(AccelKind kind);
std::optional<AccelKind> parse_accel_kind(std::string_view name);

// The instruction sets the SIMD kernels are compiled for, narrowest first. A structure is
// walked by the widest one the processor runs, up to AccelBuildOptions::max_isa.
//   sse2   - the x86-64 baseline: eight-wide boxes as two four-lane halves
//   avx2   - eight-wide boxes in one instruction, two triangle blocks at a time
//   avx512 - the AVX2 kernels with AVX-512 (F, VL, BW, DQ) allowed: 32 vector registers,
//            compares straight into masks, and leaves of three or four triangle blocks
//            tested in one sixteen-lane pass
enum class KernelIsa : std::uint8_t { kSse2, kAvx2, kAvx512 };

std::string_view kernel_isa_name(KernelIsa isa);
std::optional<KernelIsa> parse_kernel_isa(std::string_view name);
// True when this processor runs the kernels compiled for `isa`.
bool cpu_supports_kernels(KernelIsa isa);

// True for the processors whose cores lower their clock while they run 512-bit
// floating-point instructions (and for some time after, slowing whatever else the core runs
// then): Intel's first AVX-512 cores, Skylake-SP and -X, Cascade Lake and Cooper Lake
// (family 6, model 85) and the Xeon Phi (models 87 and 133). The AVX-512 kernels' sixteen-lane
// leaf test is such an instruction stream. Measured on a Cascade Lake Xeon (model 85,
// bench/accel/README.md): the AVX2 kernels trace 5-10% more rays per second there.
bool avx512_lowers_clock(std::string_view vendor, unsigned family, unsigned model);
// The widest kernels worth running on this processor: AVX-512 except where
// avx512_lowers_clock, then AVX2 (a cap: narrower where the processor lacks the set).
KernelIsa preferred_kernel_isa();

// Up to this many triangles brute force is as fast as any tree (measured, see the note in
// bench/accel/README.md); above it the wide BVH is fastest for every scene measured.
inline constexpr std::size_t kBruteForceMaxTriangles = 48;
// Up to this many visible triangles beside other bounded shapes are traced through the
// shape BVH rather than this structure (PrimitiveList::build_accelerators says why).
inline constexpr std::size_t kShapeBvhMaxTriangles = 1024;
AccelKind choose_accel_kind(std::size_t triangle_count);

struct AccelBuildOptions {
  AccelKind kind = AccelKind::kAuto;
  BvhBuildOptions bvh{};  // for kBvh
  // For kWide: the binary BVH that is collapsed, with the SAH counting 4-triangle blocks,
  // and the largest subtree the collapse turns into one leaf (see collapse_to_wide). Chosen
  // by measurement on suzanne-sub5 (bench/accel/README.md): leaves of 4 or 8 and costs
  // from 0.5 to 2 were within noise; merging subtrees of up to 16 was 5-10% faster than
  // none and uses 15% less memory.
  BvhBuildOptions wide{4, 4, 1.0f, 1.0f, 16, true};
  std::uint32_t wide_merge_limit = 16;
  // For kWide: pre-splitting (presplit.hpp), up to this many extra references per triangle,
  // given to the triangles that fill their boxes worst; 0 keeps one reference per triangle.
  // Unset (the default): chosen from the mesh by choose_presplit_budget, which pre-splits
  // only where the triangles fill their boxes poorly (measured, bench/accel/README.md).
  std::optional<float> presplit_budget;
  // For kWide: build the binary BVH with spatial splits (sbvh.hpp) instead of the binned
  // builder, with up to this many extra references per triangle; 0: the binned builder. A
  // budget above 0 turns pre-splitting off. Unset (the default): chosen by
  // choose_spatial_split_budget.
  std::optional<float> spatial_split_budget;
  OctreeLimits octree{};
  // The widest kernels used where the processor runs them (a narrower one for tests and
  // comparisons). By default the fastest for this processor (preferred_kernel_isa).
  KernelIsa max_isa = preferred_kernel_isa();
};

// The pre-split budget for a set of `triangle_count` triangles whose box_fill_ratio
// (presplit.hpp) is `fill_ratio`: none below kAutoPresplitMinFillRatio where the mesh is small
// enough for spatial splits (choose_spatial_split_budget), or below
// kAutoPresplitMinFillRatioWithoutSpatialSplits where the binned builder is the alternative,
// then one extra reference per triangle for every
// kAutoPresplitFillRatioPerReference of ratio, up to kAutoPresplitMaxBudget. Measured on the
// suite of bench/accel/README.md (1 thread, against the same Embree build): evenly
// tessellated meshes (ratio 2.9-5.2) lose up to 19% from a budget of 1; on tubes of long thin
// triangles the break-even against the binned builder is a ratio of about 13, and above it
// every doubling of the budget up to 4 gains (ratio 31: +21% with 1, +42% with 4; ratio 520:
// +67% with 1, +300% with 4). Against spatial splits the break-even is higher: on held-out
// grass fields and tubes of ratio 17-32 spatial splits were as fast or faster on 9 of 10
// ray sets (up to 20% on diffuse rays at 22), and pre-splitting won from 42 up (grass at 43:
// +36% primary, +60% diffuse). 4 keeps the build within Embree's high-quality build time and
// the memory at five references per triangle (250 bytes).
inline constexpr double kAutoPresplitMinFillRatio = 32.0;
inline constexpr double kAutoPresplitMinFillRatioWithoutSpatialSplits = 16.0;
inline constexpr double kAutoPresplitFillRatioPerReference = 16.0;
inline constexpr float kAutoPresplitMaxBudget = 4.0f;
float choose_presplit_budget(double fill_ratio, std::size_t triangle_count);

// The spatial-split budget for a mesh of `triangle_count` kept triangles whose pre-split
// budget (given or chosen) is `presplit_budget`: kAutoSpatialSplitBudget where nothing is
// pre-split and the mesh has at most kAutoSpatialSplitMaxTriangles triangles, 0 otherwise
// (the binned builder, several times faster, for the largest meshes; pre-splitting for
// meshes of long thin triangles, where it measured far better than spatial splits: tubes
// 2.2x Embree's diffuse speed against 0.7x). Measured over the mesh suite
// (bench/accel/README.md): spatial splits took engine from 0.85x to 1.0-1.05x Embree high
// on diffuse rays, uneven from 0.92x to 1.0x, bunny from 0.92x to 0.97x, and cost house 6%
// (still above Embree), for builds within twice Embree's high-quality build.
inline constexpr float kAutoSpatialSplitBudget = 1.0f;
inline constexpr std::size_t kAutoSpatialSplitMaxTriangles = std::size_t{4} << 20;
float choose_spatial_split_budget(std::size_t triangle_count, float presplit_budget);

struct AccelStats {
  AccelKind kind = AccelKind::kAuto;  // the structure actually built
  std::string_view isa;               // "scalar" or kernel_isa_name of the kernels
  double build_seconds = 0.0;
  std::size_t bytes = 0;  // nodes, leaf data and references, excluding the input triangles
  std::size_t nodes = 0;
  std::uint32_t depth = 0;
  std::size_t triangles = 0;
  std::size_t leaf_references = 0;    // > triangles where the octree duplicates references
  std::size_t degenerate = 0;         // zero or near-zero area (is_degenerate): dropped, never hit
  double fill_ratio = 0.0;            // box_fill_ratio of the kept triangles (kWide only)
  float presplit_budget = 0.0f;       // the pre-split budget used (kWide only; 0: none)
  bool presplit_chosen = false;       // the budget was chosen from the mesh, not given
  float spatial_split_budget = 0.0f;  // spatial splits' budget (kWide only; 0: binned build)
  bool spatial_split_chosen = false;  // that budget was chosen, not given
  WideSahCost sah{};                  // of the wide tree (kWide and kOctree): its quality
};

// The read-only data the SIMD kernels walk (wide BVH, octree and brute force).
struct WideTriangleView {
  const WideBvhNode* nodes = nullptr;  // null for brute force
  const TriangleBlock4* blocks = nullptr;
  std::uint32_t block_count = 0;
  // Request each entered child's memory as soon as its parent is tested: pays where the
  // structure is larger than the caches, costs where it is not (see kPrefetchMinBytes).
  bool prefetch = false;
  // The root node's box (the union of its children's), lower then upper corner, each as
  // x, y, z, z (16-byte aligned); null for brute force. Rays that miss it skip the walk's
  // per-ray set-up (accel_detail::*::may_enter_root).
  const float* root_box = nullptr;
};

// Structures of at least this many bytes (nodes and blocks; an L2 cache) are walked with
// prefetching. Measured (bench/accel/README.md, random soups and meshes): -5 to -10% from 64
// to 4,096 triangles (up to 200 kB), +3% at 16,384 (800 kB), +9% at 65,536 (3 MB), +5% on
// diffuse rays over a million triangles (50 MB).
inline constexpr std::size_t kPrefetchMinBytes = std::size_t{512} << 10;

namespace accel_detail {
// One compiled kernel per query, per structure and per instruction set, chosen when the
// structure is built; a call costs one indirect jump per ray (or per batch), never a
// test per node.
struct TriangleKernels {
  std::string_view isa;
  bool (*closest)(const WideTriangleView&, const Ray&, HitRecord&);
  bool (*occluded)(const WideTriangleView&, const Ray&);
  std::uint32_t (*all_hits)(const WideTriangleView&, const Ray&, HitRecord*, std::uint32_t);
  void (*closest_batch)(const WideTriangleView&, const Ray*, HitRecord*, std::size_t);
  void (*occluded_batch)(const WideTriangleView&, const Ray*, std::uint8_t*, std::size_t);
};
}  // namespace accel_detail

// Traces rays against a triangle set. Hits name the triangle by its index in the array
// given to build() (or by the reference given for it); u and v are the barycentric weights of p1
// and p2 (as tessera::intersect). Rays with a non-finite origin or direction, a zero direction or
// t_min > t_max never hit. t_min may be negative (hits behind the origin count), but the
// boxes' rounding padding widens them towards +t only, as tessera's scalar box test does: a hit
// behind the origin in a box the ray only grazes there (a flat box along its face) can be
// missed. The renderer's rays have t_min >= 0.
class TriangleAccel {
 public:
  TriangleAccel() = default;  // traces nothing

  // Hits name triangles[i] by references[i] when references are given (e.g. the renderer's
  // tagged primitive references), else by i.
  static TriangleAccel build(std::span<const Triangle> triangles,
                             const AccelBuildOptions& options = {},
                             std::span<const std::uint32_t> references = {});

  // Closest hit in (ray.t_min, ray.t_max); `hit` is written only on a hit.
  bool closest(const Ray& ray, HitRecord& hit) const;
  // Any hit in (ray.t_min, ray.t_max): stops at the first one found.
  bool occluded(const Ray& ray) const;
  // The `capacity` nearest hits in (ray.t_min, ray.t_max), sorted by t, each triangle once;
  // returns how many were written.
  std::uint32_t all_hits(const Ray& ray, HitRecord* hits, std::uint32_t capacity) const;

  // Batches: hits[i].primitive is kInvalidIndex where rays[i] missed.
  void closest(std::span<const Ray> rays, std::span<HitRecord> hits) const;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;

  const AccelStats& stats() const { return stats_; }
  const Aabb& bounds() const { return bounds_; }  // of all triangles; empty when none
  const Bvh& binary_bvh() const { return bvh_; }
  const WideBvh& wide_bvh() const { return wide_; }

 private:
  WideTriangleView view() const {
    return WideTriangleView{wide_.nodes.empty() ? nullptr : wide_.nodes.data(), blocks_.data(),
                            static_cast<std::uint32_t>(blocks_.size()),
                            stats_.bytes >= kPrefetchMinBytes,
                            wide_.nodes.empty() ? nullptr : root_box_.data()};
  }

  AccelStats stats_;
  Aabb bounds_;
  std::vector<Triangle> triangles_;        // kBvh only: its scalar traversal reads them directly
  std::vector<std::uint32_t> references_;  // kBvh only: hit names, when given
  Bvh bvh_;                                // kBvh only
  WideBvh wide_;                           // kWide and kOctree
  HugePageVector<TriangleBlock4> blocks_;
  alignas(16) std::array<float, 8> root_box_{};             // WideTriangleView::root_box
  const accel_detail::TriangleKernels* kernels_ = nullptr;  // null for kBvh
};

}  // namespace tessera
