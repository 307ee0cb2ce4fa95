#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "tessera/accel/bvh.hpp"
#include "tessera/accel/triangle_accel.hpp"

namespace tessera {

// One placement of a mesh: rays are taken into the mesh's own space, so any number of
// instances share one TriangleAccel.
struct MeshInstance {
  const TriangleAccel* mesh = nullptr;  // must outlive the InstanceAccel
  glm::mat4 world_from_object{1.0f};    // affine, invertible
  // Added to the mesh's primitive names by the flat queries (closest into a HitRecord,
  // all_hits), so one reference names instance and triangle together.
  std::uint32_t primitive_base = 0;
};

// The most hits all_hits collects from one instance (a larger capacity is clamped to it):
// a fixed buffer on the stack, so the query allocates nothing.
inline constexpr std::uint32_t kInstanceAllHitsMax = 32;

struct InstanceHit {
  HitRecord hit;  // t along the world ray; primitive as the mesh names it
  std::uint32_t instance = kInvalidIndex;
};

// Two-level acceleration: a BVH over the instances' world boxes, each leaf a mesh's own
// structure walked with the ray moved into object space. The direction is transformed
// without normalising, so t means the same distance along the ray in both spaces.
class InstanceAccel {
 public:
  InstanceAccel() = default;
  explicit InstanceAccel(std::vector<MeshInstance> instances);

  bool closest(const Ray& ray, InstanceHit& hit) const;
  bool occluded(const Ray& ray) const;
  // Closest hit in (ray.t_min, ray.t_max) named primitive_base + the mesh's name; `hit` is
  // written only on a hit.
  bool closest(const Ray& ray, HitRecord& hit) const;
  // The min(capacity, kInstanceAllHitsMax) nearest hits in (ray.t_min, ray.t_max), sorted
  // by t, named like closest(ray, HitRecord&); returns how many were written.
  std::uint32_t all_hits(const Ray& ray, HitRecord* hits, std::uint32_t capacity) const;

  std::size_t instance_count() const { return instances_.size(); }
  // Top-level nodes and placements, excluding the meshes (they are shared).
  std::size_t bytes() const {
    return top_.nodes.size() * sizeof(BvhNode) + top_.primitives.size() * sizeof(std::uint32_t) +
           instances_.size() * sizeof(Placed);
  }

  const Bvh& top_level() const { return top_; }

 private:
  struct Placed {
    const TriangleAccel* mesh;
    glm::mat4 object_from_world;
    std::uint32_t primitive_base;
  };
  Ray to_object(const Placed& p, const Ray& ray) const;

  std::vector<Placed> instances_;
  Bvh top_;
};

}  // namespace tessera
