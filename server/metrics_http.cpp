#include "server/metrics_http.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <variant>
#include <vector>

#include "server/listen_address.hpp"

namespace tessera::server {
namespace {

constexpr std::size_t kWorkers = 2;
constexpr std::size_t kMaxQueuedConnections = 16;
constexpr time_t kTimeoutSeconds = 5;

// httplib's ThreadPool queues without limit; this one runs a connection on the accepting
// thread once kMaxQueuedConnections wait, which stops accepting until it is served (the
// kernel's backlog, then refused connections, absorb a flood).
class BoundedTaskQueue final : public httplib::TaskQueue {
 public:
  BoundedTaskQueue() {
    for (std::size_t i = 0; i < kWorkers; ++i) workers_.emplace_back([this] { work(); });
  }

  void enqueue(std::function<void()> fn) override {
    {
      std::unique_lock lock(mutex_);
      if (queue_.size() < kMaxQueuedConnections) {
        queue_.push_back(std::move(fn));
        lock.unlock();
        ready_.notify_one();
        return;
      }
    }
    fn();
  }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    ready_.notify_all();
    for (auto& worker : workers_) worker.join();
  }

 private:
  void work() {
    for (;;) {
      std::function<void()> fn;
      {
        std::unique_lock lock(mutex_);
        ready_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping, and nothing left to close
        fn = std::move(queue_.front());
        queue_.pop_front();
      }
      fn();
    }
  }

  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

// httplib wants a bare host: "[::1]" -> "::1".
std::string bare_host(const std::string& host) {
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    return host.substr(1, host.size() - 2);
  return host;
}

}  // namespace

MetricsHttpServer::MetricsHttpServer(std::function<std::string()> render)
    : render_(std::move(render)) {}

MetricsHttpServer::~MetricsHttpServer() {
  stop();
}

int MetricsHttpServer::start(const std::string& listen) {
  const auto parsed = parse_listen_address(listen);
  if (const auto* problem = std::get_if<std::string>(&parsed))
    throw std::runtime_error("metrics_listen: " + *problem);
  const ListenAddress address = std::get<ListenAddress>(parsed);

  server_ = std::make_unique<httplib::Server>();
  server_->new_task_queue = [] { return new BoundedTaskQueue(); };
  server_->set_read_timeout(kTimeoutSeconds, 0);
  server_->set_write_timeout(kTimeoutSeconds, 0);
  server_->set_keep_alive_max_count(10);
  server_->set_payload_max_length(1024);  // a scrape has no body
  // httplib's default sets SO_REUSEPORT, with which Linux lets a second daemon bind the same
  // port and share its scrapes; SO_REUSEADDR alone still allows a quick restart.
  server_->set_socket_options([](int socket) {
    const int yes = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  server_->Get("/metrics", [this](const httplib::Request&, httplib::Response& response) {
    response.set_content(render_(), "text/plain; version=0.0.4; charset=utf-8");
  });
  // Everything else, whatever the method, is not here.
  server_->set_error_handler([](const httplib::Request&, httplib::Response& response) {
    response.status = 404;
    response.set_content("only GET /metrics is served here\n", "text/plain");
  });
  const std::string host = bare_host(address.host);
  int port = address.port;
  if (port == 0) {
    port = server_->bind_to_any_port(host);
    if (port < 0) port = 0;
  } else if (!server_->bind_to_port(host, port)) {
    port = 0;
  }
  if (port == 0) {
    server_.reset();
    throw std::runtime_error("metrics_listen: cannot listen on " + listen +
                             " (address in use, or not an address of this machine?)");
  }
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  // stop() before the thread has started listening would not reach it: wait until it has.
  for (int i = 0; i < 500 && !server_->is_running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return port;
}

void MetricsHttpServer::stop() {
  if (server_) server_->stop();
  if (thread_.joinable()) thread_.join();
  server_.reset();
}

}  // namespace tessera::server
