#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "tessera/v1/render.pb.h"

namespace tessera::server {

// SubmitJobRequest.request_id: a client-chosen id that makes a submission idempotent, so a
// client that timed out can send the same request again without creating a second job.
inline constexpr std::size_t kMaxRequestIdLength = 128;

// Why `request_id` is not a usable request id ("request_id: ..."), or nothing when it is
// (empty included: no request id). At most kMaxRequestIdLength printable ASCII characters
// (0x20 to 0x7e), so it is safe in logs and errors as it is.
std::optional<std::string> request_id_problem(std::string_view request_id);

// What identifies the work a request asks for, to tell a retry (the same scene and
// settings) from a different request reusing its id: a hash of the scene and settings in
// deterministic serialization. Name, priority, labels and submitter are not part of it: a
// retry that changes them still returns the first job as it is.
std::string request_fingerprint(const v1::SubmitJobRequest& request);

}  // namespace tessera::server
