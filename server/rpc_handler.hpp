#pragma once
// The pieces every RenderService handler is made of (render_service.cpp and
// render_service_control.cpp): private to the service's translation units.
#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <string>
#include <variant>

#include "server/access_control.hpp"
#include "server/log_text.hpp"

namespace tessera::server::rpc {

// No request, however malformed, may take the daemon down: whatever escapes a handler
// becomes INTERNAL for that call alone.
template <typename Fn>
grpc::Status guarded(const char* method, Fn&& fn) {
  try {
    return fn();
  } catch (const std::exception& e) {
    spdlog::error("{} failed: {}", method, escape_client_text(e.what(), 1024));
    return grpc::Status(grpc::StatusCode::INTERNAL, std::string(method) + ": " + e.what());
  } catch (...) {
    spdlog::error("{} failed with an unknown exception", method);
    return grpc::Status(grpc::StatusCode::INTERNAL, std::string(method) + ": unknown error");
  }
}

// The caller of a RenderService call, or UNAUTHENTICATED (logged with the peer). Every
// handler starts here, before it reads its request: unary calls through unary() below, the
// streaming ones themselves.
inline std::variant<Caller, grpc::Status> authenticate(const char* method,
                                                       const AccessControl& access,
                                                       const grpc::ServerContext& context) {
  auto caller = access.authenticate(context);
  if (const auto* refused = std::get_if<grpc::Status>(&caller))
    spdlog::info("{} from {} refused: {}", method, escape_client_text(context.peer()),
                 refused->error_message());
  return caller;
}

inline grpc::Status permission_denied(std::string message) {
  return grpc::Status(grpc::StatusCode::PERMISSION_DENIED, std::move(message));
}

// Authenticates the caller of a unary call, reads its request, runs
// `fn(caller, request, response)` and sends the response when it returns OK.
template <typename Request, typename Response, typename Fn>
grpc::Status unary(const char* method, const AccessControl& access, grpc::ServerContext& context,
                   grpc::ServerUnaryStreamer<Request, Response>& streamer, Fn&& fn) {
  const auto caller = authenticate(method, access, context);
  if (const auto* refused = std::get_if<grpc::Status>(&caller)) return *refused;
  Request request;
  if (!streamer.Read(&request))
    return grpc::Status(
        grpc::StatusCode::INVALID_ARGUMENT,
        std::string("request: not a valid ") + Request::descriptor()->full_name() + " message");
  Response response;
  const grpc::Status status =
      guarded(method, [&] { return fn(std::get<Caller>(caller), request, response); });
  if (status.ok() && !streamer.Write(response))
    return grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
  return status;
}

inline grpc::Status invalid(std::string message) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, std::move(message));
}

}  // namespace tessera::server::rpc
