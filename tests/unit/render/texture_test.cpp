// Textures: lookups against texels worked out by hand (wrap modes, bilinear weights, the
// checker's squares), the mip pyramid against block means, uv densities against the shapes'
// geometry, and rendered albedo images whose every pixel has a known answer: a texture
// mapped texel for texel, and a fine checker image minified to the mean that trilinear
// filtering must give (and that nearest sampling, as a control, does not).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../../../core/render/texture_pool.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/render/surface_textures.hpp"

namespace tessera {
namespace {

TextureDesc image_texture(std::uint32_t w, std::uint32_t h, const std::vector<float>& grey) {
  TextureDesc t;
  t.name = "image";
  t.type = "image";
  t.image_width = w;
  t.image_height = h;
  for (float g : grey) t.image_pixels.insert(t.image_pixels.end(), {g, g, g});
  return t;
}

TEST(Texture, CheckerSquaresFollowUv) {
  TextureDesc d;
  d.type = "checker";
  d.scale = 4.0;
  d.color_a = glm::dvec3(1.0, 0.0, 0.0);
  d.color_b = glm::dvec3(0.0, 0.0, 1.0);
  const TexturePool pool = build_texture_pool({d});
  const Texture& t = pool.textures[0];
  const auto at = [&](float u, float v) { return evaluate_texture(t, nullptr, {u, v}, 0.0f); };
  EXPECT_EQ(at(0.1f, 0.1f), vec3(1, 0, 0));    // square (0, 0)
  EXPECT_EQ(at(0.3f, 0.1f), vec3(0, 0, 1));    // (1, 0)
  EXPECT_EQ(at(0.3f, 0.3f), vec3(1, 0, 0));    // (1, 1)
  EXPECT_EQ(at(-0.1f, 0.1f), vec3(0, 0, 1));   // (-1, 0): the pattern goes on
  EXPECT_EQ(at(-0.1f, -0.1f), vec3(1, 0, 0));  // (-1, -1)
  EXPECT_EQ(at(100.1f, 0.1f), vec3(1, 0, 0));  // (400, 0)
}

TEST(Texture, WrapModesAndBilinearWeights) {
  // 2 x 1 texels: left 0, right 1. Texel centres at u = 0.25 and 0.75.
  TextureDesc d = image_texture(2, 1, {0.0f, 1.0f});
  for (const char* wrap : {"repeat", "clamp", "mirror"}) {
    d.wrap = wrap;
    d.filter = "bilinear";
    const TexturePool pool = build_texture_pool({d});
    const Texture& t = pool.textures[0];
    const auto at = [&](float u) {
      return evaluate_texture(t, pool.texels.data(), {u, 0.5f}, 0.0f).x;
    };
    SCOPED_TRACE(wrap);
    EXPECT_FLOAT_EQ(at(0.25f), 0.0f);
    EXPECT_FLOAT_EQ(at(0.75f), 1.0f);
    EXPECT_FLOAT_EQ(at(0.5f), 0.5f);
    EXPECT_NEAR(at(0.375f), 0.25f, 1e-6f);
    const std::string mode = wrap;
    // Beyond the right edge's centre: repeat blends towards texel 0 again, clamp and mirror
    // hold texel 1 (mirror reflects texel 1 back first).
    EXPECT_NEAR(at(0.875f), mode == "repeat" ? 0.75f : 1.0f, 1e-6f);
    // u = 1.25: repeat is u = 0.25 (texel 0), clamp the right edge, mirror u = 0.75.
    EXPECT_NEAR(at(1.25f), mode == "repeat" ? 0.0f : 1.0f, 1e-6f);
    EXPECT_NEAR(at(-0.25f), mode == "repeat" ? 1.0f : 0.0f, 1e-6f);
  }
  d.filter = "nearest";
  d.wrap = "repeat";
  const TexturePool pool = build_texture_pool({d});
  EXPECT_EQ(evaluate_texture(pool.textures[0], pool.texels.data(), {0.49f, 0.5f}, 0.0f).x, 0.0f);
  EXPECT_EQ(evaluate_texture(pool.textures[0], pool.texels.data(), {0.51f, 0.5f}, 0.0f).x, 1.0f);
}

TEST(Texture, ImageRowsRunFromTheTopDown) {
  // 1 x 2: the first row (top, v near 1) is 1, the second 0.
  const TextureDesc d = [] {
    TextureDesc t = image_texture(1, 2, {1.0f, 0.0f});
    t.filter = "nearest";
    return t;
  }();
  const TexturePool pool = build_texture_pool({d});
  EXPECT_EQ(evaluate_texture(pool.textures[0], pool.texels.data(), {0.5f, 0.9f}, 0.0f).x, 1.0f);
  EXPECT_EQ(evaluate_texture(pool.textures[0], pool.texels.data(), {0.5f, 0.1f}, 0.0f).x, 0.0f);
}

TEST(Texture, MipLevelsAreBlockMeansDownToOneTexel) {
  // 4 x 4 texels 0..15: level 1 is the means of the 2 x 2 blocks, level 2 the mean of all.
  std::vector<float> values(16);
  for (int i = 0; i < 16; ++i) values[i] = static_cast<float>(i);
  const TexturePool pool = build_texture_pool({image_texture(4, 4, values)});
  const Texture& t = pool.textures[0];
  ASSERT_EQ(t.levels, 3u);
  const vec3* level1 = pool.texels.data() + t.level_offset[1];
  EXPECT_FLOAT_EQ(level1[0].x, (0 + 1 + 4 + 5) / 4.0f);
  EXPECT_FLOAT_EQ(level1[3].x, (10 + 11 + 14 + 15) / 4.0f);
  EXPECT_FLOAT_EQ(pool.texels[t.level_offset[2]].x, 7.5f);
  // Odd sizes: 3 x 1 folds the third column into the one block, so nothing is dropped.
  const TexturePool odd = build_texture_pool({image_texture(3, 1, {3.0f, 6.0f, 9.0f})});
  ASSERT_EQ(odd.textures[0].levels, 2u);
  EXPECT_FLOAT_EQ(odd.texels[odd.textures[0].level_offset[1]].x, 6.0f);
  // A footprint the size of the whole texture reads the 1 x 1 level; none reads level 0.
  EXPECT_FLOAT_EQ(evaluate_texture(t, pool.texels.data(), {0.1f, 0.9f}, 1.0f).x, 7.5f);
  EXPECT_FLOAT_EQ(evaluate_texture(t, pool.texels.data(), {0.125f, 0.875f}, 0.0f).x, 0.0f);
  // Halfway between levels 0 and 1 in log2 (a footprint of sqrt(2) texels): the mean of both.
  const float between =
      evaluate_texture(t, pool.texels.data(), {0.125f, 0.875f}, std::sqrt(2.0f) / 4.0f).x;
  const float level1_here = evaluate_texture(t, pool.texels.data(), {0.125f, 0.875f}, 0.5f).x;
  EXPECT_NEAR(between, 0.5f * (0.0f + level1_here), 1e-5f);
}

TEST(Texture, UvDensityFollowsTheShape) {
  SceneDescription scene;
  MaterialDesc plain_material;
  plain_material.name = "m";
  scene.materials.push_back(plain_material);
  QuadDesc quad;
  quad.u = glm::dvec3(2.0, 0.0, 0.0);
  quad.v = glm::dvec3(0.0, 0.0, 4.0);
  scene.quads.push_back(quad);
  SphereDesc sphere;
  sphere.center = glm::dvec3(10.0, 0.0, 0.0);
  sphere.radius = 3.0;
  scene.spheres.push_back(sphere);
  const auto prepared = PreparedScene::build(scene);
  const SceneView view = prepared->view();
  // The rectangle maps 8 units of area onto uv's unit square.
  const std::uint32_t quad_ref = make_primitive_ref(PrimitiveType::kQuad, 0);
  EXPECT_NEAR(uv_per_length(view, quad_ref, {0.5f, 0.5f}), 1.0f / std::sqrt(8.0f), 1e-6f);
  // At the sphere's equator (v = 1/2) u runs 2 pi r per unit, v pi r per unit.
  const std::uint32_t sphere_ref = make_primitive_ref(PrimitiveType::kSphere, 0);
  EXPECT_NEAR(uv_per_length(view, sphere_ref, {0.3f, 0.5f}),
              1.0f / std::sqrt(2.0f * kPi * kPi * 9.0f), 1e-6f);
}

// An orthographic camera that sees uv's unit square on a rectangle in z = 0, texel (x, y) of
// an n x n texture under pixel (x, y), through the albedo integrator.
SceneDescription texel_per_pixel_scene(std::uint32_t pixels, const TextureDesc& texture,
                                       std::uint32_t spp) {
  SceneDescription scene;
  scene.camera.position = glm::dvec3(0.5, 0.5, 1.0);
  scene.camera.look_at = glm::dvec3(0.5, 0.5, 0.0);
  scene.camera.projection = "orthographic";
  scene.camera.ortho_height = 1.0;
  scene.textures.push_back(texture);
  MaterialDesc m;
  m.name = "textured";
  m.albedo_texture = texture.name;
  scene.materials.push_back(m);
  QuadDesc quad;
  quad.u = glm::dvec3(1.0, 0.0, 0.0);
  quad.v = glm::dvec3(0.0, 1.0, 0.0);
  scene.quads.push_back(quad);
  scene.render.width = scene.render.height = pixels;
  scene.render.samples_per_pixel = spp;
  scene.render.tile_size = 16;
  scene.render.integrator = IntegratorKind::kAlbedo;
  return scene;
}

TEST(Texture, RendersTexelForTexel) {
  constexpr std::uint32_t n = 8;
  std::vector<float> values(n * n);
  for (std::uint32_t i = 0; i < n * n; ++i) values[i] = static_cast<float>(i) / (n * n);
  TextureDesc texture = image_texture(n, n, values);
  texture.filter = "nearest";
  const std::vector<float> image =
      render_image(*PreparedScene::build(texel_per_pixel_scene(n, texture, 4)));
  ASSERT_EQ(image.size(), std::size_t{n} * n * 4);
  for (std::uint32_t i = 0; i < n * n; ++i)
    ASSERT_NEAR(image[4 * i], values[i], 1e-6f) << "pixel " << i;
}

// A 256 x 256 texture of one-texel checks seen on 8 x 8 pixels, one sample each: every
// pixel covers 32 x 32 texels, so a filtered lookup gives their mean, 0.5. Point sampling
// (the control) gives 0 or 1: the aliasing mip mapping is for.
TEST(Texture, MinifiedTexturesAreFilteredByTheirMipmaps) {
  constexpr std::uint32_t texels = 256, pixels = 8;
  std::vector<float> checks(texels * texels);
  for (std::uint32_t y = 0; y < texels; ++y)
    for (std::uint32_t x = 0; x < texels; ++x) checks[y * texels + x] = ((x + y) & 1) ? 1.0f : 0.0f;
  TextureDesc texture = image_texture(texels, texels, checks);
  const std::vector<float> filtered =
      render_image(*PreparedScene::build(texel_per_pixel_scene(pixels, texture, 1)));
  for (std::uint32_t i = 0; i < pixels * pixels; ++i)
    EXPECT_NEAR(filtered[4 * i], 0.5f, 1e-4f) << "pixel " << i;
  texture.filter = "nearest";
  const std::vector<float> point =
      render_image(*PreparedScene::build(texel_per_pixel_scene(pixels, texture, 1)));
  int extremes = 0;
  for (std::uint32_t i = 0; i < pixels * pixels; ++i)
    extremes += point[4 * i] == 0.0f || point[4 * i] == 1.0f;
  EXPECT_EQ(extremes, static_cast<int>(pixels * pixels));
}

TEST(Texture, RoughnessTextureSetsTheAlphasAsTheMaterialMaps) {
  TextureDesc d;
  d.name = "rough";
  d.type = "checker";
  d.color_a = glm::dvec3(0.8);
  d.color_b = glm::dvec3(0.2);
  SceneDescription scene;
  scene.textures.push_back(d);
  MaterialDesc metal;
  metal.name = "metal";
  metal.type = MaterialType::kMetal;
  metal.roughness_texture = "rough";
  MaterialDesc glass;
  glass.name = "glass";
  glass.type = MaterialType::kGlass;
  glass.roughness_texture = "rough";
  glass.albedo = glm::dvec3(1.0);
  scene.materials = {metal, glass};
  scene.quads.push_back(QuadDesc{});
  const auto prepared = PreparedScene::build(scene);
  const SceneView view = prepared->view();
  SurfaceInteraction si;
  si.uv = vec2(0.5f, 0.5f);  // square (0, 0): color_a, roughness 0.8
  const std::uint32_t quad_ref = make_primitive_ref(PrimitiveType::kQuad, 0);
  MaterialScratch scratch;
  const Material& m = material_at(view, view.materials[0], quad_ref, si, 0.0f, scratch);
  EXPECT_FLOAT_EQ(m.alpha_x, 0.4f);  // metal: roughness / 2
  const Material& g = material_at(view, view.materials[1], quad_ref, si, 0.0f, scratch);
  EXPECT_FLOAT_EQ(g.alpha_x, 0.64f);  // glass: roughness^2
  si.uv = vec2(1.5f, 0.5f);           // square (1, 0): color_b
  EXPECT_FLOAT_EQ(material_at(view, view.materials[0], quad_ref, si, 0.0f, scratch).alpha_y, 0.1f);
  // Without a texture the material is used as it is, not copied.
  EXPECT_EQ(&material_at(view, view.materials[0], quad_ref, si, 0.0f, scratch) == &scratch.material,
            true);
  MaterialDesc plain = metal;
  plain.roughness_texture.clear();
  plain.roughness = 0.6;
  scene.materials = {plain};
  const auto untextured = PreparedScene::build(scene);
  const Material& own = untextured->view().materials[0];
  EXPECT_EQ(&material_at(untextured->view(), own, quad_ref, si, 0.0f, scratch), &own);
  EXPECT_FLOAT_EQ(own.alpha_x, 0.3f);
}

}  // namespace
}  // namespace tessera
