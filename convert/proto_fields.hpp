#pragma once
// Reads and writes declared fields (tessera/scene/schema) on protobuf messages by name,
// through reflection: the one generic mapping between a kind's description struct and its
// message. Structured fields (std::monostate members) are left to the caller.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "tessera/scene/scene_error.hpp"
#include "tessera/scene/schema/checks.hpp"
#include "tessera/scene/schema/field.hpp"

namespace tessera::proto_fields {

namespace pb = google::protobuf;

// Collects structural problems (missing required fields, non-finite numbers) with the
// protobuf field paths.
class Reader {
 public:
  explicit Reader(std::vector<SceneIssue>& issues) : issues_(issues) {}

  void fail(std::string field, std::string message) {
    issues_.push_back(SceneIssue{"", 0, std::move(field), std::move(message)});
  }
  double number(const std::string& field, double value) {
    if (!std::isfinite(value))
      fail(field, "must be a finite number, got " + schema::Checks::format(value));
    return value;
  }
  // A Vec3 message (x, y, z).
  glm::dvec3 vec3(const std::string& field, const pb::Message& vec) {
    const pb::Descriptor* d = vec.GetDescriptor();
    const pb::Reflection* r = vec.GetReflection();
    glm::dvec3 out;
    static constexpr const char* kAxes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
      out[i] = number(field + "." + kAxes[i], r->GetDouble(vec, d->FindFieldByName(kAxes[i])));
    return out;
  }

 private:
  std::vector<SceneIssue>& issues_;
};

inline void write_vec3(pb::Message& vec, const glm::dvec3& v) {
  const pb::Descriptor* d = vec.GetDescriptor();
  const pb::Reflection* r = vec.GetReflection();
  r->SetDouble(&vec, d->FindFieldByName("x"), v.x);
  r->SetDouble(&vec, d->FindFieldByName("y"), v.y);
  r->SetDouble(&vec, d->FindFieldByName("z"), v.z);
}

// The field of `message` a declaration names; schema_test proves every declared field exists
// with a matching type, so a null here is a programming error reported as an issue.
inline const pb::FieldDescriptor* find(const pb::Message& message, std::string_view name) {
  return message.GetDescriptor()->FindFieldByName(std::string(name));
}

// Fills `desc` from `message` for every declared field with a member. A field that has
// presence (a message, or `optional`) and is unset keeps the declared default, or reads as
// zero when required; a plain proto3 scalar at 0 keeps a non-zero default when the field
// says so.
template <typename Desc, typename Fields>
void read(const pb::Message& message, const Fields& fields, Desc& desc, const std::string& prefix,
          Reader& reader) {
  const pb::Reflection* r = message.GetReflection();
  for (const schema::Field<Desc>& field : fields) {
    if (!field.on_proto()) continue;
    std::visit(
        [&](auto member) {
          using M = decltype(member);
          if constexpr (!std::is_same_v<M, std::monostate>) {
            const std::string path =
                prefix.empty() ? std::string(field.name) : prefix + "." + std::string(field.name);
            const pb::FieldDescriptor* fd = find(message, field.name);
            if (fd == nullptr) {
              reader.fail(path, "is declared but missing from " +
                                    message.GetDescriptor()->full_name() + " (internal error)");
              return;
            }
            // proto3 has no required fields: an unset required one is its zero value, as
            // for any proto3 scalar (the API's documented rule), an unset optional one keeps
            // the declared default.
            const bool present = !fd->has_presence() || r->HasField(message, fd);
            if (!present) {
              using Unset = std::remove_reference_t<decltype(desc.*member)>;
              if (field.presence == schema::Presence::kRequired) desc.*member = Unset{};
              return;
            }
            using Value = std::remove_reference_t<decltype(desc.*member)>;
            if constexpr (std::is_same_v<Value, double>) {
              const double value = r->GetDouble(message, fd);
              if (value == 0.0 && field.zero_means_default && !fd->has_presence()) return;
              desc.*member = reader.number(path, value);
            } else if constexpr (std::is_same_v<Value, glm::dvec3>) {
              desc.*member = reader.vec3(path, r->GetMessage(message, fd));
            } else if constexpr (std::is_same_v<Value, bool>) {
              desc.*member = r->GetBool(message, fd);
            } else if constexpr (std::is_same_v<Value, std::uint32_t>) {
              const std::uint32_t value = r->GetUInt32(message, fd);
              if (value == 0 && field.zero_means_default && !fd->has_presence()) return;
              desc.*member = value;
            } else {
              static_assert(std::is_same_v<Value, std::string>);
              desc.*member = r->GetString(message, fd);
            }
          }
        },
        field.member);
  }
}

// Writes every declared field with a member, explicitly (also values equal to defaults).
template <typename Desc, typename Fields>
void write(const Desc& desc, const Fields& fields, pb::Message& message) {
  const pb::Reflection* r = message.GetReflection();
  for (const schema::Field<Desc>& field : fields) {
    if (!field.on_proto()) continue;
    std::visit(
        [&](auto member) {
          using M = decltype(member);
          if constexpr (!std::is_same_v<M, std::monostate>) {
            const pb::FieldDescriptor* fd = find(message, field.name);
            if (fd == nullptr) return;  // schema_test fails on such a declaration
            using Value = std::remove_cvref_t<decltype(desc.*member)>;
            if constexpr (std::is_same_v<Value, double>)
              r->SetDouble(&message, fd, desc.*member);
            else if constexpr (std::is_same_v<Value, glm::dvec3>)
              write_vec3(*r->MutableMessage(&message, fd), desc.*member);
            else if constexpr (std::is_same_v<Value, bool>)
              r->SetBool(&message, fd, desc.*member);
            else if constexpr (std::is_same_v<Value, std::uint32_t>)
              r->SetUInt32(&message, fd, desc.*member);
            else
              r->SetString(&message, fd, desc.*member);
          }
        },
        field.member);
  }
}

// MATERIAL_TYPE_LAMBERTIAN from ("MATERIAL_TYPE_", "lambertian"): the protobuf enums are the
// core's name lists, upper-cased under a prefix.
inline std::string enum_value_name(std::string_view prefix, std::string_view name) {
  std::string out(prefix);
  for (char c : name) out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace tessera::proto_fields
