// The CLI as scripts and containers use it, against tesserad as a separate process: --json
// output parses and has the documented fields, health and version, `-o -`, and Ctrl-C
// (SIGINT to a real `tessera` process) cancelling a render, keeping its partial image and
// exiting 130, or only stopping a watch.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <thread>

#include "cli_run.hpp"
#include "client/cli_options.hpp"
#include "client/client.hpp"
#include "client/commands.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "tessera/image/exr.hpp"
#include "tesserad_process.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;
using test::CliRun;
using test::cornell;
using test::kCornell;
using test::run_cli;
using test::TesseradProcess;
using Json = nlohmann::json;

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The fields README documents for a job in --json output, with their JSON types.
void expect_job_fields(const Json& job) {
  for (const char* key : {"id", "name", "state", "submitter", "request_id", "error"})
    EXPECT_TRUE(job.contains(key) && job[key].is_string()) << key << " in " << job.dump();
  for (const char* key : {"priority", "submitted_unix_ms", "finished_unix_ms"})
    EXPECT_TRUE(job.contains(key) && job[key].is_number_integer()) << key << " in " << job.dump();
  EXPECT_TRUE(job["labels"].is_object()) << job.dump();
  for (const char* key :
       {"width", "height", "samples_per_pixel", "max_depth", "tile_size", "seed", "passes"})
    EXPECT_TRUE(job["settings"].contains(key)) << key << " in " << job.dump();
  for (const char* key : {"tiles_done", "tiles_total", "percent", "rays_traced", "elapsed_seconds",
                          "rays_per_second", "eta_seconds"})
    EXPECT_TRUE(job["progress"].contains(key)) << key << " in " << job.dump();
}

// `tessera` as a child process, its stdout and stderr in files.
class CliProcess {
 public:
  CliProcess(std::vector<std::string> args, const std::filesystem::path& out,
             const std::filesystem::path& err) {
    args.insert(args.begin(), TESSERA_CLI_PATH);
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const std::string out_path = out.string(), err_path = err.string();
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      const int out_fd = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err_fd = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(out_fd, STDOUT_FILENO);
      ::dup2(err_fd, STDERR_FILENO);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~CliProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }

  void interrupt() { ::kill(pid_, SIGINT); }

  // The exit status (128 + signal when killed by one), or -1 if it is still running after
  // `timeout`.
  int wait(std::chrono::seconds timeout) {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < give_up) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(20ms);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
};

class CliScriptingTest : public test::TesseradDirTest {
 protected:
  // The job the daemon lists first (the newest), once it has at least `tiles` tiles done.
  static v1::Job wait_for_tiles(Client& client, std::uint32_t tiles) {
    const auto give_up = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < give_up) {
      const std::vector<v1::Job> jobs = client.list();
      if (!jobs.empty() && jobs.front().progress().tiles_done() >= tiles) return jobs.front();
      std::this_thread::sleep_for(50ms);
    }
    throw std::runtime_error("no job reached " + std::to_string(tiles) + " tiles");
  }
};

