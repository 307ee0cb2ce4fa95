#pragma once
// Textures in render form: an image's mip pyramid in the scene's texel pool, or a procedural
// checker, looked up by uv. Plain data and TESSERA_HD functions, so the GPU path reads the
// same arrays (nothing calls OpenImageIO at shading time).
#include <cmath>
#include <cstdint>

#include "tessera/math/vec.hpp"

namespace tessera {

enum class TextureSource : std::uint32_t { kImage = 0, kChecker = 1 };
enum class TextureWrap : std::uint32_t { kRepeat = 0, kClamp = 1, kMirror = 2 };
enum class TextureFilter : std::uint32_t { kTrilinear = 0, kBilinear = 1, kNearest = 2 };

// 2^15 texels on a side gives 16 levels.
inline constexpr std::uint32_t kMaxTextureLevels = 16;

struct Texture {
  TextureSource source = TextureSource::kChecker;
  TextureWrap wrap = TextureWrap::kRepeat;
  TextureFilter filter = TextureFilter::kTrilinear;
  float scale = 1.0f;  // repeats per unit of uv
  vec3 color_a{0.9f}, color_b{0.1f};
  std::uint32_t width = 0, height = 0;  // level 0
  std::uint32_t levels = 0;
  // Where each level starts in the texel pool; level l is max(1, width >> l) by
  // max(1, height >> l), rows from the top (v = 1) down.
  std::uint32_t level_offset[kMaxTextureLevels] = {};

  TESSERA_HD std::uint32_t level_width(std::uint32_t level) const {
    const std::uint32_t w = width >> level;
    return w > 0 ? w : 1;
  }
  TESSERA_HD std::uint32_t level_height(std::uint32_t level) const {
    const std::uint32_t h = height >> level;
    return h > 0 ? h : 1;
  }
};

namespace texture_detail {

// An integer texel coordinate folded into [0, size) as the wrap mode says.
TESSERA_HD inline std::int32_t wrap_index(std::int32_t i, std::int32_t size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::kClamp:
      return i < 0 ? 0 : (i >= size ? size - 1 : i);
    case TextureWrap::kMirror: {
      const std::int32_t period = 2 * size;
      std::int32_t m = i % period;
      if (m < 0) m += period;
      return m < size ? m : period - 1 - m;
    }
    case TextureWrap::kRepeat:
      break;
  }
  std::int32_t m = i % size;
  return m < 0 ? m + size : m;
}

TESSERA_HD inline vec3 texel(const Texture& t, const vec3* pool, std::uint32_t level,
                             std::int32_t x, std::int32_t y) {
  const auto w = static_cast<std::int32_t>(t.level_width(level));
  const auto h = static_cast<std::int32_t>(t.level_height(level));
  x = wrap_index(x, w, t.wrap);
  y = wrap_index(y, h, t.wrap);
  return pool[t.level_offset[level] +
              static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(w) +
              static_cast<std::uint32_t>(x)];
}

// Texel coordinates of uv on `level`: x grows with u, y grows downwards (v = 1 is row 0),
// texel centres at half-integers. Very large uv are folded first so float keeps precision.
TESSERA_HD inline void texel_position(const Texture& t, std::uint32_t level, const vec2& uv,
                                      float& x, float& y) {
  float u = uv.x, v = uv.y;
  if (t.wrap == TextureWrap::kRepeat) {
    u -= std::floor(u);
    v -= std::floor(v);
  } else if (t.wrap == TextureWrap::kMirror) {
    u -= 2.0f * std::floor(0.5f * u);
    v -= 2.0f * std::floor(0.5f * v);
  } else {
    u = u < 0.0f ? 0.0f : (u > 1.0f ? 1.0f : u);
    v = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
  }
  x = u * static_cast<float>(t.level_width(level));
  y = (1.0f - v) * static_cast<float>(t.level_height(level));
}

TESSERA_HD inline vec3 nearest(const Texture& t, const vec3* pool, std::uint32_t level,
                               const vec2& uv) {
  float x, y;
  texel_position(t, level, uv, x, y);
  return texel(t, pool, level, static_cast<std::int32_t>(std::floor(x)),
               static_cast<std::int32_t>(std::floor(y)));
}

TESSERA_HD inline vec3 bilinear(const Texture& t, const vec3* pool, std::uint32_t level,
                                const vec2& uv) {
  float x, y;
  texel_position(t, level, uv, x, y);
  x -= 0.5f;
  y -= 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const auto x0 = static_cast<std::int32_t>(fx), y0 = static_cast<std::int32_t>(fy);
  return (1.0f - ay) * ((1.0f - ax) * texel(t, pool, level, x0, y0) +
                        ax * texel(t, pool, level, x0 + 1, y0)) +
         ay * ((1.0f - ax) * texel(t, pool, level, x0, y0 + 1) +
               ax * texel(t, pool, level, x0 + 1, y0 + 1));
}

}  // namespace texture_detail

// The texture's value at `uv`. `footprint` is the width, in uv units, of the area the
// lookup stands for (the ray's footprint on the surface); trilinear filtering picks the mip
// levels whose texels are that wide, and 0 reads the finest level. The checker is point
// sampled: the pixel's samples filter its edges.
TESSERA_HD inline vec3 evaluate_texture(const Texture& t, const vec3* pool, vec2 uv,
                                        float footprint) {
  uv *= t.scale;
  if (t.source == TextureSource::kChecker) {
    const auto parity =
        static_cast<std::int64_t>(std::floor(uv.x)) + static_cast<std::int64_t>(std::floor(uv.y));
    return (parity & 1) == 0 ? t.color_a : t.color_b;
  }
  if (t.filter == TextureFilter::kNearest) return texture_detail::nearest(t, pool, 0, uv);
  if (t.filter == TextureFilter::kBilinear || !(footprint > 0.0f))
    return texture_detail::bilinear(t, pool, 0, uv);
  const float texels =
      footprint * t.scale * static_cast<float>(t.width > t.height ? t.width : t.height);
  const float lod = texels > 1.0f ? std::log2(texels) : 0.0f;
  const float top = static_cast<float>(t.levels - 1);
  if (lod >= top) return texture_detail::bilinear(t, pool, t.levels - 1, uv);
  const auto fine = static_cast<std::uint32_t>(lod);
  const float blend = lod - static_cast<float>(fine);
  const vec3 a = texture_detail::bilinear(t, pool, fine, uv);
  if (blend <= 0.0f) return a;
  return (1.0f - blend) * a + blend * texture_detail::bilinear(t, pool, fine + 1, uv);
}

// The mean of a texel's channels, clamped to [0, 1]: a roughness from any texture.
TESSERA_HD inline float texture_scalar(const vec3& value) {
  const float mean = (value.x + value.y + value.z) * (1.0f / 3.0f);
  return mean < 0.0f ? 0.0f : (mean > 1.0f ? 1.0f : mean);
}

}  // namespace tessera
