#pragma once
// tesserad as a separate process for the integration tests: started on a free port with
// its log appended to a file, stopped with SIGKILL or SIGTERM, its memory read from /proc.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/test_dir.hpp"

namespace tessera::test {

// One tesserad process on a free port, its log appended to `log`.
class TesseradProcess {
 public:
  // `extra_args` follow the others (`--config FILE`).
  TesseradProcess(const std::filesystem::path& data, const std::filesystem::path& log,
                  unsigned threads = 2, const std::string& listen = "127.0.0.1:0",
                  const std::vector<std::string>& extra_args = {}) {
    std::vector<std::string> args = {
        TESSERAD_PATH,          "--listen", listen, "--data", data.string(), "--threads",
        std::to_string(threads)};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const std::string log_path = log.string();

    int out[2];
    if (::pipe(out) != 0) throw std::runtime_error("pipe failed");
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      // Only async-signal-safe calls between fork and exec: this process has threads.
      ::dup2(out[1], STDOUT_FILENO);
      const int log_fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (log_fd >= 0) ::dup2(log_fd, STDERR_FILENO);
      ::close(out[0]);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(out[1]);
    stdout_fd_ = out[0];
    port_ = read_port();
  }
  ~TesseradProcess() {
    if (pid_ > 0) kill_now();
    if (stdout_fd_ >= 0) ::close(stdout_fd_);
  }
  TesseradProcess(const TesseradProcess&) = delete;
  TesseradProcess& operator=(const TesseradProcess&) = delete;

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }

  // A line of /proc/PID/status in bytes ("VmHWM": peak resident memory, "VmRSS": now).
  std::size_t status_bytes(const std::string& key) const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1)) * 1024;
    throw std::runtime_error("no " + key + " in /proc/" + std::to_string(pid_) + "/status");
  }

  void kill_now() {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

  // SIGTERM, then the exit status (128 + signal when killed by one).
  int terminate() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  // Reads stdout up to "tesserad listening on HOST:PORT (port N)".
  int read_port() {
    std::string text;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < give_up) {
      pollfd fd{stdout_fd_, POLLIN, 0};
      if (::poll(&fd, 1, 100) <= 0) continue;
      char buffer[256];
      const ssize_t n = ::read(stdout_fd_, buffer, sizeof buffer);
      if (n <= 0) break;
      text.append(buffer, static_cast<std::size_t>(n));
      const auto at = text.find("(port ");
      if (at != std::string::npos && text.find(')', at) != std::string::npos)
        return std::stoi(text.substr(at + 6));
    }
    throw std::runtime_error("tesserad did not report its port; stdout: " + text);
  }

  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  int port_ = 0;
};

// A folder per test for a tesserad run by a test: its data directory and log, removed
// unless the test failed (then kept for a look).
class TesseradDirTest : public TestDirFixture {
 protected:
  TesseradDirTest() : TestDirFixture("tesserad") {}

  void TearDown() override {
    if (!HasFailure()) TestDirFixture::TearDown();
  }

  std::filesystem::path data() const { return dir_ / "data"; }
  std::filesystem::path log() const { return dir_ / "tesserad.log"; }
};

}  // namespace tessera::test
