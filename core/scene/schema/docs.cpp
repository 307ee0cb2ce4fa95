#include "tessera/scene/schema/docs.hpp"

#include <sstream>
#include <type_traits>
#include <variant>

#include "tessera/scene/schema/kinds.hpp"

namespace tessera::schema {
namespace {

std::string quoted(std::string_view name) {
  return "`" + std::string(name) + "`";
}

std::string number(double value) {
  return Checks::format(value);
}

// What a rule allows, in words.
template <typename Desc>
std::string rule_text(const Field<Desc>& field) {
  switch (field.rule) {
    case Rule::kPositive:
      return "> 0";
    case Rule::kNonNegative:
      return ">= 0";
    case Rule::kInRange:
      return "[" + number(field.lo) + ", " + number(field.hi) + "]";
    case Rule::kNonZeroVector:
      return "non-zero vector";
    case Rule::kNonNegativeComponents:
      return "components >= 0";
    case Rule::kPositiveComponents:
      return "components > 0";
    case Rule::kNonZeroComponents:
      return "components non-zero";
    case Rule::kOneOf: {
      std::string choices(field.choices);
      for (char& c : choices)
        if (c == '|') c = ',';
      return "one of " + choices;
    }
    case Rule::kFinite:
      break;
  }
  return "";
}

// The declared default (the struct's member initialiser), for optional fields.
template <typename Desc>
std::string default_text(const Field<Desc>& field) {
  if (field.presence == Presence::kRequired) return "";
  static const Desc kDefaults{};  // static: GCC 12 misreads a local one as uninitialised
  return std::visit(
      [](auto member) -> std::string {
        using M = decltype(member);
        if constexpr (std::is_same_v<M, std::monostate>) {
          return "";
        } else {
          using Value = std::remove_cvref_t<decltype(std::declval<Desc>().*member)>;
          const Value value = kDefaults.*member;
          if constexpr (std::is_same_v<Value, glm::dvec3>)
            return Checks::format(value);
          else if constexpr (std::is_same_v<Value, bool>)
            return value ? "[true]" : "[false]";
          else if constexpr (std::is_same_v<Value, std::string>)
            return value.empty() ? "[none]" : "[" + value + "]";
          else
            return "[" + Checks::format(static_cast<double>(value)) + "]";
        }
      },
      field.member);
}

// `name` [default] and its documentation, as a shape row lists it.
template <typename Desc>
std::string shape_field(const Field<Desc>& field) {
  std::string text = quoted(field.key(true));
  if (const std::string fallback = default_text(field); !fallback.empty()) text += " " + fallback;
  if (!field.doc.empty())
    text += field.doc.front() == '[' ? " " + std::string(field.doc)
                                     : " (" + std::string(field.doc) + ")";
  return text;
}

}  // namespace

std::string shape_table_markdown() {
  std::ostringstream out;
  out << "| `type` | protobuf `Geometry` field | fields (required unless a default is given "
         "in brackets) |\n|---|---|---|\n";
  for_each_kind<ShapeKinds>([&](auto kind) {
    using Kind = decltype(kind);
    out << "| " << quoted(Kind::name);
    for (const Alias& alias : Kind::aliases) {
      out << " (or " << quoted(alias.name);
      if (!alias.requires_field.empty()) out << ", which requires " << quoted(alias.requires_field);
      out << ")";
    }
    out << " | " << quoted(Kind::proto_name) << " | ";
    bool first = true;
    for (const auto& field : Kind::fields) {
      if (!field.on_yaml()) continue;
      out << (first ? "" : ", ") << shape_field(field);
      first = false;
    }
    std::string proto_only;
    for (const auto& field : Kind::fields)
      if (!field.on_yaml()) proto_only += (proto_only.empty() ? "" : ", ") + quoted(field.name);
    if (!proto_only.empty()) out << "; protobuf: " << proto_only;
    if constexpr (requires { Kind::note; }) out << " — " << Kind::note;
    out << " |\n";
  });
  return out.str();
}

std::string material_table_markdown() {
  std::ostringstream out;
  out << "| field | default | allowed | meaning |\n|---|---|---|---|\n";
  const auto rows = [&](const auto& fields, const std::string& prefix) {
    for (const auto& field : fields) {
      out << "| " << quoted(prefix + std::string(field.name)) << " | "
          << (field.presence == Presence::kRequired ? "required" : default_text(field)) << " | "
          << rule_text(field) << " | " << field.doc << " |\n";
    }
  };
  rows(MaterialKind::fields, "");
  rows(PatternKind::fields, "pattern.");
  return out.str();
}

std::string section_table_markdown() {
  std::ostringstream out;
  out << "| YAML | protobuf | default | allowed | meaning |\n|---|---|---|---|---|\n";
  const auto rows = [&](auto kind) {
    using Kind = decltype(kind);
    for (const auto& field : Kind::fields)
      out << "| "
          << (field.on_yaml()
                  ? quoted(std::string(Kind::yaml_section) + "." + std::string(field.key(true)))
                  : std::string("—"))
          << " | "
          << (field.on_proto()
                  ? quoted(std::string(Kind::proto_section) + "." + std::string(field.name))
                  : std::string("—"))
          << " | " << default_text(field) << " | " << rule_text(field) << " | " << field.doc
          << " |\n";
  };
  rows(CameraKind{});
  rows(BackgroundKind{});
  rows(EnvironmentKind{});
  rows(LightKind{});
  rows(TextureKind{});
  rows(RenderKind{});
  return out.str();
}

}  // namespace tessera::schema
