#pragma once
#include <grpcpp/security/server_credentials.h>

#include <memory>

#include "server/config.hpp"

namespace tessera::server {

// The credentials tesserad listens with: plaintext without tls_cert, TLS with it, and
// mutual TLS (a client certificate signed by tls_client_ca, required and verified) with
// tls_client_ca. The PEM files are read and checked here, before the server binds, because
// gRPC would only fail at the first handshake: each file must be readable and hold what
// its key says (certificates, an unencrypted private key), the key must belong to the
// certificate and the certificate must not have expired. Throws ConfigError naming the key
// and the file.
std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const DaemonConfig& config);

}  // namespace tessera::server
