#pragma once
#include <cstdint>

namespace tessera {

// How the path tracer finds emitters at a vertex that is not a mirror or glass.
enum class LightStrategy : std::uint32_t {
  kMis = 0,    // light and BSDF samples, weighted by the power heuristic
  kLight = 1,  // light samples only; emitters a scattered ray hits are not counted
  kBsdf = 2,   // BSDF samples only; hidden emitters (no ray can hit) are still light-sampled
};

}  // namespace tessera
