#pragma once
// Log lines with structured fields, and the JSON line format (--log-format json).
//
// Code logs through spdlog as before; an event that has fields worth querying (an RPC, a
// job submitted, started, finished) goes through log_event, which logs its text the same
// way and hands its fields to the JSON formatter. In text format the fields are dropped:
// the text says the same in words. In JSON format every line is one object:
//   {"time":"2026-11-24T06:40:00.123Z","level":"info","logger":"tesserad","thread":42,
//    "event":"job_submitted","message":"job 8f... 'name' submitted ...","job_id":"8f...",...}
// Strings are escaped by the JSON writer (quotes, backslashes, control characters; bytes
// that are not UTF-8 become U+FFFD), so no client text can break a line.
#include <spdlog/common.h>
#include <spdlog/formatter.h>

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <variant>

#include "server/config.hpp"

namespace tessera::server {

using LogValue = std::variant<std::string, std::int64_t, std::uint64_t, double, bool>;

struct LogField {
  const char* key;
  LogValue value;
};

// Logs `text` at `level` on the default logger, with `event` and `fields` for JSON lines.
// Field keys must not be time, level, logger, thread, event or message.
void log_event(spdlog::level::level_enum level, const char* event,
               std::initializer_list<LogField> fields, std::string_view text);

// spdlog formatter writing one JSON object per line. It reads the fields of the event
// being logged from the logging thread, so it works with synchronous sinks (tesserad's)
// and not with spdlog's async logger.
class JsonLogFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& dest) override;
  std::unique_ptr<spdlog::formatter> clone() const override;
};

// Installs tesserad's default logger ("tesserad", on stderr) in `format` at `level`.
void configure_logging(LogFormat format, spdlog::level::level_enum level);

}  // namespace tessera::server
