#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "tessera/math/host_device.hpp"

namespace tessera {

using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using dvec3 = glm::dvec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;

TESSERA_HD TESSERA_INLINE float max_component(const vec3& v) {
  return glm::max(v.x, glm::max(v.y, v.z));
}

// Orthonormal basis around a unit normal (Duff et al. 2017, branchless). Its three uses per
// path vertex are inlined: GCC called them out of line from the path tracer's large
// functions, spilling the caller's registers around a few multiplies.
struct Frame {
  vec3 tangent, bitangent, normal;

  TESSERA_HD TESSERA_FORCE_INLINE static Frame from_normal(const vec3& n) {
    const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return Frame{vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x),
                 vec3(b, sign + n.y * n.y * a, -n.y), n};
  }
  // A basis whose tangent is `t` made orthogonal to the unit normal `n` (t must not be
  // parallel to n).
  TESSERA_HD static Frame from_normal_and_tangent(const vec3& n, const vec3& t) {
    const vec3 tangent = glm::normalize(t - n * glm::dot(t, n));
    return Frame{tangent, glm::cross(n, tangent), n};
  }
  TESSERA_HD TESSERA_FORCE_INLINE vec3 to_world(const vec3& local) const {
    return tangent * local.x + bitangent * local.y + normal * local.z;
  }
  TESSERA_HD TESSERA_FORCE_INLINE vec3 to_local(const vec3& world) const {
    return vec3(glm::dot(world, tangent), glm::dot(world, bitangent), glm::dot(world, normal));
  }
};

}  // namespace tessera
