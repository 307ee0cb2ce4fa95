#include "client/client_error.hpp"

namespace tessera {

const char* status_code_name(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return "OK";
    case grpc::StatusCode::CANCELLED:
      return "CANCELLED";
    case grpc::StatusCode::UNKNOWN:
      return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT:
      return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND:
      return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS:
      return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED:
      return "PERMISSION_DENIED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION:
      return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED:
      return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE:
      return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED:
      return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL:
      return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE:
      return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS:
      return "DATA_LOSS";
    case grpc::StatusCode::UNAUTHENTICATED:
      return "UNAUTHENTICATED";
    default:
      return "UNKNOWN_CODE";
  }
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

const char* ClientError::code_name() const {
  return status_code_name(code_);
}

}  // namespace tessera
