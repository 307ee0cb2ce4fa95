#include "server/rpc_log.hpp"

#include <grpcpp/grpcpp.h>
#include <spdlog/fmt/fmt.h>

#include <chrono>
#include <string>

#include "server/log_text.hpp"
#include "server/structured_log.hpp"

#include <absl/status/status.h>

namespace tessera::server {
namespace {

// gRPC's codes are abseil's, numerically: its names, rather than a copy of the table.
std::string status_code_name(grpc::StatusCode code) {
  const std::string name = absl::StatusCodeToString(static_cast<absl::StatusCode>(code));
  return name.empty() ? "UNKNOWN" : name;
}
class RpcLogInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit RpcLogInterceptor(grpc::experimental::ServerRpcInfo* info)
      : info_(info), start_(std::chrono::steady_clock::now()) {}

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_STATUS))
      log(methods->GetSendStatus());
    methods->Proceed();
  }

 private:
  void log(const grpc::Status& status) const {
    const std::string method = info_->method() ? info_->method() : "?";
    const std::string peer = info_->server_context() ? info_->server_context()->peer() : "";
    const double milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
    const std::string code = status_code_name(status.error_code());
    const bool health = method.rfind("/grpc.health.v1.Health/", 0) == 0;
    const auto level = health ? spdlog::level::debug : spdlog::level::info;
    // The error text may quote the client's input: escaped in the text line, and the JSON
    // writer escapes the field.
    std::string text =
        fmt::format("rpc {} from {}: {} in {:.1f} ms", method, peer, code, milliseconds);
    if (status.ok()) {
      log_event(level, "rpc",
                {{"method", method},
                 {"peer", peer},
                 {"code", std::string(code)},
                 {"duration_ms", milliseconds}},
                text);
      return;
    }
    text += ": " + escape_client_text(status.error_message(), 512);
    log_event(level, "rpc",
              {{"method", method},
               {"peer", peer},
               {"code", std::string(code)},
               {"duration_ms", milliseconds},
               {"error", status.error_message()}},
              text);
  }

  grpc::experimental::ServerRpcInfo* info_;
  std::chrono::steady_clock::time_point start_;
};

class RpcLogInterceptorFactory final
    : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  grpc::experimental::Interceptor* CreateServerInterceptor(
      grpc::experimental::ServerRpcInfo* info) override {
    return new RpcLogInterceptor(info);
  }
};

}  // namespace

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> make_rpc_log_interceptor() {
  return std::make_unique<RpcLogInterceptorFactory>();
}

}  // namespace tessera::server
