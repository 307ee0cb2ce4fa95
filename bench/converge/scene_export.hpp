#pragma once
#include <filesystem>
#include <string>

#include "tessera/scene/scene_description.hpp"

namespace tessera::bench {

// The scene as another renderer needs it to draw the same picture, as JSON (format
// "tessera-scene-export", version 1; bench/peers/cycles_render.py reads it):
//   camera, background, environment (what escaping rays see: "type" constant|gradient|
//   image, colour, intensity, rotation, and for an image the name of the EXR beside the
//   JSON holding its pixels), lights (point, spot, directional: the scene's fields),
//   render (width, height, max_depth, seed), materials (the scene's fields and what
//   make_material maps them to: "bsdf", the albedo and ior it uses; texture and pattern
//   names), textures (checker and image fields; an image's EXR name), shapes (one object
//   each: "type" sphere|quad|disk|plane|mesh|cylinder|cone|torus, its fields in object
//   space, "matrix" the 16 row-major numbers of its transform or null, "visible"); shape
//   types a peer cannot draw are listed as {"type": "unsupported", "kind": ...} so the
//   peer can say what it left out rather than silently rendering another scene.
// Meshes carry their positions, indices and normals inline: the peer then needs neither
// the mesh file nor its loader, and YAML triangles (which have no file) work the same way.
std::string scene_to_json(const SceneDescription& scene);
// Writes the JSON to `path`, and an image environment's and image textures' pixels beside
// it (kEnvironmentImageName, texture_image_name: float EXRs).
void write_scene_json(const SceneDescription& scene, const std::filesystem::path& path);
inline constexpr const char* kEnvironmentImageName = "environment.exr";
// The file an image texture's pixels (linear RGB, rows from v = 1 down) are written to,
// beside the JSON, by its index in SceneDescription::textures.
std::string texture_image_name(std::size_t index);

}  // namespace tessera::bench
