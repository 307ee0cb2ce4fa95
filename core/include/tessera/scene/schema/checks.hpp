#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "tessera/scene/scene_error.hpp"
#include "tessera/scene/schema/path_style.hpp"

namespace tessera::schema {

// Collects issues for the fields of one value (a shape, a material, the camera) under a
// path prefix; a kind's own rules speak through it with bare field names.
class Checks {
 public:
  Checks(std::vector<SceneIssue>& issues, std::string prefix, PathStyle style)
      : issues_(issues), prefix_(std::move(prefix)), style_(style) {}

  bool yaml() const { return style_ == PathStyle::kYaml; }
  std::string path(std::string_view field) const {
    if (field.empty()) return prefix_;
    return prefix_.empty() ? std::string(field) : prefix_ + "." + std::string(field);
  }
  // The same checks under a longer prefix (a transform's `rotate`, a face's `surface`).
  Checks nested(std::string_view field) const { return Checks(issues_, path(field), style_); }

  void fail(std::string_view field, std::string message) {
    issues_.push_back(SceneIssue{"", 0, path(field), std::move(message)});
  }
  bool finite(std::string_view field, double value);
  bool finite(std::string_view field, const glm::dvec3& value);
  bool positive(std::string_view field, double value);
  bool non_negative(std::string_view field, double value);
  bool in_range(std::string_view field, double value, double lo, double hi);
  bool non_zero_vector(std::string_view field, const glm::dvec3& value);

  std::size_t issue_count() const { return issues_.size(); }

  static std::string format(double value);
  static std::string format(const glm::dvec3& value);

 private:
  std::vector<SceneIssue>& issues_;
  std::string prefix_;
  PathStyle style_;
};

// Sorts issues stably into input order: sections as a file or request lists them, then
// geometry entries and materials by index.
void sort_in_input_order(std::vector<SceneIssue>& issues, PathStyle style);

}  // namespace tessera::schema
