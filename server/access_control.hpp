#pragma once
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>
#include <string_view>
#include <variant>

#include "server/access_tokens.hpp"

namespace tessera::server {

// Who makes a RenderService call, as its bearer token says.
struct Caller {
  // The token's name (the submitter of the jobs it submits); empty when the daemon has no
  // tokens.
  std::string name;
  // A `submit` token: sees and controls only jobs whose submitter is `name`. Without tokens,
  // and for `admin` tokens, every job.
  bool restricted = false;

  bool authenticated() const { return !name.empty(); }
  bool may_act_on(std::string_view submitter) const { return !restricted || submitter == name; }
};

// The one authentication check of the RenderService handlers (rpc_handler.hpp). Without a
// token table every call is let through as an unrestricted, unnamed caller (the daemon's
// behaviour before tokens); with one, a call needs `authorization: Bearer <token>` naming
// a token of the table. Health and reflection are other services and stay open.
class AccessControl {
 public:
  AccessControl() = default;  // open: no tokens
  explicit AccessControl(TokenTable tokens);

  bool requires_tokens() const { return tokens_ != nullptr; }

  // The caller, or UNAUTHENTICATED saying what is wrong (the token itself is never echoed).
  std::variant<Caller, grpc::Status> authenticate(const grpc::ServerContext& context) const;

 private:
  std::shared_ptr<const TokenTable> tokens_;
};

// The authorization metadata key (gRPC lowercases keys) and its scheme (RFC 6750).
inline constexpr const char* kAuthorizationMetadataKey = "authorization";

}  // namespace tessera::server