TEST_F(CliScriptingTest, JsonOutputParsesAndHasTheDocumentedFields) {
  TesseradProcess daemon(data(), log());
  const std::string server = daemon.address();
  const CliRun submitted =
      run_cli({"submit", kCornell, "--width", "48", "--height", "32", "--spp", "2", "--tile-size",
               "16", "--label", "shot=010", "--json", "--server", server});
  ASSERT_EQ(submitted.exit_code, kExitOk) << submitted.err;
  const Json job = Json::parse(submitted.out);
  expect_job_fields(job);
  EXPECT_EQ(job["name"], "cornell");
  EXPECT_EQ(job["labels"]["shot"], "010");
  EXPECT_EQ(job["settings"]["width"], 48);
  EXPECT_EQ(job["progress"]["tiles_total"], 6);
  EXPECT_EQ(job["request_id"].get<std::string>().size(), 32u);  // the CLI's random id
  const std::string id = job["id"];

  const std::filesystem::path exr = dir_ / "watched.exr";
  const CliRun watched = run_cli({"watch", id, "-o", exr.string(), "--json", "--server", server});
  ASSERT_EQ(watched.exit_code, kExitOk) << watched.err;
  std::istringstream lines(watched.out);
  std::string line;
  std::vector<Json> events;
  while (std::getline(lines, line)) events.push_back(Json::parse(line));
  ASSERT_EQ(events.size(), 7u) << watched.out;  // 6 tiles, then the end
  std::set<int> indices;
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(events[i]["event"], "tile");
    EXPECT_EQ(events[i]["job_id"], id);
    EXPECT_EQ(events[i]["sequence"], i + 1);
    EXPECT_EQ(events[i]["progress"]["tiles_done"], i + 1);
    for (const char* key : {"index", "x", "y", "width", "height", "pass"})
      EXPECT_TRUE(events[i]["tile"].contains(key)) << key;
    indices.insert(events[i]["tile"]["index"].get<int>());
  }
  EXPECT_EQ(indices.size(), 6u);
  const Json& done = events.back();
  EXPECT_EQ(done["event"], "completed");
  EXPECT_EQ(done["output"], exr.string());
  expect_job_fields(done["job"]);
  EXPECT_EQ(done["job"]["state"], "completed");
  EXPECT_TRUE(std::filesystem::exists(exr));

  // The watch reports the server's time for the job, which status reports too.
  const CliRun status = run_cli({"status", id, "--json", "--server", server});
  ASSERT_EQ(status.exit_code, kExitOk) << status.err;
  const Json status_job = Json::parse(status.out);
  expect_job_fields(status_job);
  EXPECT_EQ(status_job["progress"]["elapsed_seconds"], done["elapsed_seconds"]);
  EXPECT_EQ(status_job["progress"]["elapsed_seconds"], done["job"]["progress"]["elapsed_seconds"]);

  // list: filters by state, limits, and is one document.
  ASSERT_EQ(run_cli({"submit", kCornell, "--width", "16", "--height", "16", "--server", server})
                .exit_code,
            kExitOk);
  ASSERT_EQ(run_cli({"submit", kCornell, "--width", "16", "--height", "16", "--server", server})
                .exit_code,
            kExitOk);
  const CliRun all = run_cli({"list", "--json", "--server", server});
  ASSERT_EQ(all.exit_code, kExitOk) << all.err;
  const Json listed = Json::parse(all.out);
  ASSERT_EQ(listed["jobs"].size(), 3u);
  for (const Json& each : listed["jobs"]) expect_job_fields(each);
  EXPECT_EQ(listed["jobs"][2]["id"], id);  // newest first
  const CliRun limited = run_cli({"list", "--json", "--limit", "2", "--server", server});
  ASSERT_EQ(limited.exit_code, kExitOk) << limited.err;
  EXPECT_EQ(Json::parse(limited.out)["jobs"].size(), 2u);
  const CliRun completed =
      run_cli({"list", "--json", "--state", "completed", "--limit", "1", "--server", server});
  ASSERT_EQ(completed.exit_code, kExitOk) << completed.err;
  const Json only = Json::parse(completed.out)["jobs"];
  ASSERT_EQ(only.size(), 1u);
  EXPECT_EQ(only[0]["state"], "completed");
  EXPECT_EQ(daemon.terminate(), 0);
}

TEST_F(CliScriptingTest, HealthAndVersionAskTheServer) {
  TesseradProcess daemon(data(), log());
  const CliRun healthy = run_cli({"health", "--address", daemon.address()});
  EXPECT_EQ(healthy.exit_code, kExitOk) << healthy.err;
  EXPECT_EQ(healthy.out, "tesserad at " + daemon.address() + ": serving\n");
  const CliRun version = run_cli({"version", "--server", daemon.address()});
  EXPECT_EQ(version.exit_code, kExitOk) << version.err;
  EXPECT_EQ(version.out.rfind(std::string("tessera ") + TESSERA_VERSION + "\nserver: tesserad " +
                                  TESSERA_VERSION + " at " + daemon.address(),
                              0),
            0u)
      << version.out;
  const std::string address = daemon.address();
  EXPECT_EQ(daemon.terminate(), 0);

  const CliRun gone = run_cli({"health", "--address", address});
  EXPECT_EQ(gone.exit_code, kExitFailed);
  EXPECT_NE(gone.err.find("cannot reach the server at " + address), std::string::npos) << gone.err;
  const CliRun version_alone = run_cli({"version", "--server", address});
  EXPECT_EQ(version_alone.exit_code, kExitOk);
  EXPECT_NE(version_alone.out.find("server: unreachable ("), std::string::npos)
      << version_alone.out;
}

TEST_F(CliScriptingTest, DashOutputWritesTheExrToStdout) {
  TesseradProcess daemon(data(), log());
  const CliRun rendered = run_cli({"render", kCornell, "--width", "40", "--height", "24", "--spp",
                                   "2", "-o", "-", "--server", daemon.address()});
  ASSERT_EQ(rendered.exit_code, kExitOk) << rendered.err;
  const std::vector<std::uint8_t> bytes(rendered.out.begin(), rendered.out.end());
  const RgbaImage image = decode_exr(bytes);
  EXPECT_EQ(image.width, 40u);
  EXPECT_EQ(image.height, 24u);
  EXPECT_NE(rendered.err.find(": stdout"), std::string::npos) << rendered.err;
  EXPECT_EQ(daemon.terminate(), 0);
}

