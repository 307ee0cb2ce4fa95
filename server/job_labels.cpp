#include "server/job_labels.hpp"

#include "server/log_text.hpp"

namespace tessera::server {
namespace {

bool is_alnum(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
}

}  // namespace

std::optional<std::string> label_key_problem(std::string_view key) {
  if (key.empty()) return "must not be empty";
  if (key.size() > kMaxLabelKeyLength)
    return "must be at most " + std::to_string(kMaxLabelKeyLength) + " bytes, got " +
           std::to_string(key.size());
  if (!is_alnum(key.front())) return "must start with a letter or digit";
  for (const char c : key)
    if (!is_alnum(c) && c != '.' && c != '_' && c != '-' && c != '/')
      return "may hold only letters, digits and . _ - /";
  return std::nullopt;
}

std::optional<std::string> label_value_problem(std::string_view value) {
  if (value.size() > kMaxLabelValueLength)
    return "must be at most " + std::to_string(kMaxLabelValueLength) + " bytes, got " +
           std::to_string(value.size());
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) return "must not hold control characters";
  }
  return std::nullopt;
}

std::optional<std::string> labels_problem(const JobLabels& labels, const std::string& field) {
  if (labels.size() > kMaxLabels)
    return field + ": at most " + std::to_string(kMaxLabels) + " labels, got " +
           std::to_string(labels.size());
  for (const auto& [key, value] : labels) {
    if (const auto problem = label_key_problem(key))
      return field + ": key '" + escape_client_text(key, 80) + "' " + *problem;
    if (const auto problem = label_value_problem(value))
      return field + "[" + key + "]: value " + *problem;
  }
  return std::nullopt;
}

std::optional<LabelFilter> parse_label_filter(std::string_view text, const std::string& field,
                                              std::string& problem) {
  LabelFilter filter;
  const auto equals = text.find('=');
  filter.key = std::string(text.substr(0, equals));
  if (equals != std::string_view::npos) filter.value = std::string(text.substr(equals + 1));
  if (const auto key_problem = label_key_problem(filter.key)) {
    problem = field + ": key '" + escape_client_text(filter.key, 80) + "' " + *key_problem +
              " (expected key=value or key)";
    return std::nullopt;
  }
  if (filter.value)
    if (const auto value_problem = label_value_problem(*filter.value)) {
      problem = field + ": value " + *value_problem;
      return std::nullopt;
    }
  return filter;
}

}  // namespace tessera::server
