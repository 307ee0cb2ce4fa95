#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace tessera::server {

// Text from a client made safe to put in a log line or an error message: printable ASCII
// is kept, a backslash is doubled, every other byte (newlines, escape sequences, UTF-8)
// becomes \xNN, so no client text can start a line of its own or forge a log entry; text
// longer than `max_bytes` is cut and ends in "...".
std::string escape_client_text(std::string_view text, std::size_t max_bytes = 256);

}  // namespace tessera::server