// SIGINT to `tessera render --keep-partial` mid-job: the job is cancelled on the server, the
// tiles received so far are written (the rest transparent black) and the exit status is 130.
TEST_F(CliScriptingTest, CtrlCDuringRenderCancelsTheJobKeepsThePartialImageAndExits130) {
  TesseradProcess daemon(data(), log(), 1);
  const std::filesystem::path exr = dir_ / "partial.exr";
  // 64 tiles of 16x16 at 1024 spp: seconds per tile on one thread, so it is mid-job.
  CliProcess cli(
      {"render", kCornell, "--width", "128", "--height", "128", "--spp", "1024", "--tile-size",
       "16", "--keep-partial", "-o", exr.string(), "--server", daemon.address()},
      dir_ / "cli.out", dir_ / "cli.err");
  Client client(ClientOptions{.target = daemon.address()});
  const v1::Job running = wait_for_tiles(client, 2);
  std::this_thread::sleep_for(500ms);  // the stream delivers within milliseconds on loopback
  cli.interrupt();
  EXPECT_EQ(cli.wait(60s), kExitInterrupted) << read_text(dir_ / "cli.err");
  const std::string err = read_text(dir_ / "cli.err");
  EXPECT_NE(err.find("interrupted: job " + running.id() + " cancelled; kept "), std::string::npos)
      << err;
  EXPECT_EQ(client.get(running.id()).state(), v1::JOB_STATE_CANCELLED);

  ASSERT_TRUE(std::filesystem::exists(exr));
  const std::string file = read_text(exr);
  const RgbaImage image = decode_exr(std::vector<std::uint8_t>(file.begin(), file.end()));
  ASSERT_EQ(image.width, 128u);
  ASSERT_EQ(image.height, 128u);
  // Received tiles have coverage where the box is; missing ones have none anywhere.
  std::size_t covered = 0;
  for (std::size_t i = 3; i < image.pixels.size(); i += 4) covered += image.pixels[i] > 0.0f;
  EXPECT_GT(covered, 0u) << "no tile was kept";
  EXPECT_LT(covered, 128u * 128) << "a cancelled job's image is complete";
  const std::size_t kept_at = err.find("; kept ");
  ASSERT_NE(kept_at, std::string::npos) << err;
  EXPECT_GE(std::stoi(err.substr(kept_at + 7)), 1) << err;
  EXPECT_EQ(daemon.terminate(), 0);
}

// SIGINT to `tessera watch` without --cancel stops watching (exit 130, no file kept) and
// leaves the job running: a watcher may not own the job.
TEST_F(CliScriptingTest, CtrlCDuringWatchStopsWatchingOnly) {
  TesseradProcess daemon(data(), log(), 1);
  Client client(ClientOptions{.target = daemon.address()});
  const v1::Job job = client.submit(make_submit_request(cornell(128, 128, 1024, 16), "watched", 0));
  const std::filesystem::path exr = dir_ / "watched.exr";
  CliProcess cli({"watch", job.id(), "-o", exr.string(), "--json", "--server", daemon.address()},
                 dir_ / "cli.out", dir_ / "cli.err");
  // Once the watch has printed a tile it is streaming (the process takes a while to start).
  const auto give_up = std::chrono::steady_clock::now() + 60s;
  while (read_text(dir_ / "cli.out").empty() && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(50ms);
  ASSERT_FALSE(read_text(dir_ / "cli.out").empty()) << "the watch received no tile";
  cli.interrupt();
  EXPECT_EQ(cli.wait(60s), kExitInterrupted) << read_text(dir_ / "cli.err");
  EXPECT_NE(read_text(dir_ / "cli.err").find("stopped watching job " + job.id() + " (it goes on)"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(exr));
  // The last JSON line says what happened.
  std::istringstream lines(read_text(dir_ / "cli.out"));
  std::string line, last_line;
  while (std::getline(lines, line)) last_line = line;
  const Json last = Json::parse(last_line);
  EXPECT_EQ(last["event"], "interrupted");
  EXPECT_EQ(last["cancelled"], false);
  EXPECT_EQ(client.get(job.id()).state(), v1::JOB_STATE_RUNNING);
  client.cancel(job.id());
  EXPECT_EQ(daemon.terminate(), 0);
}

}  // namespace
}  // namespace tessera
