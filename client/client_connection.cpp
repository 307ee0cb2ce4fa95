#include "client/client_connection.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tessera {
namespace {

std::string read_pem_file(const char* flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string(flag) + ": cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().find("-----BEGIN ") == std::string::npos)
    throw std::runtime_error(std::string(flag) + ": '" + path + "' is not a PEM file");
  return text.str();
}

}  // namespace

ClientOptions client_options(const CliCommand& command) {
  ClientOptions options;
  options.target = command.server;
  const ConnectionSecurity& security = command.security;
  options.token = security.token;
  options.tls.enabled =
      security.tls || !security.ca_file.empty() || !security.client_cert_file.empty();
  if (!security.ca_file.empty())
    options.tls.root_certs_pem = read_pem_file("--ca", security.ca_file);
  if (!security.client_cert_file.empty()) {
    options.tls.client_cert_pem = read_pem_file("--client-cert", security.client_cert_file);
    options.tls.client_key_pem = read_pem_file("--client-key", security.client_key_file);
  }
  return options;
}

}  // namespace tessera
