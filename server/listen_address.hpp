#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

namespace tessera::server {

// A TCP address to listen on: `HOST:PORT`, where HOST is a name, an IPv4 address or a
// bracketed IPv6 address (`[::1]`) and PORT is 0 to 65535 (0: any free port).
struct ListenAddress {
  std::string host;
  std::uint16_t port = 0;

  std::string to_string() const { return host + ":" + std::to_string(port); }
};

// The address, or why the text is not one (for messages such as `listen: <reason>`).
std::variant<ListenAddress, std::string> parse_listen_address(const std::string& text);

// Whether only this machine can reach `host`: 127.0.0.0/8, [::1] or localhost. The wildcard
// addresses (0.0.0.0, [::]) and every other name are not, whatever they resolve to now.
bool is_loopback_host(const std::string& host);

}  // namespace tessera::server
