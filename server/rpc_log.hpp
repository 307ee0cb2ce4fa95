#pragma once
// One log line per RPC (every service: RenderService, health, reflection), written when
// the call's status is sent: method, peer, status code and duration. Health checks are
// logged at debug level, so a container's probe does not fill the log.
#include <grpcpp/support/server_interceptor.h>

#include <memory>

namespace tessera::server {

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> make_rpc_log_interceptor();

}  // namespace tessera::server
