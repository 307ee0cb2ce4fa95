#include "server/structured_log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <ctime>

namespace tessera::server {
namespace {

struct EventContext {
  const char* event;
  std::initializer_list<LogField> fields;
};

// The event being logged on this thread, for the formatter the same call reaches.
thread_local const EventContext* current_event = nullptr;

std::string utc_time(spdlog::log_clock::time_point time) {
  const auto since_epoch = time.time_since_epoch();
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
  const auto millis =
      std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds).count();
  const std::time_t whole = static_cast<std::time_t>(seconds.count());
  std::tm utc{};
  gmtime_r(&whole, &utc);
  char text[40];
  const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof text - n, ".%03dZ", static_cast<int>(millis));
  return text;
}

}  // namespace

void log_event(spdlog::level::level_enum level, const char* event,
               std::initializer_list<LogField> fields, std::string_view text) {
  auto logger = spdlog::default_logger_raw();
  if (!logger->should_log(level)) return;
  const EventContext context{event, fields};
  current_event = &context;
  logger->log(level, "{}", text);
  current_event = nullptr;
}

void JsonLogFormatter::format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& dest) {
  nlohmann::ordered_json line;
  line["time"] = utc_time(message.time);
  const auto level = spdlog::level::to_string_view(message.level);
  line["level"] = std::string(level.data(), level.size());
  line["logger"] = std::string(message.logger_name.data(), message.logger_name.size());
  line["thread"] = message.thread_id;
  if (current_event) line["event"] = current_event->event;
  line["message"] = std::string(message.payload.data(), message.payload.size());
  if (current_event)
    for (const LogField& field : current_event->fields)
      std::visit([&](const auto& value) { line[field.key] = value; }, field.value);
  const std::string text =
      line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  dest.append(text.data(), text.data() + text.size());
}

std::unique_ptr<spdlog::formatter> JsonLogFormatter::clone() const {
  return std::make_unique<JsonLogFormatter>();
}

void configure_logging(LogFormat format, spdlog::level::level_enum level) {
  std::shared_ptr<spdlog::logger> logger;
  if (format == LogFormat::kJson) {
    // No colour codes: a line must be nothing but its object.
    logger = spdlog::stderr_logger_mt("tesserad");
    logger->set_formatter(std::make_unique<JsonLogFormatter>());
  } else {
    logger = spdlog::stderr_color_mt("tesserad");
  }
  spdlog::set_default_logger(std::move(logger));
  spdlog::set_level(level);
}

}  // namespace tessera::server
