#pragma once
// Applies each declared field's rule to a description (validate_scene's generic half).
#include <type_traits>
#include <variant>

#include "tessera/scene/schema/checks.hpp"
#include "tessera/scene/schema/field.hpp"

namespace tessera::schema {

bool choice_allowed(std::string_view choices, std::string_view value);

template <typename Desc>
void apply_rule(const Field<Desc>& field, double value, Checks& check) {
  const std::string_view name = field.key(check.yaml());
  switch (field.rule) {
    case Rule::kPositive:
      check.positive(name, value);
      break;
    case Rule::kNonNegative:
      check.non_negative(name, value);
      break;
    case Rule::kInRange:
      check.in_range(name, value, field.lo, field.hi);
      break;
    default:
      check.finite(name, value);
      break;
  }
}

template <typename Desc>
void apply_rule(const Field<Desc>& field, const glm::dvec3& value, Checks& check) {
  const std::string_view name = field.key(check.yaml());
  if (field.rule == Rule::kNonZeroVector) {
    check.non_zero_vector(name, value);
    return;
  }
  if (!check.finite(name, value)) return;
  const bool all_positive = value.x > 0.0 && value.y > 0.0 && value.z > 0.0;
  const bool none_negative = value.x >= 0.0 && value.y >= 0.0 && value.z >= 0.0;
  const bool none_zero = value.x != 0.0 && value.y != 0.0 && value.z != 0.0;
  if (field.rule == Rule::kPositiveComponents && !all_positive)
    check.fail(name, "components must be > 0, got " + Checks::format(value));
  if (field.rule == Rule::kNonNegativeComponents && !none_negative)
    check.fail(name, "components must not be negative, got " + Checks::format(value));
  if (field.rule == Rule::kNonZeroComponents && !none_zero)
    check.fail(name, "components must not be zero (the transform would be singular)");
}

template <typename Desc>
void apply_rule(const Field<Desc>& field, const std::string& value, Checks& check) {
  if (field.rule != Rule::kOneOf || value.empty() || choice_allowed(field.choices, value)) return;
  std::string expected(field.choices);
  for (char& c : expected)
    if (c == '|') c = ',';
  check.fail(field.key(check.yaml()), "unknown " + std::string(field.name) + " '" + value +
                                          "' (expected one of " + expected + ")");
}

template <typename Desc, typename Value>
void apply_rule(const Field<Desc>&, const Value&, Checks&) {}  // bool, counts: any value

// Every declared field's rule on `desc`; returns whether all passed.
template <typename Desc, typename Fields>
bool check_fields(const Desc& desc, const Fields& fields, Checks& check) {
  const std::size_t before = check.issue_count();
  for (const Field<Desc>& field : fields)
    std::visit(
        [&](auto member) {
          if constexpr (!std::is_same_v<decltype(member), std::monostate>)
            apply_rule(field, desc.*member, check);
        },
        field.member);
  return check.issue_count() == before;
}

}  // namespace tessera::schema
