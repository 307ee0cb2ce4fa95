// The tokens file: what it accepts, the errors that name the entry and field, and the
// lookup of a bearer token by its SHA-256.
#include "server/access_tokens.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "server/config.hpp"

namespace tessera::server {
namespace {

std::string hex(const Sha256Digest& digest) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string text;
  for (unsigned char byte : digest) {
    text.push_back(kHex[byte >> 4]);
    text.push_back(kHex[byte & 0xf]);
  }
  return text;
}

// The ConfigError message of loading `text`, or "" when it loads.
std::string error_of(const std::string& text) {
  try {
    load_token_yaml(text, "tokens.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Sha256, MatchesTheStandardTestVectors) {
  // FIPS 180-2 examples.
  EXPECT_EQ(hex(sha256("abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hex(sha256("")), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(TokenTable, FindsATokenByItsDigestAndNothingElse) {
  const std::string alice = hex(sha256("alice-secret"));
  std::string root = hex(sha256("root-secret"));
  for (char& c : root) c = static_cast<char>(std::toupper(c));  // hex in either case
  const TokenTable table = load_token_yaml("- name: alice\n  sha256: " + alice +
                                               "\n  role: submit\n"
                                               "- {name: root@ops, sha256: " +
                                               root + ", role: admin}\n",
                                           "tokens.yaml");
  ASSERT_EQ(table.tokens().size(), 2u);
  const AccessToken* found = table.find("alice-secret");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->name, "alice");
  EXPECT_EQ(found->role, TokenRole::kSubmit);
  found = table.find("root-secret");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->name, "root@ops");
  EXPECT_EQ(found->role, TokenRole::kAdmin);
  EXPECT_EQ(table.find("alice-secreT"), nullptr);
  EXPECT_EQ(table.find(""), nullptr);
  EXPECT_EQ(table.find(alice), nullptr);  // the digest is not the token
  EXPECT_EQ(table.find(std::string(kMaxBearerTokenLength + 1, 'a')), nullptr);
}

TEST(TokenTable, ErrorsNameTheLineEntryAndField) {
  const std::string a = hex(sha256("a"));
  const std::string b = hex(sha256("b"));
  const std::string entry_a = "- {name: alice, sha256: " + a + ", role: submit}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {entry_a + "- {name: alice, sha256: " + b + ", role: admin}\n",
       "tokens.yaml:2: tokens[1].name: 'alice' is already the name of tokens[0]"},
      {entry_a + "- {name: bob, sha256: " + a + ", role: admin}\n",
       "tokens.yaml:2: tokens[1].sha256: the same digest as tokens[0]"},
      {entry_a + "- {name: bob, sha256: " + b.substr(1) + ", role: submit}\n",
       "tokens.yaml:2: tokens[1].sha256: must be 64 hexadecimal digits (the token's SHA-256), "
       "got 63 characters"},
      {entry_a + "- {name: bob, sha256: " + b.substr(0, 63) + "g, role: submit}\n",
       "tokens.yaml:2: tokens[1].sha256: must be 64 hexadecimal digits (the token's SHA-256); "
       "character 64 is not one"},
      {entry_a + "- {name: bob, sha256: " + b + ", role: root}\n",
       "tokens.yaml:2: tokens[1].role: must be submit or admin, got 'root'"},
      {entry_a + "- {name: bob, role: submit}\n",
       "tokens.yaml:2: tokens[1].sha256: is required but missing"},
      {entry_a + "- {name: bob, sha256: " + b + ", role: submit, expires: never}\n",
       "tokens.yaml:2: tokens[1].expires: unknown field"},
      {entry_a + "- {name: 'bob smith', sha256: " + b + ", role: submit}\n",
       "tokens.yaml:2: tokens[1].name: may hold only letters, digits"},
      {entry_a + "- {name: '', sha256: " + b + ", role: submit}\n",
       "tokens.yaml:2: tokens[1].name: must be 1 to 128 characters, got 0"},
      {entry_a + "- {name: [x], sha256: " + b + ", role: submit}\n",
       "tokens.yaml:2: tokens[1].name: must be a string"},
      {entry_a + "- just-a-name\n", "tokens.yaml:2: tokens[1]: must be a map"},
      {"alice: " + a + "\n", "tokens.yaml: must be a YAML list of tokens"},
      {"[]\n", "tokens.yaml: lists no tokens"},
      {"- {name: alice\n", "tokens.yaml:2: YAML syntax error"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = error_of(text);
    EXPECT_EQ(message.rfind(expected, 0), 0u) << "file:\n" << text << "message: " << message;
  }
  EXPECT_EQ(error_of(entry_a), "");
}

TEST(TokenTable, AMissingFileIsAnErrorNamingIt) {
  try {
    load_token_file("/nonexistent/tokens.yaml");
    FAIL() << "loaded a missing file";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "tokens: cannot read the tokens file '/nonexistent/tokens.yaml'");
  }
}

}  // namespace
}  // namespace tessera::server
