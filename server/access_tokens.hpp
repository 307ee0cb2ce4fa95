#pragma once
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace tessera::server {

// What a bearer token may do: `submit` sees and controls the jobs it submitted (their
// submitter is the token's name); `admin` sees and controls every job.
enum class TokenRole { kSubmit, kAdmin };

using Sha256Digest = std::array<unsigned char, 32>;

// SHA-256 of `text` (OpenSSL's EVP).
Sha256Digest sha256(std::string_view text);

// One entry of the tokens file. The daemon never holds a token itself, only its digest, so
// the file can be read by more people than the tokens are given to.
struct AccessToken {
  std::string name;  // becomes the submitter of the jobs the token submits
  Sha256Digest digest{};
  TokenRole role = TokenRole::kSubmit;
};

inline constexpr std::size_t kMaxTokenNameLength = 128;  // the API's submitter limit
// A longer bearer token is refused without being hashed.
inline constexpr std::size_t kMaxBearerTokenLength = 4096;

// The tokens tesserad accepts, from a YAML list:
//
//   - name: alice                 # [A-Za-z0-9._@+-], 1 to 128 characters, unique
//     sha256: 2cf24dba5fb0a30e...   # 64 hex digits: the SHA-256 of the token, unique
//     role: submit                # submit or admin
//
// Immutable once loaded, so RPC threads read it without a lock.
class TokenTable {
 public:
  TokenTable() = default;
  explicit TokenTable(std::vector<AccessToken> tokens);

  // The entry whose digest is the token's, or null. Every entry is compared, each with
  // CRYPTO_memcmp, so the time taken does not tell how close a guess came.
  const AccessToken* find(std::string_view token) const;

  const std::vector<AccessToken>& tokens() const { return tokens_; }

 private:
  std::vector<AccessToken> tokens_;
};

// Parses the tokens file; throws ConfigError naming the file, line, entry and field
// (`tokens.yaml:7: tokens[2].role: must be submit or admin, got 'root'`).
TokenTable load_token_yaml(const std::string& text, const std::string& display_name);
TokenTable load_token_file(const std::filesystem::path& path);

const char* to_string(TokenRole role);

}  // namespace tessera::server
