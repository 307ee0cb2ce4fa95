#pragma once
#include <string>
#include <vector>
#include "server/config.hpp"
#include "tessera/v1/render.pb.h"

namespace tessera::server {

// GetServerInfo's answer for a daemon running with `config`: its version and build, its
// devices, the limits it enforces (the memory budget resolved) and what the renderer
// supports. The capabilities are read from the renderer's own name tables and kind
// declarations, not listed here, so a new integrator or shape appears without an edit.
// `gpus`: the names of the GPUs the scheduler renders on (one device entry each).
v1::ServerInfo make_server_info(const DaemonConfig& config,
                                const std::vector<std::string>& gpus = {});

}  // namespace tessera::server
