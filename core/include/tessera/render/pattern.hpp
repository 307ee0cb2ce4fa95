#pragma once
// RayON's procedural patterns on a material's albedo, evaluated per hit. fibonacci_dots
// paints dots around the points of a spherical Fibonacci spiral (golden-angle steps in
// longitude, equal-area steps in z), as seen along a direction from the shape's centre.
// RayON parses checkerboard and stripes but draws them as the plain albedo; so does this.
#include <cmath>
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

enum class PatternType : std::uint32_t { kNone = 0, kFibonacciDots, kCheckerboard, kStripes };

struct MaterialPattern {
  PatternType type = PatternType::kNone;
  vec3 color{0.0f};
  std::uint32_t dot_count = 0;
  float cos_dot_radius = 1.0f;  // a direction within the dot radius has a larger cosine
};

// Point i of n on the unit sphere: z steps down in equal areas from the north pole, the
// longitude turns by the golden angle pi (3 - sqrt 5) each step.
TESSERA_HD TESSERA_INLINE vec3 spherical_fibonacci_point(std::uint32_t i, std::uint32_t n) {
  constexpr float kGoldenAngle = 2.39996323f;
  const float k = static_cast<float>(i) + 0.5f;
  const float z = 1.0f - 2.0f * k / static_cast<float>(n);
  const float r = std::sqrt(glm::max(0.0f, 1.0f - z * z));
  const float longitude = kGoldenAngle * k;
  return vec3(std::cos(longitude) * r, std::sin(longitude) * r, z);
}

// Whether unit `direction` lies within the dot radius of any of the pattern's points (a
// linear scan, as RayON's: the count is bounded by validation).
TESSERA_HD inline bool in_fibonacci_dot(const MaterialPattern& p, const vec3& direction) {
  for (std::uint32_t i = 0; i < p.dot_count; ++i)
    if (glm::dot(direction, spherical_fibonacci_point(i, p.dot_count)) > p.cos_dot_radius)
      return true;
  return false;
}

// The albedo at a hit: `from_centre` is the hit point relative to the shape's centre (a
// sphere's; the world origin for other shapes, as RayON has it).
TESSERA_HD inline vec3 patterned_albedo(const MaterialPattern& p, const vec3& albedo,
                                        const vec3& from_centre) {
  if (p.type != PatternType::kFibonacciDots) return albedo;
  const float length2 = glm::dot(from_centre, from_centre);
  if (!(length2 > 0.0f)) return albedo;
  return in_fibonacci_dot(p, from_centre / std::sqrt(length2)) ? p.color : albedo;
}

}  // namespace tessera
