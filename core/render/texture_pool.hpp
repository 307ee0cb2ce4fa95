#pragma once
// Textures in render form: every texture's mip pyramid back to back in one texel pool
// (tessera/render/texture.hpp reads it), and the materials pointed at them by index.
#include <vector>

#include "tessera/render/material.hpp"
#include "tessera/render/texture.hpp"
#include "tessera/scene/scene_description.hpp"

namespace tessera {

struct TexturePool {
  std::vector<Texture> textures;  // in SceneDescription::textures order
  std::vector<vec3> texels;
};

// Builds each image's pyramid by 2x2 box filtering down to 1x1 (a level of odd size folds
// its last row or column into the one before, so no texel is dropped). The descriptions
// must be valid (validate_scene checks them).
TexturePool build_texture_pool(const std::vector<TextureDesc>& descriptions);

// Sets each material's albedo_texture and roughness_texture from the names its
// description gives. `materials` is indexed like `descriptions`.
void bind_material_textures(const std::vector<MaterialDesc>& descriptions,
                            const std::vector<TextureDesc>& textures,
                            std::vector<Material>& materials);

}  // namespace tessera
