#pragma once
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/schema/checks.hpp"
#include "tessera/scene/schema/field.hpp"

// Every kind of the scene model, declared once: its names in YAML and protobuf, its fields
// (name, member, presence, rule, documentation) and the rules that tie fields together.
// Defaults are the description structs' member initialisers (scene_description.hpp).
//
// To add a field: give the struct a member, add a Field line here and the field (same
// name) to scene.proto. The YAML loader, both protobuf directions, validation and the
// README tables follow; schema_test checks the proto and the README agree.
// To add a shape: a description struct and its list in SceneDescription, a kind here, its
// entry in ShapeKinds, its message in scene.proto's Geometry oneof, and the renderer's
// arrays (render/).
namespace tessera::schema {

using enum Presence;
using enum Rule;

// ---------------------------------------------------------------- camera, background, render

struct CameraKind {
  using Desc = CameraDesc;
  static constexpr std::string_view yaml_section = "camera";
  static constexpr std::string_view proto_section = "camera";
  static constexpr Field<Desc> fields[] = {
      {.name = "position", .member = &Desc::position, .doc = "eye point"},
      {.name = "look_at", .member = &Desc::look_at, .doc = "point the camera looks at"},
      {.name = "up", .member = &Desc::up, .doc = "up direction"},
      {.name = "fov_degrees",
       .member = &Desc::fov_degrees,
       .rule = kInRange,
       .lo = 1e-3,
       .hi = 179.0,
       .doc = "vertical field of view, degrees",
       .yaml_name = "fov",
       .zero_means_default = true},
      {.name = "projection",
       .member = &Desc::projection,
       .rule = kOneOf,
       .doc = "perspective (default) or orthographic (parallel rays)",
       .choices = "perspective|orthographic"},
      {.name = "ortho_height",
       .member = &Desc::ortho_height,
       .rule = kNonNegative,
       .doc = "orthographic: image height, world units (0: the perspective view's at look_at)"},
      {.name = "aperture_radius",
       .member = &Desc::aperture_radius,
       .rule = kNonNegative,
       .doc = "thin lens radius, world units (0: pinhole, all sharp)"},
      {.name = "focus_distance",
       .member = &Desc::focus_distance,
       .rule = kNonNegative,
       .doc = "distance of the sharp plane along the view (0: through look_at)"},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
  static void check(const Desc& camera, Checks& check) {
    if (glm::length(camera.look_at - camera.position) == 0.0)
      check.fail("look_at", "must differ from camera.position");
    else if (glm::length(glm::cross(camera.look_at - camera.position, camera.up)) == 0.0)
      check.fail("up", "must not be parallel to the viewing direction");
    if (camera.projection == "orthographic" && camera.aperture_radius > 0.0)
      check.fail("aperture_radius",
                 "must be 0 for an orthographic camera (depth of field needs perspective)");
  }
};

// YAML keeps RayON's layout (`settings.background_color`); protobuf has a Background message.
struct BackgroundKind {
  using Desc = BackgroundDesc;
  static constexpr std::string_view yaml_section = "settings";
  static constexpr std::string_view proto_section = "background";
  static constexpr Field<Desc> fields[] = {
      {.name = "color",
       .member = &Desc::color,
       .rule = kNonNegativeComponents,
       .doc = "radiance of a miss, linear RGB (times intensity)",
       .grey_scalar = true,
       .yaml_name = "background_color"},
      {.name = "intensity",
       .member = &Desc::intensity,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1e6,
       .doc = "multiplies color",
       .yaml_name = "background_intensity"},
  };
  static constexpr IgnoredKey ignored[] = {
      {"ambient_light", "RayON's ambient term is not supported (light comes from emitters)"},
      {"use_bvh", "Tessera always picks its own acceleration structure"},
      {"adaptive_sampling", "set render.target_error for adaptive sampling"},
  };
  static void check(const Desc&, Checks&) {}
};

// An image travelling as pixels (environment, texture): a size, 3 floats per pixel, each
// finite and >= 0. A YAML scene read them from `file`, so its errors name that field.
inline void check_image_pixels(std::uint32_t width, std::uint32_t height,
                               const std::vector<float>& rgb, const char* missing, Checks& check) {
  const std::size_t pixels = std::size_t{width} * height;
  if (pixels == 0) {
    check.fail(check.yaml() ? "file" : "image_width", missing);
  } else if (rgb.size() != 3 * pixels) {
    check.fail(check.yaml() ? "file" : "image_pixels", "must hold 3 floats per pixel (" +
                                                           std::to_string(3 * pixels) + "), got " +
                                                           std::to_string(rgb.size()));
  } else {
    for (std::size_t i = 0; i < rgb.size(); ++i)
      if (!(rgb[i] >= 0.0f) || !std::isfinite(rgb[i])) {
        check.fail(check.yaml() ? "file" : "image_pixels",
                   "pixel values must be finite and >= 0, got " + Checks::format(rgb[i]) + " at " +
                       std::to_string(i));
        break;
      }
  }
}

// The environment (YAML and protobuf `environment`); when given it replaces the background.
// RayON's `settings` block becomes a gradient environment of its background_intensity (RayON
// draws that sky and ignores background_color), unless the scene gives `environment`.
struct EnvironmentKind {
  using Desc = EnvironmentDesc;
  static constexpr std::string_view yaml_section = "environment";
  static constexpr std::string_view proto_section = "environment";
  static constexpr Field<Desc> fields[] = {
      {.name = "type",
       .member = &Desc::type,
       .rule = kOneOf,
       .doc = "constant, gradient (RayON's sky: white below to (0.5, 0.7, 1.0) above) or image "
              "(equirectangular)",
       .choices = "constant|gradient|image"},
      {.name = "color",
       .member = &Desc::color,
       .rule = kNonNegativeComponents,
       .doc = "constant: radiance, linear RGB (times intensity)",
       .grey_scalar = true},
      {.name = "intensity",
       .member = &Desc::intensity,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1e6,
       .doc = "multiplies the environment"},
      {.name = "file",
       .member = &Desc::file,
       .doc = "image: HDR/EXR file, read where mesh files may be",
       .side = Side::kYaml},
      {.name = "rotation_degrees",
       .member = &Desc::rotation_degrees,
       .doc = "image: turned about +y, degrees"},
      {.name = "image_width",
       .member = &Desc::image_width,
       .doc = "image: pixels",
       .side = Side::kProto},
      {.name = "image_height",
       .member = &Desc::image_height,
       .doc = "image: pixels",
       .side = Side::kProto},
      {.name = "image_pixels",
       .doc = "image: linear RGB floats, rows from the zenith down",
       .side = Side::kProto},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
  static void check(const Desc& env, Checks& check) {
    if (env.type == "image")
      check_image_pixels(env.image_width, env.image_height, env.image_pixels,
                         "an image environment needs an image", check);
  }
};

// One entry of the top-level `lights` list (protobuf `Scene.lights`): lights that are not
// shapes. Fields that do not apply to the type are not used.
struct LightKind {
  using Desc = LightDesc;
  static constexpr std::string_view yaml_section = "lights[i]";
  static constexpr std::string_view proto_section = "lights[i]";
  static constexpr Field<Desc> fields[] = {
      {.name = "type",
       .member = &Desc::type,
       .presence = kRequired,
       .rule = kOneOf,
       .doc = "point, spot, directional (alias sun)",
       .choices = "point|spot|directional|sun"},
      {.name = "position", .member = &Desc::position, .doc = "point, spot: where the light is"},
      {.name = "direction",
       .member = &Desc::direction,
       .rule = kNonZeroVector,
       .doc = "spot: the axis it shines along; directional: the way its light travels"},
      {.name = "color",
       .member = &Desc::color,
       .rule = kNonNegativeComponents,
       .doc = "linear RGB, multiplies intensity or irradiance",
       .grey_scalar = true},
      {.name = "intensity",
       .member = &Desc::intensity,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1e12,
       .doc = "point, spot: radiant intensity, W/sr"},
      {.name = "irradiance",
       .member = &Desc::irradiance,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1e12,
       .doc = "directional: W/m^2 on a surface facing it"},
      {.name = "cone_angle_degrees",
       .member = &Desc::cone_angle_degrees,
       .rule = kInRange,
       .lo = 1e-3,
       .hi = 180.0,
       .doc = "spot: half-angle of the cone, where the light ends"},
      {.name = "cone_falloff_degrees",
       .member = &Desc::cone_falloff_degrees,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 180.0,
       .doc = "spot: width of the smooth edge inside the cone (smoothstep in cos)"},
      {.name = "angular_radius_degrees",
       .member = &Desc::angular_radius_degrees,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 90.0,
       .doc = "directional: 0 is a delta direction; the sun is about 0.27"},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
  static void check(const Desc& light, Checks& check) {
    if (light.type.empty()) check.fail("type", "must be set: point, spot, directional or sun");
    if (light.type == "spot" && light.cone_falloff_degrees > light.cone_angle_degrees)
      check.fail("cone_falloff_degrees", "must not exceed cone_angle_degrees (" +
                                             Checks::format(light.cone_angle_degrees) + "), got " +
                                             Checks::format(light.cone_falloff_degrees));
  }
};

// The render section (YAML `render`, protobuf RenderSettings, which travels beside the
// Scene as `settings`). The width, height, spp, depth and tile-size bounds come from
// SceneLimits (a server configures them), so their checks are the kind's own rules.
struct RenderKind {
  using Desc = RenderSettings;
  static constexpr std::string_view yaml_section = "render";
  static constexpr std::string_view proto_section = "settings";
  static constexpr Field<Desc> fields[] = {
      {.name = "width",
       .member = &Desc::width,
       .doc = "pixels (at most 16384 unless the server sets another limit)",
       .zero_means_default = true},
      {.name = "height", .member = &Desc::height, .doc = "pixels", .zero_means_default = true},
      {.name = "samples_per_pixel",
       .member = &Desc::samples_per_pixel,
       .doc = "samples per pixel",
       .yaml_name = "spp",
       .zero_means_default = true},
      {.name = "max_depth",
       .member = &Desc::max_depth,
       .doc = "longest path, in bounces",
       .zero_means_default = true},
      {.name = "tile_size",
       .member = &Desc::tile_size,
       .doc = "tile edge, pixels",
       .zero_means_default = true},
      {.name = "seed", .doc = "random seed (the image is a function of it)"},
      {.name = "integrator", .doc = "path, normals, shadow, transparency, albedo, depth or phong"},
      {.name = "aovs",
       .doc = "extra outputs: albedo, normal, depth, primitive_id, variance, sample_count"},
      {.name = "sampler", .doc = "sobol (default) or independent"},
      {.name = "light_strategy", .doc = "direct light: mis (default), light or bsdf"},
      {.name = "device", .doc = "where a daemon renders the job: any (default), cpu or gpu"},
      {.name = "transparent_background",
       .member = &Desc::transparent_background,
       .doc = "camera rays that miss leave RGB and alpha 0 (the background still lights the "
              "scene)"},
      {.name = "clamp",
       .member = &Desc::clamp,
       .rule = kNonNegative,
       .doc = "largest colour component one indirect light contribution of a sample may add; "
              "0 = off"},
      {.name = "pixel_filter",
       .member = &Desc::pixel_filter,
       .rule = kOneOf,
       .doc = "box (default), gaussian or blackman_harris, by filter importance sampling",
       .choices = "box|gaussian|blackman_harris"},
      {.name = "filter_width",
       .member = &Desc::filter_width,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 16.0,
       .doc = "pixel filter's full width, pixels (0: box 1, gaussian 3 with sigma = width / 6, "
              "blackman_harris 3)"},
      {.name = "target_error",
       .member = &Desc::target_error,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1.0,
       .doc = "adaptive sampling: a pixel stops once the relative standard error of its mean "
              "is below this (0: off; spp is then the most a pixel takes)"},
      {.name = "min_samples_per_pixel",
       .member = &Desc::min_samples_per_pixel,
       .doc = "adaptive sampling: samples every pixel takes before it may stop",
       .yaml_name = "min_spp",
       .zero_means_default = true},
      {.name = "passes",
       .member = &Desc::passes,
       .doc = "progressive passes: the daemon delivers every tile after each pass, the last "
              "equal bit for bit to one pass (0 or 1: one pass; at most spp; not with "
              "target_error)",
       .zero_means_default = true},
      {.name = "accel_builder",
       .member = &Desc::accel_builder,
       .rule = kOneOf,
       .doc = "triangle structure: auto (default; chosen per mesh), spatial (spatial splits "
              "for every mesh) or binned (shortest build, for previews); never changes the "
              "image",
       .choices = "auto|spatial|binned"},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
};

// One entry of the top-level `textures` list (protobuf `Scene.textures`): images and
// procedural checkers that materials name for their albedo or roughness.
struct TextureKind {
  using Desc = TextureDesc;
  static constexpr std::string_view yaml_section = "textures[i]";
  static constexpr std::string_view proto_section = "textures[i]";
  static constexpr Field<Desc> fields[] = {
      {.name = "name",
       .member = &Desc::name,
       .presence = kRequired,
       .doc = "unique; materials refer to it"},
      {.name = "type",
       .member = &Desc::type,
       .presence = kRequired,
       .rule = kOneOf,
       .doc = "image or checker",
       .choices = "image|checker"},
      {.name = "file",
       .member = &Desc::file,
       .doc = "image: any format OpenImageIO reads, read where mesh files may be",
       .side = Side::kYaml},
      {.name = "color_space",
       .member = &Desc::color_space,
       .rule = kOneOf,
       .doc = "image file: srgb, linear, or auto (8- and 16-bit files sRGB, float linear)",
       .choices = "auto|srgb|linear"},
      {.name = "wrap",
       .member = &Desc::wrap,
       .rule = kOneOf,
       .doc = "outside [0, 1]: repeat, clamp or mirror",
       .choices = "repeat|clamp|mirror"},
      {.name = "filter",
       .member = &Desc::filter,
       .rule = kOneOf,
       .doc = "image: trilinear (mipmapped, level from the ray footprint), bilinear or nearest",
       .choices = "trilinear|bilinear|nearest"},
      {.name = "scale",
       .member = &Desc::scale,
       .rule = kInRange,
       .lo = 1e-6,
       .hi = 1e6,
       .doc = "repeats per unit of uv (checker: squares per unit)"},
      {.name = "color_a",
       .member = &Desc::color_a,
       .rule = kNonNegativeComponents,
       .doc = "checker: the square at uv (0, 0), linear RGB",
       .grey_scalar = true},
      {.name = "color_b",
       .member = &Desc::color_b,
       .rule = kNonNegativeComponents,
       .doc = "checker: the other squares",
       .grey_scalar = true},
      {.name = "image_width",
       .member = &Desc::image_width,
       .doc = "image: pixels",
       .side = Side::kProto},
      {.name = "image_height",
       .member = &Desc::image_height,
       .doc = "image: pixels",
       .side = Side::kProto},
      {.name = "image_pixels",
       .doc = "image: linear RGB floats, rows from the top (v = 1) down",
       .side = Side::kProto},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
  static void check(const Desc& texture, Checks& check) {
    if (texture.type == "image")
      check_image_pixels(texture.image_width, texture.image_height, texture.image_pixels,
                         "an image texture needs an image", check);
  }
};

// ---------------------------------------------------------------- materials

// A material's `pattern` sub-block.
struct PatternKind {
  using Desc = PatternDesc;
  static constexpr Field<Desc> fields[] = {
      {.name = "type",
       .member = &Desc::type,
       .presence = kRequired,
       .rule = kOneOf,
       .doc = "checkerboard and stripes draw the plain albedo, as in RayON",
       .choices = "fibonacci_dots|checkerboard|stripes"},
      {.name = "color",
       .member = &Desc::color,
       .rule = kNonNegativeComponents,
       .doc = "the dots' colour",
       .grey_scalar = true},
      {.name = "dot_count",
       .member = &Desc::dot_count,
       .doc = "fibonacci_dots: dots on the sphere, 1 to 10000"},
      {.name = "dot_radius",
       .member = &Desc::dot_radius,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 3.14159265358979323846,
       .doc = "fibonacci_dots: angular radius, radians"},
  };
  // Every shading point tests every dot, so the count is bounded.
  static constexpr std::uint32_t kMaxDots = 10000;
  static void check(const Desc& pattern, Checks& check) {
    if (pattern.type == "fibonacci_dots" && (pattern.dot_count < 1 || pattern.dot_count > kMaxDots))
      check.fail("dot_count", "must be in [1, " + std::to_string(kMaxDots) +
                                  "] for fibonacci_dots, got " + std::to_string(pattern.dot_count));
  }
};

struct MaterialKind {
  using Desc = MaterialDesc;
  static constexpr Field<Desc> fields[] = {
      {.name = "name",
       .member = &Desc::name,
       .presence = kRequired,
       .doc = "unique; geometry refers to it"},
      {.name = "type",
       .presence = kRequired,
       .doc = "lambertian, light, metal, rough_mirror, glass (alias dielectric), "
              "anisotropic_metal, clear_coat, thin_film, mirror, constant (unlit albedo), "
              "show_normals (the normal as a colour)"},
      {.name = "albedo",
       .member = &Desc::albedo,
       .rule = kNonNegativeComponents,
       .doc = "reflectance, linear RGB (lights, glass, anisotropic_metal: 1); glass: the "
              "tint of light entering it",
       .grey_scalar = true},
      {.name = "emission",
       .member = &Desc::emission,
       .rule = kNonNegativeComponents,
       .doc = "emitted radiance (required for lights)",
       .grey_scalar = true},
      {.name = "roughness",
       .member = &Desc::roughness,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1.0,
       .doc = "GGX alpha = roughness / 2 (metal, rough_mirror, clear_coat), roughness^2 "
              "(anisotropic_metal, glass); 0: mirror, smooth glass"},
      {.name = "refractive_index",
       .member = &Desc::refractive_index,
       .rule = kInRange,
       .lo = 1.0,
       .hi = 4.0,
       .doc = "glass, clear_coat; thin_film: the medium around the film (thin_film: 1)"},
      // RayON reads metallic and transmission but none of its renderers (CUDA, OptiX, CPU)
      // uses them: its look comes from the type alone.
      {.name = "metallic",
       .member = &Desc::metallic,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1.0,
       .doc = "read, not rendered (RayON's renderers ignore it too)"},
      {.name = "transmission",
       .member = &Desc::transmission,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1.0,
       .doc = "the transparency view's opacity is 1 - transmission; the path tracer, like "
              "RayON, ignores it"},
      {.name = "anisotropy",
       .member = &Desc::anisotropy,
       .rule = kInRange,
       .lo = -1.0,
       .hi = 1.0,
       .doc = "conductors: alpha / a along the tangent cross(+y, n), alpha * a across, "
              "a = sqrt(1 - 0.9 anisotropy)"},
      {.name = "preset",
       .member = &Desc::preset,
       .rule = kOneOf,
       .doc = "conductors: measured eta and k of this metal",
       .choices = "silver|gold|copper|aluminium|aluminum|chromium"},
      {.name = "eta",
       .member = &Desc::eta,
       .rule = kNonNegativeComponents,
       .doc = "conductors: real part of the complex index per RGB (with k; 0: unset)"},
      {.name = "k",
       .member = &Desc::k,
       .rule = kNonNegativeComponents,
       .doc = "conductors: extinction coefficient per RGB (with eta)"},
      {.name = "transmittance",
       .member = &Desc::transmittance,
       .rule = kNonNegativeComponents,
       .doc = "glass: share of light left after transmittance_distance inside (Beer's law), "
              "each in (0, 1]",
       .grey_scalar = true},
      {.name = "transmittance_distance",
       .member = &Desc::transmittance_distance,
       .rule = kPositive,
       .doc = "glass: the distance transmittance is measured over, scene units"},
      {.name = "film_thickness",
       .member = &Desc::film_thickness,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 1e5,
       .doc = "thin_film, nanometres (thin_film: 400)"},
      {.name = "film_ior",
       .member = &Desc::film_ior,
       .rule = kInRange,
       .lo = 1.0,
       .hi = 4.0,
       .doc = "thin_film"},
      {.name = "color",
       .member = &Desc::color,
       .rule = kNonNegativeComponents,
       .doc = "with emission_intensity: emission = color * emission_intensity",
       .grey_scalar = true},
      {.name = "emission_intensity",
       .member = &Desc::emission_intensity,
       .rule = kNonNegative,
       .doc = "scales color into emission; not with emission"},
      {.name = "pattern", .doc = "{ type, color, dot_count, dot_radius }: see below"},
      {.name = "albedo_texture",
       .member = &Desc::albedo_texture,
       .doc = "a texture's name: gives the albedo at each hit (replaces albedo)"},
      {.name = "roughness_texture",
       .member = &Desc::roughness_texture,
       .doc = "a texture's name: the mean of its RGB, clamped to [0, 1], is the roughness at "
              "each hit (replaces roughness)"},
  };
  static constexpr std::array<IgnoredKey, 0> ignored{};
  // A light without emission would be black: RayON requires it too. The shorthand and
  // `emission` together would be ambiguous (RayON silently drops `emission`).
  static void check(const Desc& material, Checks& check) {
    if (material.emission_intensity > 0.0 && material.emission != glm::dvec3(0.0))
      check.fail("emission_intensity",
                 "cannot be combined with emission: write emission, or color and "
                 "emission_intensity");
    else if (material.type == MaterialType::kLight &&
             material.emitted_radiance() == glm::dvec3(0.0))
      check.fail("emission",
                 "is required for a light material (and must not be zero): write emission, or "
                 "color and emission_intensity");
    // A complex index needs its real part: eta = 0 reflects everything whatever k says.
    const bool has_eta = material.eta != glm::dvec3(0.0);
    if (material.k != glm::dvec3(0.0) && !has_eta)
      check.fail("eta", "is required with k (the complex index is eta + i k)");
    if (has_eta && (material.eta.x <= 0.0 || material.eta.y <= 0.0 || material.eta.z <= 0.0))
      check.fail("eta", "must be > 0 in every channel");
    const glm::dvec3& t = material.transmittance;
    if (!(t.x > 0.0 && t.y > 0.0 && t.z > 0.0 && t.x <= 1.0 && t.y <= 1.0 && t.z <= 1.0))
      check.fail("transmittance", "must be in (0, 1] in every channel");
    if (has_eta && !material.preset.empty())
      check.fail("preset", "cannot be combined with eta and k (both give the metal's index)");
  }
};

// ---------------------------------------------------------------- placement

struct RotationKind {
  using Desc = TransformDesc;
  static constexpr Field<Desc> fields[] = {
      {.name = "axis",
       .member = &Desc::rotate_axis,
       .presence = kRequired,
       .rule = kNonZeroVector,
       .doc = "right-handed rotation axis"},
      {.name = "degrees", .member = &Desc::rotate_degrees, .presence = kRequired, .doc = "angle"},
  };
};

struct TransformKind {
  using Desc = TransformDesc;
  static constexpr Field<Desc> fields[] = {
      {
          .name = "translate",
          .member = &Desc::translate,
      },
      {.name = "rotate", .doc = "{ axis, degrees }"},
      {.name = "scale",
       .member = &Desc::scale,
       .rule = kNonZeroComponents,
       .doc = "one number or three",
       .grey_scalar = true},
  };
};

// ---------------------------------------------------------------- shapes

// Fields of the Geometry entry itself, whatever its shape.
struct GeometryCommon {
  static constexpr std::string_view fields[] = {"type", "material", "visible", "transform"};
};

struct SphereKind {
  using Desc = SphereDesc;
  static constexpr std::string_view name = "sphere";
  static constexpr std::string_view proto_name = "sphere";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::spheres;
  static constexpr Field<Desc> fields[] = {
      {.name = "center", .member = &Desc::center, .presence = kRequired},
      {.name = "radius", .member = &Desc::radius, .presence = kRequired, .rule = kPositive},
  };
  static void check(const Desc&, Checks&) {}
};

struct DisplacedSphereKind {
  using Desc = DisplacedSphereDesc;
  static constexpr std::string_view name = "displaced_sphere";
  static constexpr std::string_view proto_name = "displaced_sphere";
  static constexpr std::string_view note =
      "RayON's golf ball: a sphere shaded with 150 dimples (the silhouette stays round)";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::displaced_spheres;
  static constexpr Field<Desc> fields[] = {
      {.name = "center", .member = &Desc::center, .presence = kRequired},
      {.name = "radius", .member = &Desc::radius, .rule = kPositive},
      {.name = "displacement_scale",
       .member = &Desc::displacement_scale,
       .rule = kInRange,
       .lo = 0.0,
       .hi = 10.0,
       .doc = "how far the dimples tilt the shading normal; 0: a plain sphere"},
      {.name = "pattern_type",
       .member = &Desc::pattern_type,
       .doc = "0: golf-ball dimples (RayON's only pattern)"},
  };
  static void check(const Desc& sphere, Checks& check) {
    if (sphere.pattern_type != 0)
      check.fail("pattern_type",
                 "must be 0 (golf-ball dimples), got " + std::to_string(sphere.pattern_type));
  }
};

struct QuadKind {
  using Desc = QuadDesc;
  static constexpr std::string_view name = "rectangle";
  static constexpr std::string_view proto_name = "rectangle";
  static constexpr std::string_view note = "the parallelogram corner + s·u + t·v";
  static constexpr std::array<Alias, 1> aliases{{{"quad"}}};
  static constexpr auto list = &SceneDescription::quads;
  static constexpr Field<Desc> fields[] = {
      {.name = "corner", .member = &Desc::corner, .presence = kRequired},
      {.name = "u", .member = &Desc::u, .presence = kRequired},
      {.name = "v", .member = &Desc::v, .presence = kRequired},
  };
  static void check(const Desc& q, Checks& check) {
    if (glm::length(glm::cross(q.u, q.v)) == 0.0)
      check.fail("v", "u and v must span a parallelogram (they are parallel or zero)");
  }
};

struct PlaneKind {
  using Desc = PlaneDesc;
  static constexpr std::string_view name = "plane";
  static constexpr std::string_view proto_name = "plane";
  static constexpr std::string_view note = "infinite; may not emit light";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::planes;
  static constexpr bool may_emit = false;  // its power would be infinite
  static constexpr Field<Desc> fields[] = {
      {
          .name = "point",
          .member = &Desc::point,
      },
      {.name = "normal", .member = &Desc::normal, .presence = kRequired, .rule = kNonZeroVector},
  };
  static void check(const Desc&, Checks&) {}
};

struct DiskKind {
  using Desc = DiskDesc;
  static constexpr std::string_view name = "disk";
  static constexpr std::string_view proto_name = "disk";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::disks;
  static constexpr Field<Desc> fields[] = {
      {.name = "center", .member = &Desc::center, .presence = kRequired},
      {.name = "normal", .member = &Desc::normal, .presence = kRequired, .rule = kNonZeroVector},
      {.name = "radius", .member = &Desc::radius, .presence = kRequired, .rule = kPositive},
      {.name = "inner_radius", .member = &Desc::inner_radius, .doc = "an annulus when > 0"},
  };
  static void check(const Desc& d, Checks& check) {
    if (d.radius > 0.0 && !(d.inner_radius >= 0.0 && d.inner_radius < d.radius))
      check.fail("inner_radius", "must be in [0, radius) = [0, " + Checks::format(d.radius) +
                                     "), got " + Checks::format(d.inner_radius));
  }
};

struct CylinderKind {
  using Desc = CylinderDesc;
  static constexpr std::string_view name = "cylinder";
  static constexpr std::string_view proto_name = "cylinder";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::cylinders;
  static constexpr Field<Desc> fields[] = {
      {.name = "base", .member = &Desc::base, .presence = kRequired},
      {
          .name = "axis",
          .member = &Desc::axis,
          .rule = kNonZeroVector,
      },
      {.name = "radius", .member = &Desc::radius, .presence = kRequired, .rule = kPositive},
      {.name = "height", .member = &Desc::height, .presence = kRequired, .rule = kPositive},
      {
          .name = "caps",
          .member = &Desc::caps,
      },
  };
  static void check(const Desc&, Checks&) {}
};

struct ConeKind {
  using Desc = ConeDesc;
  static constexpr std::string_view name = "cone";
  static constexpr std::string_view proto_name = "cone";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::cones;
  static constexpr Field<Desc> fields[] = {
      {.name = "base", .member = &Desc::base, .presence = kRequired},
      {
          .name = "axis",
          .member = &Desc::axis,
          .rule = kNonZeroVector,
      },
      {.name = "base_radius",
       .member = &Desc::base_radius,
       .presence = kRequired,
       .rule = kNonNegative},
      {.name = "top_radius",
       .member = &Desc::top_radius,
       .rule = kNonNegative,
       .doc = "0: pointed"},
      {.name = "height", .member = &Desc::height, .presence = kRequired, .rule = kPositive},
      {
          .name = "caps",
          .member = &Desc::caps,
      },
  };
  static void check(const Desc& c, Checks& check) {
    if (c.base_radius == 0.0 && c.top_radius == 0.0)
      check.fail("base_radius", "base_radius and top_radius must not both be 0");
  }
};

struct TorusKind {
  using Desc = TorusDesc;
  static constexpr std::string_view name = "torus";
  static constexpr std::string_view proto_name = "torus";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::tori;
  static constexpr Field<Desc> fields[] = {
      {.name = "center", .member = &Desc::center, .presence = kRequired},
      {
          .name = "axis",
          .member = &Desc::axis,
          .rule = kNonZeroVector,
      },
      {.name = "major_radius",
       .member = &Desc::major_radius,
       .presence = kRequired,
       .rule = kPositive},
      {.name = "minor_radius",
       .member = &Desc::minor_radius,
       .presence = kRequired,
       .rule = kPositive,
       .doc = "ring, horn or spindle"},
  };
  static void check(const Desc&, Checks&) {}
};

struct SdfBoxKind {
  using Desc = SdfBoxDesc;
  static constexpr std::string_view name = "sdf_box";
  static constexpr std::string_view proto_name = "sdf_box";
  static constexpr std::string_view note = "sphere traced";
  static constexpr std::array<Alias, 1> aliases{{{"sdf_rounded_box", "rounding"}}};
  static constexpr auto list = &SceneDescription::sdf_boxes;
  static constexpr Field<Desc> fields[] = {
      {
          .name = "center",
          .member = &Desc::center,
      },
      {.name = "half_extent",
       .member = &Desc::half_extent,
       .presence = kRequired,
       .rule = kPositiveComponents},
      {.name = "rounding",
       .member = &Desc::rounding,
       .rule = kNonNegative,
       .doc = "edge radius, at most the smallest half extent"},
  };
  static void check(const Desc& b, Checks& check) {
    const double smallest = glm::min(b.half_extent.x, glm::min(b.half_extent.y, b.half_extent.z));
    if (smallest > 0.0 && b.rounding > smallest)
      check.fail("rounding", "must be in [0, smallest half extent] = [0, " +
                                 Checks::format(smallest) + "], got " + Checks::format(b.rounding));
  }
};

struct SdfTorusKind {
  using Desc = SdfTorusDesc;
  static constexpr std::string_view name = "sdf_torus";
  static constexpr std::string_view proto_name = "sdf_torus";
  static constexpr std::string_view note = "sphere traced";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::sdf_tori;
  static constexpr Field<Desc> fields[] = {
      {.name = "center", .member = &Desc::center, .presence = kRequired},
      {
          .name = "axis",
          .member = &Desc::axis,
          .rule = kNonZeroVector,
      },
      {.name = "major_radius",
       .member = &Desc::major_radius,
       .presence = kRequired,
       .rule = kPositive},
      {.name = "minor_radius",
       .member = &Desc::minor_radius,
       .presence = kRequired,
       .rule = kPositive,
       .doc = "< major_radius: ring tori only"},
  };
  static void check(const Desc& t, Checks& check) {
    if (t.major_radius > 0.0 && t.minor_radius > 0.0 && !(t.minor_radius < t.major_radius))
      check.fail("minor_radius", "must be < major_radius (" + Checks::format(t.major_radius) +
                                     ") for a signed-distance torus, got " +
                                     Checks::format(t.minor_radius));
  }
};

struct SdfCapsuleKind {
  using Desc = SdfCapsuleDesc;
  static constexpr std::string_view name = "sdf_capsule";
  static constexpr std::string_view proto_name = "sdf_capsule";
  static constexpr std::string_view note = "sphere traced";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::sdf_capsules;
  static constexpr Field<Desc> fields[] = {
      {.name = "a", .member = &Desc::a, .presence = kRequired, .doc = "segment end"},
      {.name = "b", .member = &Desc::b, .presence = kRequired, .doc = "segment end"},
      {.name = "radius", .member = &Desc::radius, .presence = kRequired, .rule = kPositive},
  };
  static void check(const Desc&, Checks&) {}
};

// Patches, trimmed faces, triangles and meshes have structured fields (grids, loops, files,
// inline arrays) that the loaders read with code of their own; the declaration still names
// every field, so unknown keys, the README and the proto check know them.
struct SplinePatchKind {
  using Desc = SplinePatchDesc;
  static constexpr std::string_view name = "bspline_patch";
  static constexpr std::string_view proto_name = "spline_patch";
  static constexpr std::string_view note = "bicubic B-spline, NURBS with weights";
  static constexpr std::string_view proto_surface_name = "patch";  // in TrimmedFace
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::patches;
  static constexpr Field<Desc> fields[] = {
      {.name = "control_points",
       .presence = kRequired,
       .doc = "rows along u, each row the points along v; at least 4 x 4"},
      {.name = "weights",
       .doc = "[none] (same shape; any given makes it a NURBS patch, each > 0, the largest at "
              "most 1e6 times the smallest)"},
      {.name = "knots_u",
       .doc = "[clamped uniform on [0, 1]] (count + 4 non-decreasing values, a value repeated at "
              "most 4 times)"},
      {.name = "knots_v", .doc = "as knots_u"},
      {.name = "count_u", .member = &Desc::count_u, .presence = kRequired, .side = Side::kProto},
      {.name = "count_v", .member = &Desc::count_v, .presence = kRequired, .side = Side::kProto},
  };
};

struct TrimmedFaceKind {
  using Desc = TrimmedFaceDesc;
  static constexpr std::string_view name = "trimmed";
  static constexpr std::string_view proto_name = "trimmed_face";
  static constexpr std::string_view note =
      "the part of the surface inside the loops, in its own uv";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr auto list = &SceneDescription::trimmed_faces;
  static constexpr Field<Desc> fields[] = {
      {.name = "surface",
       .presence = kRequired,
       .doc = "a plane, disk, rectangle, sphere, cylinder, cone, torus or bspline_patch without "
              "material, visible, transform or caps"},
      {.name = "loops",
       .presence = kRequired,
       .doc = "the outer loop, then holes: [[[u, v], ...], ...]"},
  };
};

struct TriangleKind {
  using Desc = TriangleMeshDesc;
  static constexpr std::string_view name = "triangle";
  static constexpr std::string_view proto_name = "triangle";
  static constexpr std::array<Alias, 0> aliases{};
  static constexpr Field<Desc> fields[] = {
      {.name = "v0", .presence = kRequired},
      {.name = "v1", .presence = kRequired},
      {.name = "v2", .presence = kRequired},
  };
};

struct MeshKind {
  using Desc = TriangleMeshDesc;
  static constexpr std::string_view name = "mesh";
  static constexpr std::string_view proto_name = "mesh";
  static constexpr std::array<Alias, 1> aliases{{{"obj"}}};
  static constexpr auto list = &SceneDescription::meshes;
  static constexpr Field<Desc> fields[] = {
      {.name = "file",
       .presence = kRequired,
       .doc = "OBJ, PLY, glTF, STL, ... through assimp",
       .side = Side::kYaml},
      {.name = "position", .doc = "RayON's placement", .side = Side::kYaml},
      {.name = "scale", .doc = "RayON's placement", .side = Side::kYaml},
      {.name = "positions", .presence = kRequired, .side = Side::kProto},
      {.name = "indices", .presence = kRequired, .side = Side::kProto},
      {.name = "normals", .side = Side::kProto},
      {.name = "uvs", .side = Side::kProto},
  };
};

// The analytic kinds a trimmed face may cut (its `surface`), and every shape kind in the
// order of the README table.
using SurfaceKinds = std::tuple<PlaneKind, DiskKind, QuadKind, SphereKind, CylinderKind, ConeKind,
                                TorusKind, SplinePatchKind>;
using ShapeKinds = std::tuple<SphereKind, DisplacedSphereKind, QuadKind, TriangleKind, MeshKind,
                              PlaneKind, DiskKind, CylinderKind, ConeKind, TorusKind, SdfBoxKind,
                              SdfTorusKind, SdfCapsuleKind, SplinePatchKind, TrimmedFaceKind>;

// The kinds whose fields are all plain values, read and written by the generic code.
template <typename Kind>
concept PlainShapeKind = requires(const typename Kind::Desc& desc, Checks& checks) {
  Kind::check(desc, checks);
  Kind::list;
};

template <typename Kind>
constexpr std::string_view surface_proto_name() {
  if constexpr (requires { Kind::proto_surface_name; })
    return Kind::proto_surface_name;
  else
    return Kind::proto_name;
}

// Calls fn(Kind{}) for every kind of a tuple.
template <typename Tuple, typename Fn>
constexpr void for_each_kind(Fn&& fn) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (fn(std::tuple_element_t<I, Tuple>{}), ...);
  }
  (std::make_index_sequence<std::tuple_size_v<Tuple>>{});
}

}  // namespace tessera::schema
