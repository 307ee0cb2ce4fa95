#include "server/request_id.hpp"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <cstdint>
#include <cstdio>

namespace tessera::server {
namespace {

// Deterministic: map entries (material names, labels) in key order, so the same message
// gives the same bytes on every call and in every build.
void append_deterministic(const google::protobuf::MessageLite& message, std::string& out) {
  google::protobuf::io::StringOutputStream stream(&out);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  message.SerializeToCodedStream(&coded);
}

}  // namespace

std::optional<std::string> request_id_problem(std::string_view request_id) {
  if (request_id.size() > kMaxRequestIdLength)
    return "request_id: must be at most " + std::to_string(kMaxRequestIdLength) +
           " characters, got " + std::to_string(request_id.size());
  for (std::size_t i = 0; i < request_id.size(); ++i) {
    const auto c = static_cast<unsigned char>(request_id[i]);
    if (c < 0x20 || c >= 0x7f)
      return "request_id: must be printable ASCII; byte " + std::to_string(i) + " is 0x" + [c] {
        char hex[3];
        std::snprintf(hex, sizeof hex, "%02x", c);
        return std::string(hex);
      }();
  }
  return std::nullopt;
}

std::string request_fingerprint(const v1::SubmitJobRequest& request) {
  std::string bytes;
  append_deterministic(request.scene(), bytes);
  const std::size_t scene_size = bytes.size();
  append_deterministic(request.settings(), bytes);
  // FNV-1a, 64 bits, with both sizes: not a security boundary (the ids are the
  // submitter's own), only telling a retry from another request.
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  char text[64];
  std::snprintf(text, sizeof text, "fnv1a64-%016llx-%zu-%zu", static_cast<unsigned long long>(hash),
                scene_size, bytes.size() - scene_size);
  return text;
}

}  // namespace tessera::server
