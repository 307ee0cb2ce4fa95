#pragma once
// The plain-HTTP endpoint Prometheus scrapes: GET /metrics on its own port (cpp-httplib),
// 404 for every other path and method. It must not be able to hurt the daemon: two worker
// threads, a bounded queue of connections (beyond it the accepting thread serves the
// connection itself, so accepting slows down instead of memory growing), 5 s read and write
// timeouts and no request bodies.
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace tessera::server {

class MetricsHttpServer {
 public:
  // `render` produces the exposition text; it runs on the HTTP server's threads.
  explicit MetricsHttpServer(std::function<std::string()> render);
  ~MetricsHttpServer();  // stop()
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  // Binds `listen` (HOST:PORT, port 0 picks one) and serves on a thread of its own.
  // Returns the bound port; throws std::runtime_error when it cannot listen.
  int start(const std::string& listen);
  void stop();

 private:
  std::function<std::string()> render_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
};

}  // namespace tessera::server
