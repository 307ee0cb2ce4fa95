#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "server/job_store.hpp"

namespace tessera::server {

// The rules for job labels (SubmitJob, UpdateJob) and label filters (ListJobs, WatchJobs).
// Keys are identifiers, so they can be typed on a command line and matched exactly; values
// are free text without control characters, so they cannot forge a log line.
inline constexpr std::size_t kMaxLabels = 64;
inline constexpr std::size_t kMaxLabelKeyLength = 63;
inline constexpr std::size_t kMaxLabelValueLength = 256;

// Why `key` is not a label key, or nothing: 1 to 63 bytes of letters, digits and . _ - /,
// starting with a letter or digit.
std::optional<std::string> label_key_problem(std::string_view key);
// Why `value` is not a label value, or nothing: at most 256 bytes, no control characters.
std::optional<std::string> label_value_problem(std::string_view value);
// The first problem of a label set, naming `field` and the key, or nothing.
std::optional<std::string> labels_problem(const JobLabels& labels, const std::string& field);

// A label filter: "key=value" (that label) or "key" (any value).
struct LabelFilter {
  std::string key;
  std::optional<std::string> value;
};
// The filter `text` names, or the problem (naming `field`) in `problem`.
std::optional<LabelFilter> parse_label_filter(std::string_view text, const std::string& field,
                                              std::string& problem);

}  // namespace tessera::server
