#pragma once
#include <cstdint>
#include <limits>
#include <type_traits>

#include "tessera/math/vec.hpp"

#if !defined(__CUDA_ARCH__) && (defined(__SSE2__) || defined(_M_X64))
#include <xmmintrin.h>
#define TESSERA_RAY_SSE 1
#endif

namespace tessera {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr std::uint32_t kInvalidIndex = 0xffffffffU;

struct Ray {
  vec3 origin{0.0f};
  vec3 direction{0.0f, 0.0f, 1.0f};
  float t_min = 0.0f;
  float t_max = kInfinity;
};
static_assert(sizeof(Ray) == 8 * sizeof(float) && std::is_standard_layout_v<Ray>,
              "store_ray writes a ray as eight floats");

// `to` = Ray{origin, direction, t_min, t_max}, written on the host as two 16-byte stores.
// A ray a hit program leaves for the pipeline's next trace is copied out as two 16-byte
// loads at once; written field by field (an 8-byte and a 4-byte store per vector), each load
// spanned several stores, which the processor cannot forward from its store buffer, so the
// load waited for them to reach the cache: 1.3% of a path-traced sample's time on the
// converge scene two_lights (perf, Zen 5), at the copy in Pipeline::launch.
TESSERA_HD TESSERA_FORCE_INLINE void store_ray(Ray& to, const vec3& origin, const vec3& direction,
                                               float t_min, float t_max) {
#if defined(TESSERA_RAY_SSE)
  // The two halves by byte offset into the ray (standard layout, eight floats).
  char* bytes = reinterpret_cast<char*>(&to);
  _mm_storeu_ps(reinterpret_cast<float*>(bytes),
                _mm_setr_ps(origin.x, origin.y, origin.z, direction.x));
  _mm_storeu_ps(reinterpret_cast<float*>(bytes + 16),
                _mm_setr_ps(direction.y, direction.z, t_min, t_max));
#else
  to = Ray{origin, direction, t_min, t_max};
#endif
}

// What traversal records about the closest hit so far: enough to shade it later.
// Shading data (normal, uv) is derived afterwards from (primitive, u, v) so the inner loop
// carries only four words.
struct HitRecord {
  float t = kInfinity;
  float u = 0.0f;  // shape parameters: barycentrics for triangles, uv for quads/spheres
  float v = 0.0f;
  std::uint32_t primitive = kInvalidIndex;  // tagged primitive reference, see PrimitiveRef

  TESSERA_HD bool valid() const { return primitive != kInvalidIndex; }
};

// Ray with precomputed reciprocal direction for slab tests. Zero components give infinite
// reciprocals on purpose (+0.0 gives +inf, -0.0 gives -inf); intersect_aabb handles the
// 0 * inf = NaN of an origin lying on a slab plane.
struct TraversalRay {
  vec3 origin;
  vec3 inv_direction;

  TESSERA_HD explicit TraversalRay(const Ray& ray)
      : origin(ray.origin),
        inv_direction(1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z) {}
};

}  // namespace tessera
