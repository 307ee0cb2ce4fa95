// The security settings of tesserad's configuration: which addresses count as loopback,
// plaintext refused elsewhere unless allowed, the TLS files given in pairs, and the keys
// of the configuration file and the command line.
#include <gtest/gtest.h>

#include <fstream>

#include "config_fixture.hpp"
#include "server/command_line.hpp"
#include "server/config.hpp"
#include "server/listen_address.hpp"

namespace tessera::server {
namespace {

using testing::parse_tesserad;

// The ConfigError message of validating `config`, or "" when it is valid.
std::string error_of(const DaemonConfig& config) {
  try {
    validate_config(config);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(LoopbackHost, OnlyAddressesNoOtherMachineCanReach) {
  for (const char* host : {"127.0.0.1", "127.1.2.3", "127.255.255.255", "[::1]", "localhost"})
    EXPECT_TRUE(is_loopback_host(host)) << host;
  for (const char* host :
       {"0.0.0.0", "[::]", "10.0.0.7", "192.168.1.2", "127.example.com", "127.0.0", "127.0.0.1.5",
        "127.0.0.256", "localhost.example.com", "myhost", "[::2]", "[fe80::1]"})
    EXPECT_FALSE(is_loopback_host(host)) << host;
}

TEST(TransportSecurity, PlaintextOffLoopbackIsRefusedSayingWhatToSet) {
  DaemonConfig config;
  config.listen = "0.0.0.0:50051";
  const std::string message = error_of(config);
  EXPECT_EQ(message.rfind("listen: 0.0.0.0:50051 can be reached from other machines", 0), 0u)
      << message;
  for (const char* hint : {"tls_cert", "tls_key", "--tls-cert", "allow_insecure_remote: true",
                           "--allow-insecure-remote", "127.0.0.1"})
    EXPECT_NE(message.find(hint), std::string::npos) << hint << " missing from: " << message;

  config.allow_insecure_remote = true;
  EXPECT_EQ(error_of(config), "");
  config.allow_insecure_remote = false;
  config.tls_cert = "server.crt";
  config.tls_key = "server.key";
  EXPECT_EQ(error_of(config), "");  // the files are read at start (server_credentials.hpp)
  config.listen = "[::1]:50051";
  config.tls_cert.clear();
  config.tls_key.clear();
  EXPECT_EQ(error_of(config), "");
}

TEST(TransportSecurity, TlsFilesComeInPairsAndClientCaNeedsTls) {
  DaemonConfig config;
  config.tls_key = "server.key";
  EXPECT_EQ(error_of(config).rfind("tls_cert: is required with tls_key", 0), 0u);
  config.tls_key.clear();
  config.tls_cert = "server.crt";
  EXPECT_EQ(error_of(config).rfind("tls_key: is required with tls_cert", 0), 0u);
  config.tls_cert.clear();
  config.tls_client_ca = "ca.crt";
  EXPECT_EQ(error_of(config).rfind("tls_client_ca: needs tls_cert and tls_key", 0), 0u);
}

class SecurityConfigFile : public testing::ConfigFileTest {};

TEST_F(SecurityConfigFile, KeysAndFlagsSetTheSecuritySettings) {
  const std::string file = write(
      "listen: 0.0.0.0:6000\n"
      "tls_cert: /etc/tessera/server.crt\n"
      "tls_key: /etc/tessera/server.key\n"
      "tls_client_ca: /etc/tessera/clients.crt\n"
      "tokens: /etc/tessera/tokens.yaml\n");
  const CommandLine from_file = parse_tesserad({"--config", file});
  ASSERT_FALSE(from_file.exit_code) << from_file.message;
  EXPECT_TRUE(from_file.warnings.empty());
  EXPECT_EQ(from_file.config.tls_cert, "/etc/tessera/server.crt");
  EXPECT_EQ(from_file.config.tls_key, "/etc/tessera/server.key");
  EXPECT_EQ(from_file.config.tls_client_ca, "/etc/tessera/clients.crt");
  EXPECT_EQ(from_file.config.tokens_file, "/etc/tessera/tokens.yaml");
  EXPECT_FALSE(from_file.config.allow_insecure_remote);

  const CommandLine flags =
      parse_tesserad({"--config", file, "--tls-cert", "a.crt", "--tls-key", "a.key",
                      "--tls-client-ca", "b.crt", "--tokens", "t.yaml"});
  ASSERT_FALSE(flags.exit_code) << flags.message;
  EXPECT_EQ(flags.config.tls_cert, "a.crt");
  EXPECT_EQ(flags.config.tls_key, "a.key");
  EXPECT_EQ(flags.config.tls_client_ca, "b.crt");
  EXPECT_EQ(flags.config.tokens_file, "t.yaml");

  const CommandLine insecure =
      parse_tesserad({"--listen", "0.0.0.0:6000", "--allow-insecure-remote"});
  ASSERT_FALSE(insecure.exit_code) << insecure.message;
  EXPECT_TRUE(insecure.config.allow_insecure_remote);
  const CommandLine insecure_file =
      parse_tesserad({"--config", write("listen: '[::]:6000'\nallow_insecure_remote: true\n")});
  ASSERT_FALSE(insecure_file.exit_code) << insecure_file.message;
  EXPECT_TRUE(insecure_file.config.allow_insecure_remote);
}

TEST_F(SecurityConfigFile, BadValuesAreUsageErrorsNamingTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"allow_insecure_remote: maybe\n", ":1: allow_insecure_remote: must be true or false"},
      {"tls_cert: ''\n", ":1: tls_cert: must not be empty"},
      {"tokens: [a, b]\n", ":1: tokens: must be a string, got a list"},
      {"listen: 10.1.2.3:7000\n", "listen: 10.1.2.3:7000 can be reached from other machines"},
      {"tls_client_ca: ca.crt\n", "tls_client_ca: needs tls_cert and tls_key"},
  };
  for (const auto& [text, expected] : cases) {
    const CommandLine cl = parse_tesserad({"--config", write(text)});
    ASSERT_TRUE(cl.exit_code) << text;
    EXPECT_EQ(*cl.exit_code, kExitUsage);
    EXPECT_NE(cl.message.find(expected), std::string::npos) << cl.message;
  }
  const CommandLine empty_flag = parse_tesserad({"--tokens", ""});
  ASSERT_TRUE(empty_flag.exit_code);
  EXPECT_NE(empty_flag.message.find("--tokens: must not be empty"), std::string::npos)
      << empty_flag.message;
}

}  // namespace
}  // namespace tessera::server
