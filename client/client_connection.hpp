#pragma once
#include "client/cli_options.hpp"
#include "client/client.hpp"

namespace tessera {

// The ClientOptions of a command: its --server, and TLS and the bearer token as its
// security flags say (--ca, --client-cert and --client-key are read here). TLS is on with
// --tls, --ca or --client-cert. Throws std::runtime_error naming the flag when a file
// cannot be read.
ClientOptions client_options(const CliCommand& command);

}  // namespace tessera
