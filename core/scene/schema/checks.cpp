#include "tessera/scene/schema/checks.hpp"

#include "tessera/scene/schema/field.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace tessera::schema {

std::string Checks::format(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string Checks::format(const glm::dvec3& value) {
  std::ostringstream out;  // not a chain of +: GCC 12 warns falsely (-Wrestrict) on those
  out << '[' << value.x << ", " << value.y << ", " << value.z << ']';
  return out.str();
}

namespace {

std::string magnitude_bound() {
  return "must be within +-" + Checks::format(kMaxMagnitude) +
         " (the renderer works in single precision), got ";
}

}  // namespace

bool Checks::finite(std::string_view field, double value) {
  if (!std::isfinite(value)) {
    fail(field, "must be a finite number, got " + format(value));
    return false;
  }
  if (std::fabs(value) <= kMaxMagnitude) return true;
  fail(field, magnitude_bound() + format(value));
  return false;
}

bool Checks::finite(std::string_view field, const glm::dvec3& value) {
  if (!std::isfinite(value.x) || !std::isfinite(value.y) || !std::isfinite(value.z)) {
    fail(field, "must be three finite numbers, got " + format(value));
    return false;
  }
  const double largest = std::max({std::fabs(value.x), std::fabs(value.y), std::fabs(value.z)});
  if (largest <= kMaxMagnitude) return true;
  fail(field, magnitude_bound() + format(value));
  return false;
}

bool Checks::positive(std::string_view field, double value) {
  if (!finite(field, value)) return false;
  if (value > 0.0) return true;
  fail(field, "must be > 0, got " + format(value));
  return false;
}

bool Checks::non_negative(std::string_view field, double value) {
  if (!finite(field, value)) return false;
  if (value >= 0.0) return true;
  fail(field, "must be >= 0, got " + format(value));
  return false;
}

bool Checks::in_range(std::string_view field, double value, double lo, double hi) {
  if (!finite(field, value)) return false;
  if (value >= lo && value <= hi) return true;
  fail(field, "must be in [" + format(lo) + ", " + format(hi) + "], got " + format(value));
  return false;
}

bool Checks::non_zero_vector(std::string_view field, const glm::dvec3& value) {
  if (!finite(field, value)) return false;
  if (glm::length(value) > 0.0) return true;
  fail(field, "must not be the zero vector");
  return false;
}

// Issues in input order: sections as a file lists them, geometry entries by index.
void sort_in_input_order(std::vector<SceneIssue>& issues, PathStyle style) {
  static constexpr std::string_view kYamlOrder[] = {"camera", "settings", "materials", "geometry",
                                                    "render"};
  static constexpr std::string_view kProtoOrder[] = {"camera", "background", "materials",
                                                     "geometry", "settings"};
  const auto key = [&](const SceneIssue& issue) {
    const std::string_view path = issue.field;
    const std::size_t end = path.find_first_of(".[");
    const std::string_view head = path.substr(0, end);
    const auto& order = style == PathStyle::kYaml ? kYamlOrder : kProtoOrder;
    const std::size_t rank = static_cast<std::size_t>(
        std::find(std::begin(order), std::end(order), head) - std::begin(order));
    std::size_t index = static_cast<std::size_t>(-1);  // whole-section issues last
    if (end != std::string_view::npos && path[end] == '[')
      std::from_chars(path.data() + end + 1, path.data() + path.size(), index);
    return std::pair(rank, index);
  };
  std::stable_sort(issues.begin(), issues.end(),
                   [&](const SceneIssue& a, const SceneIssue& b) { return key(a) < key(b); });
}

std::vector<std::string> choice_names(std::string_view choices) {
  std::vector<std::string> names;
  while (!choices.empty()) {
    const std::size_t bar = choices.find('|');
    names.emplace_back(choices.substr(0, bar));
    if (bar == std::string_view::npos) break;
    choices.remove_prefix(bar + 1);
  }
  return names;
}

bool choice_allowed(std::string_view choices, std::string_view value) {
  while (!choices.empty()) {
    const std::size_t bar = choices.find('|');
    if (choices.substr(0, bar) == value) return true;
    if (bar == std::string_view::npos) break;
    choices.remove_prefix(bar + 1);
  }
  return false;
}

}  // namespace tessera::schema
