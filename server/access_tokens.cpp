#include "server/access_tokens.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "server/config.hpp"
#include "server/yaml_document.hpp"

namespace tessera::server {
namespace {

constexpr const char* kFormat =
    "a YAML list of tokens, each {name: NAME, sha256: HEX, role: submit|admin}";

std::string at_line(const std::string& file, const YAML::Node& node) {
  std::string where = file;
  if (!node.Mark().is_null()) where.append(":").append(std::to_string(node.Mark().line + 1));
  return where;
}

bool is_name_character(unsigned char c) {
  return std::isalnum(c) || c == '.' || c == '_' || c == '@' || c == '+' || c == '-';
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Why `text` is not a hex SHA-256 digest, or empty when `digest` now holds it.
std::string parse_digest(const std::string& text, Sha256Digest& digest) {
  if (text.size() != 2 * digest.size())
    return "must be 64 hexadecimal digits (the token's SHA-256), got " +
           std::to_string(text.size()) + " characters";
  for (std::size_t i = 0; i < digest.size(); ++i) {
    const int high = hex_value(text[2 * i]);
    const int low = hex_value(text[2 * i + 1]);
    if (high < 0 || low < 0)
      return "must be 64 hexadecimal digits (the token's SHA-256); character " +
             std::to_string(2 * i + (high < 0 ? 1 : 2)) + " is not one";
    digest[i] = static_cast<unsigned char>(high * 16 + low);
  }
  return {};
}

}  // namespace

Sha256Digest sha256(std::string_view text) {
  Sha256Digest digest{};
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1 ||
      length != digest.size())
    throw std::runtime_error("SHA-256 failed (OpenSSL EVP_Digest)");
  return digest;
}

const char* to_string(TokenRole role) {
  return role == TokenRole::kAdmin ? "admin" : "submit";
}

TokenTable::TokenTable(std::vector<AccessToken> tokens) : tokens_(std::move(tokens)) {}

const AccessToken* TokenTable::find(std::string_view token) const {
  if (token.empty() || token.size() > kMaxBearerTokenLength) return nullptr;
  const Sha256Digest digest = sha256(token);
  const AccessToken* found = nullptr;
  for (const AccessToken& entry : tokens_)
    if (CRYPTO_memcmp(entry.digest.data(), digest.data(), digest.size()) == 0) found = &entry;
  return found;
}

TokenTable load_token_yaml(const std::string& text, const std::string& display_name) {
  const YAML::Node root = parse_yaml_document(text, display_name);
  if (!root.IsSequence()) throw ConfigError(display_name + ": must be " + kFormat);
  if (root.size() == 0)
    throw ConfigError(display_name +
                      ": lists no tokens, so every call would be refused; add one, or run "
                      "without --tokens");

  std::vector<AccessToken> tokens;
  std::map<std::string, std::size_t> names;
  std::map<Sha256Digest, std::size_t> digests;
  for (std::size_t index = 0; index < root.size(); ++index) {
    const YAML::Node entry = root[index];
    const std::string where =
        at_line(display_name, entry) + ": tokens[" + std::to_string(index) + "]";
    if (!entry.IsMap()) throw ConfigError(where + ": must be a map {name, sha256, role}");
    for (const auto& field : entry) {
      const std::string key = field.first.IsScalar() ? field.first.Scalar() : "?";
      if (key != "name" && key != "sha256" && key != "role")
        throw ConfigError(at_line(display_name, field.first) + ": tokens[" + std::to_string(index) +
                          "]." + key + ": unknown field (a token has name, sha256 and role)");
    }
    const auto field = [&](const char* key) {
      const YAML::Node value = entry[key];
      if (!value) throw ConfigError(where + "." + key + ": is required but missing");
      if (!value.IsScalar())
        throw ConfigError(at_line(display_name, value) + ": tokens[" + std::to_string(index) +
                          "]." + key + ": must be a string");
      return std::pair{value.Scalar(), at_line(display_name, value) + ": tokens[" +
                                           std::to_string(index) + "]." + key};
    };

    AccessToken token;
    const auto [name, name_where] = field("name");
    if (name.empty() || name.size() > kMaxTokenNameLength)
      throw ConfigError(name_where + ": must be 1 to " + std::to_string(kMaxTokenNameLength) +
                        " characters, got " + std::to_string(name.size()));
    if (!std::all_of(name.begin(), name.end(),
                     [](unsigned char c) { return is_name_character(c); }))
      throw ConfigError(name_where +
                        ": may hold only letters, digits and . _ @ + - (it becomes the "
                        "submitter of the token's jobs)");
    if (const auto seen = names.find(name); seen != names.end())
      throw ConfigError(name_where + ": '" + name + "' is already the name of tokens[" +
                        std::to_string(seen->second) + "]; names must be unique");
    token.name = name;

    const auto [hex, digest_where] = field("sha256");
    if (const std::string problem = parse_digest(hex, token.digest); !problem.empty())
      throw ConfigError(digest_where + ": " + problem);
    if (const auto seen = digests.find(token.digest); seen != digests.end())
      throw ConfigError(digest_where + ": the same digest as tokens[" +
                        std::to_string(seen->second) + "]; one token cannot have two names");

    const auto [role, role_where] = field("role");
    if (role == "submit")
      token.role = TokenRole::kSubmit;
    else if (role == "admin")
      token.role = TokenRole::kAdmin;
    else
      throw ConfigError(role_where + ": must be submit or admin, got '" + role + "'");

    names.emplace(token.name, index);
    digests.emplace(token.digest, index);
    tokens.push_back(std::move(token));
  }
  return TokenTable(std::move(tokens));
}

TokenTable load_token_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path))
    throw ConfigError("tokens: cannot read the tokens file '" + path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return load_token_yaml(text.str(), path.string());
}

}  // namespace tessera::server
