#pragma once
// A deadline on every write of a server stream. A synchronous gRPC Write to a client that
// stopped reading blocks once HTTP/2 flow control has filled the client's window, and would
// hold its server thread for as long as the client keeps the connection open. Each write is
// registered here with a deadline; one watchdog thread cancels the call (TryCancel) of a
// write still pending at its deadline, which makes the blocked Write return false so the
// handler ends and its thread is free. The stream's data is not lost: tiles live in the
// store, and the client re-attaches from its last sequence number.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

namespace grpc {
class ServerContext;
}

namespace tessera::server {

class StreamWriteWatchdog {
 public:
  explicit StreamWriteWatchdog(std::chrono::milliseconds timeout);
  ~StreamWriteWatchdog();
  StreamWriteWatchdog(const StreamWriteWatchdog&) = delete;
  StreamWriteWatchdog& operator=(const StreamWriteWatchdog&) = delete;

  enum class Outcome { kWritten, kFailed, kTimedOut };
  // Runs `write` (a Write on `context`'s stream, true when it succeeded) under the deadline:
  // kTimedOut when the watchdog had to cancel the call, kFailed when the write failed by
  // itself (the client went away).
  Outcome write(grpc::ServerContext& context, const std::function<bool()>& write);

  std::chrono::milliseconds timeout() const { return timeout_; }
  // Writes cancelled at their deadline since this watchdog started.
  std::uint64_t timeouts() const;

 private:
  struct Pending {
    std::chrono::steady_clock::time_point deadline;
    grpc::ServerContext* context = nullptr;
    bool expired = false;
  };

  void run();

  const std::chrono::milliseconds timeout_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::uint64_t, Pending> pending_;  // by registration order, so oldest first
  std::uint64_t next_id_ = 0;
  std::uint64_t timeouts_ = 0;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace tessera::server
