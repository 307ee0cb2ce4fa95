#pragma once
#include <cstdint>

namespace tessera {

// Which sequence a SampleStream draws from (math/rng.hpp). Its own header so the scene
// settings (scene/scene_description.hpp) can name it without rng.hpp, which CUDA code
// includes, having to include scene headers. The values are the scene setting's name list
// order (render.sampler).
enum class SamplerKind : std::uint32_t {
  kIndependent = 0,  // white noise: a hash per dimension
  kSobol = 1,        // Owen-scrambled, shuffled 2D Sobol per pair of dimensions (sobol.hpp)
};

}  // namespace tessera
