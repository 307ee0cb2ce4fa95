#include "server/listen_address.hpp"

#include <algorithm>
#include <cctype>

namespace tessera::server {

std::variant<ListenAddress, std::string> parse_listen_address(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos)
    return "must be HOST:PORT (for example 127.0.0.1:50051), got '" + text + "'";
  ListenAddress address;
  address.host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  if (address.host.empty()) return "the host is missing in '" + text + "'";
  if (address.host.front() == '[') {
    if (address.host.size() < 3 || address.host.back() != ']')
      return "an IPv6 host must be written in brackets, as [::1]:50051, got '" + text + "'";
  } else if (address.host.find(':') != std::string::npos) {
    return "an IPv6 host must be written in brackets, as [::1]:50051, got '" + text + "'";
  }
  const auto bad_host_char = [](unsigned char c) {
    return !(std::isalnum(c) || c == '.' || c == '-' || c == '_' || c == ':' || c == '[' ||
             c == ']' || c == '%');
  };
  if (std::any_of(address.host.begin(), address.host.end(), bad_host_char))
    return "the host '" + address.host + "' contains characters a host name cannot have";
  if (port.empty() || port.size() > 5 ||
      !std::all_of(port.begin(), port.end(), [](unsigned char c) { return std::isdigit(c); }))
    return "the port must be a number from 0 to 65535, got '" + port + "'";
  const int value = std::stoi(port);
  if (value > 65535) return "the port must be a number from 0 to 65535, got '" + port + "'";
  address.port = static_cast<std::uint16_t>(value);
  return address;
}

bool is_loopback_host(const std::string& host) {
  if (host == "localhost" || host == "[::1]") return true;
  // 127.a.b.c with four decimal parts: a name such as 127.example.com is not loopback.
  if (host.rfind("127.", 0) != 0) return false;
  int parts = 0;
  std::size_t start = 0;
  while (start <= host.size()) {
    const std::size_t dot = std::min(host.find('.', start), host.size());
    const std::string part = host.substr(start, dot - start);
    if (part.empty() || part.size() > 3 ||
        !std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isdigit(c); }) ||
        std::stoi(part) > 255)
      return false;
    ++parts;
    start = dot + 1;
  }
  return parts == 4;
}

}  // namespace tessera::server
