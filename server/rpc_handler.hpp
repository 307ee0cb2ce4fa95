#pragma once
// The pieces every RenderService handler is made of (render_service.cpp and
// render_service_control.cpp): private to the service's translation units.
#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <string>

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

// Reads the request of a unary call, runs `fn(request, response)` and sends the response
// when it returns OK.
template <typename Request, typename Response, typename Fn>
grpc::Status unary(const char* method, grpc::ServerUnaryStreamer<Request, Response>& streamer,
                   Fn&& fn) {
  Request request;
  if (!streamer.Read(&request))
    return grpc::Status(
        grpc::StatusCode::INVALID_ARGUMENT,
        std::string("request: not a valid ") + Request::descriptor()->full_name() + " message");
  Response response;
  const grpc::Status status = guarded(method, [&] { return fn(request, response); });
  if (status.ok() && !streamer.Write(response))
    return grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
  return status;
}

inline grpc::Status invalid(std::string message) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, std::move(message));
}

}  // namespace tessera::server::rpc
