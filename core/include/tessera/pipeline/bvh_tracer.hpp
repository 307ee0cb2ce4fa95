#pragma once
#include <cstdint>

#include "tessera/accel/bvh_traversal.hpp"
#include "tessera/accel/compressed_wide_bvh.hpp"
#include "tessera/accel/nearest_hits.hpp"
#include "tessera/pipeline/concepts.hpp"
#if !defined(__CUDACC__)
#include "tessera/accel/instance_accel.hpp"
#include "tessera/accel/shape_wide_bvh.hpp"
#include "tessera/accel/triangle_accel.hpp"
#endif

namespace tessera {

// Which rays see shapes marked `visible: false`: every ray but the camera's (RayON's
// meaning, and Cycles' camera ray visibility).
enum class RayKind : std::uint8_t { kCamera, kSecondary };

// The traversal stage: a BVH walked with the configuration's intersection program.
// Closest-hit, any-hit and all-hits are separate instantiations of the traversal, so a
// shadow ray's early exit is compiled in, not tested per node. On the CPU, triangles may
// live in the SIMD structure BvhView::triangles instead of the BVH; each query then asks
// it first (one call per ray) and walks the BVH for the other shapes; placements of shared
// mesh geometry (BvhView::instances, two-level) are asked the same way. nvcc never sees
// that structure (its kernels are x86 code): device code walks the BVH alone, in its
// compressed eight-wide form (BvhView::compressed_nodes) when it is set. The CPU walks
// the other shapes through BvhView::wide_nodes, the BVH's eight-wide form, when it is set
// (closest and any hit; all-hits queries walk the binary tree). Shapes no
// box can hold (infinite planes) stay outside the BVH: an intersection program with
// kHasUnbounded tests them per ray through its *_unbounded functions. Shapes hidden from
// the camera are in a small tree of their own (BvhView::hidden_nodes) that every query but
// a camera ray's walks as well.
template <typename I>
concept HasUnboundedShapes = requires {
  requires I::kHasUnbounded;
};

template <IntersectionProgram Intersection>
class BvhTracer {
 public:
  TESSERA_HD BvhTracer(BvhView bvh, Intersection intersection)
      : bvh_(bvh), intersection_(intersection) {}

  TESSERA_HD bool trace_closest(const Ray& ray, HitRecord& hit,
                                RayKind kind = RayKind::kSecondary) const {
    hit.t = ray.t_max;
    bool found = false;
#if !defined(__CUDACC__)
    if (bvh_.triangles != nullptr) found = bvh_.triangles->closest(ray, hit);
    if (bvh_.instances != nullptr) {
      Ray nearer = ray;
      nearer.t_max = hit.t;
      found = bvh_.instances->closest(nearer, hit) || found;
    }
#endif
    if (bvh_.node_count != 0) found = walk<false>(ray, hit) || found;
    if constexpr (HasUnboundedShapes<Intersection>)
      found = intersection_.intersect_unbounded(ray, hit, kind == RayKind::kCamera) || found;
    if (kind != RayKind::kCamera && bvh_.hidden_node_count != 0)
      found = walk_hidden<false>(ray, hit) || found;
    return found;
  }

  // Any hit, with its record: the first one traversal finds, not necessarily the nearest.
  TESSERA_HD bool trace_any(const Ray& ray, HitRecord& hit,
                            RayKind kind = RayKind::kSecondary) const {
    hit.t = ray.t_max;
#if !defined(__CUDACC__)
    if (bvh_.triangles != nullptr && bvh_.triangles->closest(ray, hit)) return true;
    if (bvh_.instances != nullptr && bvh_.instances->closest(ray, hit)) return true;
#endif
    if constexpr (HasUnboundedShapes<Intersection>)
      if (intersection_.intersect_unbounded(ray, hit, kind == RayKind::kCamera)) return true;
    if (bvh_.node_count != 0 && walk<true>(ray, hit)) return true;
    return kind != RayKind::kCamera && bvh_.hidden_node_count != 0 && walk_hidden<true>(ray, hit);
  }

