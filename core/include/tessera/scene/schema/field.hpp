#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

namespace tessera::schema {

// One field of a scene kind (a shape, the material, the camera, ...), declared once. The
// YAML loader, the protobuf conversion in both directions, validate_scene and the README's
// field tables all read this declaration; nothing else lists the field.

enum class Presence : std::uint8_t {
  kRequired,  // missing is an error ("is required but missing")
  kOptional,  // missing keeps the description's default (the struct's member initialiser)
};

// The largest magnitude any number in a scene may have, whatever its rule. The renderer
// works in single precision (largest float ~3.4e38): a camera at 1e308, an emission of
// 1e308 or a radius of 1e300 is finite in the description but infinite or NaN in the
// renderer. 1e12 leaves squares (distances, areas: 1e24) and sums of many samples well
// inside float range while allowing any physical scene (a 1e12 m scene is 7 AU across).
inline constexpr double kMaxMagnitude = 1e12;

// The value rule validate_scene applies. Every number must be finite and within
// +-kMaxMagnitude whatever the rule.
enum class Rule : std::uint8_t {
  kFinite,
  kPositive,               // > 0 (lengths, radii)
  kNonNegative,            // >= 0
  kInRange,                // [lo, hi]
  kNonZeroVector,          // a direction: finite, not (0, 0, 0); need not be unit length
  kNonNegativeComponents,  // colours, emission
  kPositiveComponents,     // half extents
  kNonZeroComponents,      // scale factors
  kOneOf,                  // a string from `choices` (empty allowed when optional)
};

// Where a field exists: most fields have the same name in YAML and protobuf; a few
// structural ones exist on one side only (a mesh's `file` in YAML, its inline `positions`
// in protobuf).
enum class Side : std::uint8_t { kBoth, kYaml, kProto };

// Member pointer to the value the field fills. std::monostate: the kind reads and writes
// the field itself (structured values such as a patch's control grid); the declaration
// still names it, so unknown-key checks and the README know it.
template <typename Desc>
using Member = std::variant<std::monostate, double Desc::*, glm::dvec3 Desc::*, bool Desc::*,
                            std::uint32_t Desc::*, std::string Desc::*>;

template <typename Desc>
struct Field {
  std::string_view name;  // the protobuf field name; the YAML key unless yaml_name is set
  Member<Desc> member{};
  Presence presence = Presence::kOptional;
  Rule rule = Rule::kFinite;
  double lo = 0.0;  // kInRange bounds
  double hi = 0.0;
  std::string_view doc{};  // one phrase for the README: meaning and unit
  // YAML may write a colour as one number for grey.
  bool grey_scalar = false;
  // RayON's spelling where it differs from the protobuf name (`fov`, `spp`).
  std::string_view yaml_name{};
  Side side = Side::kBoth;
  // kOneOf: the accepted values, separated by '|'.
  std::string_view choices{};
  // Protobuf scalars without presence read 0 when unset: take the declared default then.
  bool zero_means_default = false;

  constexpr std::string_view key(bool yaml) const {
    return yaml && !yaml_name.empty() ? yaml_name : name;
  }
  constexpr bool on_yaml() const { return side != Side::kProto; }
  constexpr bool on_proto() const { return side != Side::kYaml; }
};

// A name a kind also answers to in YAML (`quad` for `rectangle`), and a field that alias
// makes required (`sdf_rounded_box` is an `sdf_box` whose `rounding` must be given).
struct Alias {
  std::string_view name;
  std::string_view requires_field{};
};

// A RayON key that Tessera reads but does not use: a warning that says so, not an error.
struct IgnoredKey {
  std::string_view name;
  std::string_view reason;
};

// The choices of the field `name` in a kind's declaration ("a|b|c"; empty when it has none),
// for what lists them outside the scene: the daemon's capabilities, the CLI's flags.
template <typename Kind>
constexpr std::string_view field_choices(std::string_view name) {
  for (const auto& field : Kind::fields)
    if (field.name == name) return field.choices;
  return {};
}

// The names in a kOneOf field's choices: "a|b|c" -> {a, b, c}.
std::vector<std::string> choice_names(std::string_view choices);

}  // namespace tessera::schema
