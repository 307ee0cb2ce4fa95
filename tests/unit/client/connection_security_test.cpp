// The CLI's security flags (--token, TESSERA_TOKEN, --ca, --client-cert, --client-key,
// --tls), the ClientOptions they make, and `tessera token hash`.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "client/cli_options.hpp"
#include "client/client_connection.hpp"
#include "client/token_hash.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera {
namespace {

struct Parsed {
  ParsedCommandLine result;
  std::string err;
};

Parsed parse(std::vector<const char*> args) {
  args.insert(args.begin(), "tessera");
  std::ostringstream out, err;
  Parsed p{parse_command_line(static_cast<int>(args.size()), args.data(), out, err), {}};
  p.err = err.str();
  return p;
}

class ConnectionSecurityTest : public test::TestDirFixture {
 protected:
  void SetUp() override {
    TestDirFixture::SetUp();
    ::unsetenv("TESSERA_TOKEN");
    ::unsetenv("TESSERA_CA");
    ::unsetenv("TESSERA_SERVER");
  }
  void TearDown() override {
    ::unsetenv("TESSERA_TOKEN");
    ::unsetenv("TESSERA_CA");
    ::unsetenv("TESSERA_SERVER");
    TestDirFixture::TearDown();
  }
  std::string file(const std::string& name, const std::string& text) {
    const auto path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
};

TEST_F(ConnectionSecurityTest, EveryCommandWithAServerTakesTheSecurityFlags) {
  const std::string ca = file("ca.crt", "-----BEGIN CERTIFICATE-----\nMIIB\n");
  const std::vector<std::vector<const char*>> commands = {{"render", "s.yaml", "-o", "a.exr"},
                                                          {"submit", "s.yaml"},
                                                          {"watch", "j", "-o", "a.exr"},
                                                          {"list"},
                                                          {"status", "j"},
                                                          {"cancel", "j"},
                                                          {"delete", "j"},
                                                          {"pause", "j"},
                                                          {"resume", "j"},
                                                          {"retry", "j"},
                                                          {"update", "j", "--priority", "1"},
                                                          {"events"}};
  for (std::vector<const char*> args : commands) {
    for (const char* flag : {"--token", "t0k3n", "--ca"}) args.push_back(flag);
    args.push_back(ca.c_str());
    const Parsed p = parse(args);
    ASSERT_TRUE(p.result.command) << args[0] << ": " << p.err;
    EXPECT_EQ(p.result.command->security.token, "t0k3n") << args[0];
    EXPECT_EQ(p.result.command->security.ca_file, ca) << args[0];
  }
  // The denoiser talks to no server, so it has no such flags.
  EXPECT_FALSE(parse({"denoise", ca.c_str(), "--token", "x"}).result.command);
}

TEST_F(ConnectionSecurityTest, TheTokenAndCaComeFromTheEnvironmentToo) {
  const std::string ca = file("ca.crt", "-----BEGIN CERTIFICATE-----\nMIIB\n");
  ::setenv("TESSERA_TOKEN", "from-env", 1);
  ::setenv("TESSERA_CA", ca.c_str(), 1);
  Parsed p = parse({"list"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->security.token, "from-env");
  const ClientOptions options = client_options(*p.result.command);
  EXPECT_EQ(options.token, "from-env");
  EXPECT_TRUE(options.tls.enabled);
  EXPECT_EQ(options.tls.root_certs_pem, "-----BEGIN CERTIFICATE-----\nMIIB\n");
  p = parse({"list", "--token", "from-flag"});  // the flag wins
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->security.token, "from-flag");
  ::setenv("TESSERA_CA", (dir_ / "missing.crt").c_str(), 1);
  p = parse({"list"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
  EXPECT_NE(p.err.find("TESSERA_CA: '"), std::string::npos) << p.err;
}

// TESSERA_SERVER is the default address; an explicit --server (or health's --address)
// wins over it. Through CLI11's envname the variable overrode the flag.
TEST_F(ConnectionSecurityTest, TheServerFlagWinsOverTesseraServer) {
  ::setenv("TESSERA_SERVER", "1.2.3.4:5", 1);
  Parsed p = parse({"list"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->server, "1.2.3.4:5");
  p = parse({"list", "--server", "9.9.9.9:9"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->server, "9.9.9.9:9");
  p = parse({"health", "--address", "8.8.8.8:8"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->server, "8.8.8.8:8");
  ::setenv("TESSERA_SERVER", "no-port", 1);
  p = parse({"list"});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
  EXPECT_NE(p.err.find("TESSERA_SERVER: "), std::string::npos) << p.err;
}

TEST_F(ConnectionSecurityTest, TlsIsOnOnlyWhenAFlagAsksForIt) {
  Parsed p = parse({"list", "--server", "farm:50051"});
  ASSERT_TRUE(p.result.command) << p.err;
  ClientOptions options = client_options(*p.result.command);
  EXPECT_EQ(options.target, "farm:50051");
  EXPECT_FALSE(options.tls.enabled);
  EXPECT_TRUE(options.token.empty());

  p = parse({"list", "--tls"});
  ASSERT_TRUE(p.result.command) << p.err;
  options = client_options(*p.result.command);
  EXPECT_TRUE(options.tls.enabled);
  EXPECT_TRUE(options.tls.root_certs_pem.empty());  // the system's roots

  const std::string cert = file("client.crt", "-----BEGIN CERTIFICATE-----\ncert\n");
  const std::string key = file("client.key", "-----BEGIN PRIVATE KEY-----\nkey\n");
  p = parse({"list", "--client-cert", cert.c_str(), "--client-key", key.c_str()});
  ASSERT_TRUE(p.result.command) << p.err;
  options = client_options(*p.result.command);
  EXPECT_TRUE(options.tls.enabled);
  EXPECT_EQ(options.tls.client_cert_pem, "-----BEGIN CERTIFICATE-----\ncert\n");
  EXPECT_EQ(options.tls.client_key_pem, "-----BEGIN PRIVATE KEY-----\nkey\n");
}

TEST_F(ConnectionSecurityTest, BadSecurityFlagsAreUsageErrors) {
  const std::string cert = file("client.crt", "-----BEGIN CERTIFICATE-----\n");
  Parsed p = parse({"list", "--client-cert", cert.c_str()});
  EXPECT_FALSE(p.result.command);
  EXPECT_EQ(p.result.exit_code, kExitUsage);
  EXPECT_NE(p.err.find("--client-key"), std::string::npos) << p.err;
  p = parse({"list", "--ca", "/nonexistent/ca.crt"});
  EXPECT_FALSE(p.result.command);
  EXPECT_NE(p.err.find("--ca"), std::string::npos) << p.err;

  const std::string not_pem = file("ca.txt", "hello\n");
  p = parse({"list", "--ca", not_pem.c_str()});
  ASSERT_TRUE(p.result.command) << p.err;
  try {
    client_options(*p.result.command);
    FAIL() << "accepted a CA file that is not PEM";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "--ca: '" + not_pem + "' is not a PEM file");
  }
}

TEST(TokenHash, IsTheSha256OfTheTokenWithoutItsNewline) {
  // FIPS 180-2's "abc", and `printf hello | sha256sum`.
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  for (const char* input : {"hello", "hello\n", "hello\r\n"}) {
    std::istringstream in(input);
    EXPECT_EQ(hash_token(in), "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824")
        << input;
  }
  for (const char* bad : {"", "\n", "two words", "tab\there", "hello\n\n"}) {
    std::istringstream in(bad);
    EXPECT_THROW(hash_token(in), std::invalid_argument) << "'" << bad << "'";
  }
  const Parsed p = parse({"token", "hash"});
  ASSERT_TRUE(p.result.command) << p.err;
  EXPECT_EQ(p.result.command->kind, CommandKind::kTokenHash);
}

}  // namespace
}  // namespace tessera