  TESSERA_HD bool occluded(const Ray& ray) const {
#if !defined(__CUDACC__)
    if (bvh_.triangles != nullptr && bvh_.triangles->occluded(ray)) return true;
    if (bvh_.instances != nullptr && bvh_.instances->occluded(ray)) return true;
#endif
    if constexpr (HasUnboundedShapes<Intersection>)
      if (intersection_.occluded_unbounded(ray)) return true;
    HitRecord hit;
    hit.t = ray.t_max;
    // Triangles alone: no call into the walks.
    if (bvh_.node_count != 0 && walk<true>(ray, hit)) return true;
    return bvh_.hidden_node_count != 0 && walk_hidden<true>(ray, hit);
  }

  // Up to kMaxHits nearest hits, sorted by t. Once the list is full, subtrees beyond its
  // farthest entry are culled, so the cost stays close to a closest-hit query for small N.
  template <int kMaxHits>
  TESSERA_HD int trace_all(const Ray& ray, HitRecord (&hits)[kMaxHits],
                           RayKind kind = RayKind::kSecondary) const {
    std::uint32_t count = 0;
    HitRecord bound;
    bound.t = ray.t_max;
    // Every source adds its hits through `keep`, which narrows the bound once the list is full.
    const auto keep = [&](const HitRecord& h) {
      if (insert_nearest(hits, count, kMaxHits, h)) bound.t = hits[kMaxHits - 1].t;
    };
#if !defined(__CUDACC__)
    if (bvh_.triangles != nullptr) {
      HitRecord found[kMaxHits];
      const std::uint32_t n = bvh_.triangles->all_hits(ray, found, kMaxHits);
      for (std::uint32_t i = 0; i < n; ++i) keep(found[i]);
    }
    if (bvh_.instances != nullptr) {
      HitRecord found[kMaxHits];
      Ray nearer = ray;
      nearer.t_max = bound.t;
      const std::uint32_t n = bvh_.instances->all_hits(nearer, found, kMaxHits);
      for (std::uint32_t i = 0; i < n; ++i) keep(found[i]);
    }
#endif
    if constexpr (HasUnboundedShapes<Intersection>)
      intersection_.intersect_all_unbounded(ray, bound.t, keep, kind == RayKind::kCamera);
    const auto keep_all = [&](std::uint32_t primitive, const Ray& r, float t_max, HitRecord&) {
      HitRecord found[4];  // a torus is crossed up to four times
      int n;
      if constexpr (HasIntersectAll<Intersection>) {
        n = intersection_.intersect_all(primitive, r, t_max, found, 4);
      } else {
        n = intersection_.intersect(primitive, r, t_max, found[0]) ? 1 : 0;
      }
      for (int i = 0; i < n; ++i) keep(found[i]);
      // `keep` tightened the walk's bound (it is `bound`); the walk must not
      // stop.
      return false;
    };
    traverse_bvh<false>(bvh_, ray, bound, keep_all);
    if (kind != RayKind::kCamera && bvh_.hidden_node_count != 0)
      traverse_bvh<false>(bvh_.hidden(), ray, bound, keep_all);
    return static_cast<int>(count);
  }

 private:
  // Closest- or any-hit walk of the BVH with the intersection program: the compressed
  // eight-wide form of the device layout when there is one, the CPU's wide form when there
  // is one, the binary tree otherwise.
  template <bool kAnyHit>
  TESSERA_HD bool walk(const Ray& ray, HitRecord& hit) const {
    const auto intersect = [this](std::uint32_t primitive, const Ray& r, float t_max,
                                  HitRecord& h) {
      return intersection_.intersect(primitive, r, t_max, h);
    };
    if (bvh_.compressed_nodes != nullptr)
      return traverse_compressed_wide<kAnyHit>(bvh_, ray, hit, intersect);
#if !defined(__CUDACC__) && TESSERA_SHAPE_WIDE_WALK
    if (bvh_.wide_nodes != nullptr) return traverse_shape_wide<kAnyHit>(bvh_, ray, hit, intersect);
#endif
    return traverse_bvh<kAnyHit>(bvh_, ray, hit, intersect);
  }

  // The tree of shapes hidden from camera rays: few (lights, mostly), so the binary walk.
  template <bool kAnyHit>
  TESSERA_HD bool walk_hidden(const Ray& ray, HitRecord& hit) const {
    return traverse_bvh<kAnyHit>(
        bvh_.hidden(), ray, hit,
        [this](std::uint32_t primitive, const Ray& r, float t_max, HitRecord& h) {
          return intersection_.intersect(primitive, r, t_max, h);
        });
  }

  BvhView bvh_;
  Intersection intersection_;
};

}  // namespace tessera
