#pragma once
// Materials the render tests' hand-built scenes share: a named lambertian and a named
// emitter, so each scene states only what differs (name, albedo, emission).
#include <string>
#include <utility>

#include "tessera/scene/scene_description.hpp"

namespace tessera::test {

inline MaterialDesc lambertian_material(std::string name, glm::dvec3 albedo = glm::dvec3(0.8)) {
  MaterialDesc material;
  material.name = std::move(name);
  material.albedo = albedo;
  return material;
}

inline MaterialDesc light_material(std::string name, glm::dvec3 emission) {
  MaterialDesc material;
  material.name = std::move(name);
  material.type = MaterialType::kLight;
  material.emission = emission;
  return material;
}

}  // namespace tessera::test
