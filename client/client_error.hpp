#pragma once
#include <grpcpp/support/status.h>

#include <stdexcept>
#include <string>

namespace tessera {

// A call to the render service that did not succeed: the gRPC status code and the
// server's (or the transport's) message, kept apart so callers can branch on the code and
// still print the message the server wrote.
class ClientError : public std::runtime_error {
 public:
  ClientError(grpc::StatusCode code, std::string message);
  static ClientError from_status(const grpc::Status& status);

  grpc::StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // The code's canonical name, e.g. "INVALID_ARGUMENT".
  std::string code_name() const;

 private:
  grpc::StatusCode code_;
  std::string message_;
};

// "INVALID_ARGUMENT" for grpc::StatusCode::INVALID_ARGUMENT; "UNKNOWN_CODE" for values
// outside the enum.
std::string status_code_name(grpc::StatusCode code);

}  // namespace tessera
