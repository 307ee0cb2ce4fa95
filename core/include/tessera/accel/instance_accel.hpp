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
};

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

  const Bvh& top_level() const { return top_; }

 private:
  struct Placed {
    const TriangleAccel* mesh;
    glm::mat4 object_from_world;
  };
  Ray to_object(const Placed& p, const Ray& ray) const;

  std::vector<Placed> instances_;
  Bvh top_;
};

}  // namespace tessera
