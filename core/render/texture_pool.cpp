#include "texture_pool.hpp"

#include <algorithm>
#include <string_view>
#include <unordered_map>

namespace tessera {
namespace {

TextureWrap wrap_of(const std::string& name) {
  if (name == "clamp") return TextureWrap::kClamp;
  if (name == "mirror") return TextureWrap::kMirror;
  return TextureWrap::kRepeat;
}

TextureFilter filter_of(const std::string& name) {
  if (name == "bilinear") return TextureFilter::kBilinear;
  if (name == "nearest") return TextureFilter::kNearest;
  return TextureFilter::kTrilinear;
}

// The next level down from `fine` (w x h): each texel the mean of the 2x2 block under it;
// with an odd size the last block takes three rows or columns, so every texel counts.
std::vector<vec3> downsample(const std::vector<vec3>& fine, std::uint32_t w, std::uint32_t h,
                             std::uint32_t cw, std::uint32_t ch) {
  std::vector<vec3> coarse(std::size_t{cw} * ch);
  for (std::uint32_t y = 0; y < ch; ++y) {
    const std::uint32_t y0 = std::min(2 * y, h - 1);
    const std::uint32_t y1 = (y + 1 == ch) ? h : std::min(2 * y + 2, h);
    for (std::uint32_t x = 0; x < cw; ++x) {
      const std::uint32_t x0 = std::min(2 * x, w - 1);
      const std::uint32_t x1 = (x + 1 == cw) ? w : std::min(2 * x + 2, w);
      vec3 sum(0.0f);
      for (std::uint32_t yy = y0; yy < std::max(y1, y0 + 1); ++yy)
        for (std::uint32_t xx = x0; xx < std::max(x1, x0 + 1); ++xx)
          sum += fine[std::size_t{yy} * w + xx];
      const auto count =
          static_cast<float>((std::max(y1, y0 + 1) - y0) * (std::max(x1, x0 + 1) - x0));
      coarse[std::size_t{y} * cw + x] = sum / count;
    }
  }
  return coarse;
}

}  // namespace

TexturePool build_texture_pool(const std::vector<TextureDesc>& descriptions) {
  TexturePool pool;
  pool.textures.reserve(descriptions.size());
  for (const TextureDesc& d : descriptions) {
    Texture& t = pool.textures.emplace_back();
    t.source = d.type == "image" ? TextureSource::kImage : TextureSource::kChecker;
    t.wrap = wrap_of(d.wrap);
    t.filter = filter_of(d.filter);
    t.scale = static_cast<float>(d.scale);
    t.color_a = vec3(d.color_a);
    t.color_b = vec3(d.color_b);
    if (t.source != TextureSource::kImage) continue;
    t.width = d.image_width;
    t.height = d.image_height;
    std::vector<vec3> level(std::size_t{t.width} * t.height);
    for (std::size_t i = 0; i < level.size(); ++i)
      level[i] = vec3(d.image_pixels[3 * i], d.image_pixels[3 * i + 1], d.image_pixels[3 * i + 2]);
    for (std::uint32_t l = 0;; ++l) {
      t.level_offset[l] = static_cast<std::uint32_t>(pool.texels.size());
      pool.texels.insert(pool.texels.end(), level.begin(), level.end());
      t.levels = l + 1;
      const std::uint32_t w = t.level_width(l), h = t.level_height(l);
      if ((w == 1 && h == 1) || t.levels == kMaxTextureLevels) break;
      level = downsample(level, w, h, t.level_width(l + 1), t.level_height(l + 1));
    }
  }
  return pool;
}

void bind_material_textures(const std::vector<MaterialDesc>& descriptions,
                            const std::vector<TextureDesc>& textures,
                            std::vector<Material>& materials) {
  std::unordered_map<std::string_view, std::int32_t> index;
  for (std::size_t i = 0; i < textures.size(); ++i)
    index.emplace(textures[i].name, static_cast<std::int32_t>(i));
  const auto find = [&](const std::string& name) {
    const auto found = index.find(name);
    return found == index.end() ? -1 : found->second;
  };
  for (std::size_t i = 0; i < descriptions.size() && i < materials.size(); ++i) {
    materials[i].albedo_texture = find(descriptions[i].albedo_texture);
    materials[i].roughness_texture = find(descriptions[i].roughness_texture);
  }
}

}  // namespace tessera
