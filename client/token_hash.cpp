#include "client/token_hash.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace tessera {

std::string sha256_hex(std::string_view text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL EVP_Digest)");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 0xf]);
  }
  return hex;
}

std::string hash_token(std::istream& in) {
  std::string token(std::istreambuf_iterator<char>(in), {});
  if (!token.empty() && token.back() == '\n') token.pop_back();
  if (!token.empty() && token.back() == '\r') token.pop_back();
  if (token.empty()) throw std::invalid_argument("no token on stdin");
  if (std::any_of(token.begin(), token.end(),
                  [](unsigned char c) { return c <= ' ' || c == 0x7f; }))
    throw std::invalid_argument(
        "the token holds whitespace or control characters, which an authorization header "
        "cannot carry; use letters, digits and -._~+/ (e.g. from `openssl rand -hex 32`)");
  return sha256_hex(token);
}

}  // namespace tessera
