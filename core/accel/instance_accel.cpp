#include "tessera/accel/instance_accel.hpp"

#include <algorithm>
#include <stdexcept>

#include "tessera/accel/bvh_traversal.hpp"

namespace tessera {
namespace {

Aabb transform_box(const glm::mat4& m, const Aabb& box) {
  Aabb out;
  if (box.empty()) return out;
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 p((corner & 1) ? box.upper.x : box.lower.x, (corner & 2) ? box.upper.y : box.lower.y,
                 (corner & 4) ? box.upper.z : box.lower.z);
    out.extend(vec3(m * vec4(p, 1.0f)));
  }
  return out;
}

}  // namespace

InstanceAccel::InstanceAccel(std::vector<MeshInstance> instances) {
  std::vector<Aabb> boxes;
  std::vector<std::uint32_t> references;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const MeshInstance& instance = instances[i];
    if (instance.mesh == nullptr)
      throw std::invalid_argument("InstanceAccel: instance without a mesh");
    if (glm::determinant(glm::mat3(instance.world_from_object)) == 0.0f)
      throw std::invalid_argument("InstanceAccel: instance transform is not invertible");
    instances_.push_back(
        Placed{instance.mesh, glm::inverse(instance.world_from_object), instance.primitive_base});
    // The box of the transformed object box holds the transformed triangles.
    boxes.push_back(transform_box(instance.world_from_object, instance.mesh->bounds()));
    references.push_back(static_cast<std::uint32_t>(i));
  }
  BvhBuildOptions options;
  options.max_leaf_size = 1;  // one instance per leaf: each costs a whole walk of its mesh
  top_ = build_bvh(boxes, references, options);
}

Ray InstanceAccel::to_object(const Placed& p, const Ray& ray) const {
  return Ray{vec3(p.object_from_world * vec4(ray.origin, 1.0f)),
             vec3(p.object_from_world * vec4(ray.direction, 0.0f)), ray.t_min, ray.t_max};
}

bool InstanceAccel::closest(const Ray& ray, InstanceHit& hit) const {
  HitRecord best;
  best.t = ray.t_max;
  std::uint32_t instance = kInvalidIndex;
  const bool found = traverse_bvh<false>(
      top_.view(), ray, best, [&](std::uint32_t index, const Ray& r, float t_max, HitRecord& h) {
        Ray object = to_object(instances_[index], r);
        object.t_max = t_max;
        if (!instances_[index].mesh->closest(object, h)) return false;
        instance = index;
        return true;
      });
  if (found) hit = InstanceHit{best, instance};
  return found;
}

bool InstanceAccel::closest(const Ray& ray, HitRecord& hit) const {
  InstanceHit found;
  if (!closest(ray, found)) return false;
  hit = found.hit;
  hit.primitive += instances_[found.instance].primitive_base;
  return true;
}

std::uint32_t InstanceAccel::all_hits(const Ray& ray, HitRecord* hits,
                                      std::uint32_t capacity) const {
  capacity = std::min(capacity, kInstanceAllHitsMax);
  if (capacity == 0) return 0;
  std::uint32_t count = 0;
  HitRecord bound;  // the farthest kept hit once the list is full: farther instances are culled
  bound.t = ray.t_max;
  traverse_bvh<false>(top_.view(), ray, bound,
                      [&](std::uint32_t index, const Ray& r, float t_max, HitRecord& b) {
                        const Placed& placed = instances_[index];
                        Ray object = to_object(placed, r);
                        object.t_max = t_max;
                        HitRecord found[kInstanceAllHitsMax];
                        const std::uint32_t n = placed.mesh->all_hits(object, found, capacity);
                        for (std::uint32_t k = 0; k < n; ++k) {
                          HitRecord h = found[k];
                          h.primitive += placed.primitive_base;
                          if (insert_nearest(hits, count, capacity, h)) b.t = hits[capacity - 1].t;
                        }
                        return false;  // the bound was tightened by hand; the walk must not stop
                      });
  return count;
}

bool InstanceAccel::occluded(const Ray& ray) const {
  HitRecord unused;
  unused.t = ray.t_max;
  return traverse_bvh<true>(top_.view(), ray, unused,
                            [&](std::uint32_t index, const Ray& r, float t_max, HitRecord&) {
                              Ray object = to_object(instances_[index], r);
                              object.t_max = t_max;
                              return instances_[index].mesh->occluded(object);
                            });
}

}  // namespace tessera
