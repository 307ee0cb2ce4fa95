#pragma once
#include <istream>
#include <string>
#include <string_view>

namespace tessera {

// The SHA-256 of `text` as 64 lowercase hex digits: the `sha256` of tesserad's tokens
// file (the same as `printf %s TOKEN | sha256sum`).
std::string sha256_hex(std::string_view text);

// `tessera token hash`: reads a token from `in` (one trailing newline or CRLF dropped, so
// `echo TOKEN |` works) and returns its sha256_hex. Throws std::invalid_argument when the
// token is empty or holds whitespace or control characters, which an authorization header
// cannot carry intact.
std::string hash_token(std::istream& in);

}  // namespace tessera
