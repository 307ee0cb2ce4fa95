#include "light_list.hpp"

namespace tessera {

void add_if_sampled_emitter(std::vector<LightSource>& lights, const Material& material,
                            std::uint32_t primitive, float sampled_area) {
  if (material.emissive() && sampled_area > 0.0f)
    lights.push_back(LightSource{primitive, sampled_area});
}

}  // namespace tessera
