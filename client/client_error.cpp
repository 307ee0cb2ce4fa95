#include "client/client_error.hpp"

#include <absl/status/status.h>

namespace tessera {

std::string status_code_name(grpc::StatusCode code) {
  // gRPC's codes are abseil's, numerically: its names, rather than a copy of the table.
  const std::string name = absl::StatusCodeToString(static_cast<absl::StatusCode>(code));
  return name.empty() ? "UNKNOWN_CODE" : name;
}
namespace {
// Appended piecewise: GCC 12 reports a false -Wrestrict for `std::string(a) + b + c` here.
std::string code_and_message(grpc::StatusCode code, const std::string& message) {
  std::string text = status_code_name(code);
  text.append(": ");
  text.append(message);
  return text;
}
}  // namespace

ClientError::ClientError(grpc::StatusCode code, std::string message)
    : std::runtime_error(code_and_message(code, message)),
      code_(code),
      message_(std::move(message)) {}

ClientError ClientError::from_status(const grpc::Status& status) {
  return ClientError(status.error_code(), status.error_message());
}

std::string ClientError::code_name() const {
  return status_code_name(code_);
}

}  // namespace tessera
