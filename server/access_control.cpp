#include "server/access_control.hpp"

#include <cctype>

namespace tessera::server {
namespace {

grpc::Status unauthenticated(std::string message) {
  return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, std::move(message));
}

// The token of "Bearer <token>" (the scheme is case-insensitive, RFC 7235), or empty.
std::string_view bearer_token(std::string_view value) {
  constexpr std::string_view kScheme = "bearer";
  if (value.size() <= kScheme.size() || value[kScheme.size()] != ' ') return {};
  for (std::size_t i = 0; i < kScheme.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(value[i])) != kScheme[i]) return {};
  value.remove_prefix(kScheme.size());
  while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
  while (!value.empty() && value.back() == ' ') value.remove_suffix(1);
  return value;
}

}  // namespace

AccessControl::AccessControl(TokenTable tokens)
    : tokens_(std::make_shared<const TokenTable>(std::move(tokens))) {}

std::variant<Caller, grpc::Status> AccessControl::authenticate(
    const grpc::ServerContext& context) const {
  if (!tokens_) return Caller{};
  const auto& metadata = context.client_metadata();
  const auto [first, last] = metadata.equal_range(kAuthorizationMetadataKey);
  if (first == last)
    return unauthenticated(
        "this server requires a bearer token: send the metadata 'authorization: Bearer "
        "<token>' (tessera: --token or TESSERA_TOKEN)");
  if (std::next(first) != last)
    return unauthenticated("more than one authorization header; send exactly one");
  const std::string_view value(first->second.data(), first->second.size());
  const std::string_view token = bearer_token(value);
  if (token.empty()) return unauthenticated("the authorization header must be 'Bearer <token>'");
  if (token.size() > kMaxBearerTokenLength)
    return unauthenticated("the bearer token is longer than " +
                           std::to_string(kMaxBearerTokenLength) + " bytes");
  const AccessToken* entry = tokens_->find(token);
  if (!entry) return unauthenticated("the bearer token is not one this server accepts");
  return Caller{.name = entry->name, .restricted = entry->role == TokenRole::kSubmit};
}

}  // namespace tessera::server
