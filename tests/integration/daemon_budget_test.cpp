// tesserad as a separate process under load and against requests built to exhaust it: many
// clients at once (no job lost), a request whose scene would take gigabytes (refused before
// the daemon allocates for it, measured by its peak RSS), a submission whose deadline
// passes while it is checked (resubmitted with its request id: one job), a preparation over
// its time limit, and the memory estimate against the RSS the daemon really reaches.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <random>
#include <thread>

#include "client/client.hpp"
#include "client/client_error.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "server/job_cost.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/memory_estimate.hpp"
#include "tesserad_process.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;

// Sanitizers keep shadow memory beside every allocation, so resident-memory bounds and
// figures mean nothing in their builds (`make sanitize`, `make tsan`).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kMeasuresMemory = false;
#else
constexpr bool kMeasuresMemory = true;
#endif
using test::cornell;
using test::TesseradProcess;

class DaemonBudgetTest : public test::TesseradDirTest {
 protected:
  // A config file with `text`, for --config.
  std::vector<std::string> config(const std::string& text) const {
    const std::filesystem::path path = dir_ / "tesserad.yaml";
    std::ofstream(path) << text;
    return {"--config", path.string()};
  }

  std::string log_text() const {
    std::ifstream in(log());
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
};

// The scene with one more geometry entry: a mesh of `triangles` triangles, all the same one
// (three vertices, indices 0 1 2 repeated), the cheapest request per triangle there is.
v1::SubmitJobRequest with_identical_triangles(const SceneDescription& scene, std::size_t triangles,
                                              const std::string& name) {
  v1::SubmitJobRequest request = make_submit_request(scene, name, 0);
  v1::Geometry& geometry = *request.mutable_scene()->add_geometry();
  geometry.set_material(scene.materials.front().name);
  v1::TriangleMesh& mesh = *geometry.mutable_mesh();
  for (const double value : {0.2, 0.2, 0.5, 0.4, 0.2, 0.5, 0.3, 0.4, 0.5})
    mesh.add_positions(value);
  mesh.mutable_indices()->Reserve(static_cast<int>(triangles * 3));
  for (std::size_t i = 0; i < triangles; ++i) {
    mesh.add_indices(0);
    mesh.add_indices(1);
    mesh.add_indices(2);
  }
  return request;
}

// 20 clients, each with its own channel and submitter name, submit 10 jobs each at once,
// then stream every one: all 200 complete, each with its one tile, of the right size and
// with pixels in it.
TEST_F(DaemonBudgetTest, TwoHundredJobsFromTwentyClientsAreAllCompleted) {
  constexpr int kClients = 20;
  constexpr int kJobsPerClient = 10;
  const SceneDescription scene = cornell(16, 16, 1, 16);  // one tile
  TesseradProcess daemon(data(), log());
  const auto started = std::chrono::steady_clock::now();
  std::mutex mutex;
  std::vector<std::string> failures;
  std::atomic<int> completed{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < kClients; ++c)
    clients.emplace_back([&, c] {
      try {
        Client client(ClientOptions{.target = daemon.address()});
        std::vector<v1::Job> jobs;
        for (int j = 0; j < kJobsPerClient; ++j) {
          v1::SubmitJobRequest request =
              make_submit_request(scene, "job " + std::to_string(j), j % 3);
          request.set_submitter("client-" + std::to_string(c));
          jobs.push_back(client.submit(request));
        }
        for (const v1::Job& job : jobs) {
          int tiles = 0;
          client.stream_tiles(job.id(), [&](const v1::Tile& tile) {
            ++tiles;
            const RgbaImage image = decode_exr(std::span(
                reinterpret_cast<const std::uint8_t*>(tile.exr().data()), tile.exr().size()));
            bool lit = false;
            for (const float v : image.pixels) lit = lit || v > 0.0f;
            if (image.width != 16 || image.height != 16 || !lit)
              throw std::runtime_error("job " + job.id() + ": a " + std::to_string(image.width) +
                                       "x" + std::to_string(image.height) +
                                       " tile, lit: " + std::to_string(lit));
          });
          const v1::Job done = client.get(job.id());
          if (tiles != 1 || done.state() != v1::JOB_STATE_COMPLETED)
            throw std::runtime_error("job " + job.id() + ": " + std::to_string(tiles) +
                                     " tiles, state " + v1::JobState_Name(done.state()));
          ++completed;
        }
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex);
        failures.push_back("client " + std::to_string(c) + ": " + e.what());
      }
    });
  for (auto& client : clients) client.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  for (const std::string& failure : failures) ADD_FAILURE() << failure;
  EXPECT_EQ(completed.load(), kClients * kJobsPerClient);
  Client client(ClientOptions{.target = daemon.address()});
  const std::vector<v1::Job> listed = client.list();
  EXPECT_EQ(listed.size(), std::size_t{kClients * kJobsPerClient});
  for (const v1::Job& job : listed) EXPECT_EQ(job.state(), v1::JOB_STATE_COMPLETED) << job.id();
  std::cout << kClients * kJobsPerClient << " jobs from " << kClients << " clients in " << seconds
            << " s (" << kClients * kJobsPerClient / seconds << " jobs/s), daemon peak RSS "
            << format_bytes(daemon.status_bytes("VmHWM")) << "\n";
  EXPECT_EQ(daemon.terminate(), 0);
}

// The request: 50 million copies of one triangle in 150 MB. Once it took the daemon
// to 11.7 GB; now its estimate is checked against the budget before the scene is converted,
// so the daemon's peak stays at what gRPC spends receiving and parsing the message.
TEST_F(DaemonBudgetTest, FiftyMillionTrianglesAreRefusedBeforeAnyLargeAllocation) {
  if (!kMeasuresMemory) GTEST_SKIP() << "resident memory is not measurable under a sanitizer";
  constexpr std::size_t kTriangles = 50'000'000;
  TesseradProcess daemon(data(), log(), 2, "127.0.0.1:0",
                         config("memory_budget: 4GiB\nmax_primitives: 100000000\n"));
  const std::size_t idle = daemon.status_bytes("VmHWM");
  std::size_t request_bytes = 0;
  const auto sent = [&] {
    const v1::SubmitJobRequest request =
        with_identical_triangles(cornell(64, 64, 1, 32), kTriangles, "fifty million");
    request_bytes = request.ByteSizeLong();
    Client client(ClientOptions{.target = daemon.address()});
    const auto start = std::chrono::steady_clock::now();
    try {
      client.submit(request);
      ADD_FAILURE() << "the request was accepted";
    } catch (const ClientError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << e.what();
      EXPECT_NE(e.message().find("estimated"), std::string::npos) << e.message();
      EXPECT_NE(e.message().find("memory budget of 4.0 GiB"), std::string::npos) << e.message();
      std::cout << "refused: " << e.message() << "\n";
    }
    return std::chrono::steady_clock::now() - start;
  }();
  const std::size_t peak = daemon.status_bytes("VmHWM");
  const double seconds = std::chrono::duration<double>(sent).count();
  std::cout << "request of " << format_bytes(request_bytes) << " refused in " << seconds
            << " s (send, parse, check); daemon peak RSS " << format_bytes(peak) << " (idle "
            << format_bytes(idle) << ")\n";
  RecordProperty("seconds_to_refuse", std::to_string(seconds));
  RecordProperty("peak_rss_bytes", std::to_string(peak));
  // The message itself: 150 MB on the wire, 600 MB as parsed indices. Building the scene
  // would take ~10 GB.
  EXPECT_LT(peak, std::size_t{2} << 30);
  Client client(ClientOptions{.target = daemon.address()});
  EXPECT_TRUE(client.list().empty());
  EXPECT_EQ(daemon.terminate(), 0);
}

// A request over max_receive_message_bytes is refused by gRPC itself, before the daemon
// parses it; a smaller one on the same daemon is accepted.
TEST_F(DaemonBudgetTest, ARequestOverTheMessageSizeLimitIsRefused) {
  TesseradProcess daemon(data(), log(), 2, "127.0.0.1:0",
                         config("max_receive_message_bytes: 1MiB\n"));
  Client client(ClientOptions{.target = daemon.address()});
  // 500,000 triangles: 1.5M indices of a byte or more, well over 1 MiB.
  try {
    client.submit(with_identical_triangles(cornell(16, 16, 1, 16), 500'000, "big"));
    ADD_FAILURE() << "the request was accepted";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << e.what();
  }
  EXPECT_TRUE(client.list().empty());
  const v1::Job small = client.submit(make_submit_request(cornell(16, 16, 1, 16), "small", 0));
  client.stream_tiles(small.id(), [](const v1::Tile&) {});
  EXPECT_EQ(client.get(small.id()).state(), v1::JOB_STATE_COMPLETED);
  EXPECT_EQ(daemon.terminate(), 0);
}

// A client whose deadline passes while the daemon still checks its scene (the client's
// deadline starts before the daemon's, so the daemon cannot promise that no job appears)
// resubmits with the same request id and gets the job the first attempt created: exactly
// one job exists, whatever the timing, also after the daemon restarts.
TEST_F(DaemonBudgetTest, AResubmissionWithTheSameRequestIdAfterATimeoutCreatesOneJob) {
  auto daemon = std::make_unique<TesseradProcess>(data(), log());
  // About a second of conversion and validation on a loaded machine; sent in a fraction of it.
  v1::SubmitJobRequest request =
      with_identical_triangles(cornell(16, 16, 1, 16), 3'000'000, "too late");
  request.set_request_id(make_request_id());
  Client hurried(
      ClientOptions{.target = daemon->address(), .submit_deadline = 150ms, .submit_attempts = 1});
  try {
    hurried.submit(request);
    ADD_FAILURE() << "the submission beat its deadline; make the scene larger";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::DEADLINE_EXCEEDED) << e.what();
  }
  // The retry may arrive while the first attempt is still being checked: it then checks the
  // scene too and finds the first attempt's job when it comes to store its own.
  Client client(ClientOptions{.target = daemon->address()});
  const v1::Job job = client.submit(request);
  EXPECT_EQ(job.request_id(), request.request_id());
  EXPECT_EQ(job.name(), "too late");
  for (int i = 0; i < 20; ++i) {
    const std::vector<v1::Job> jobs = client.list();
    ASSERT_EQ(jobs.size(), 1u) << "after " << i * 100 << " ms";
    EXPECT_EQ(jobs[0].id(), job.id());
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(daemon->terminate(), 0);

  daemon = std::make_unique<TesseradProcess>(data(), log());
  Client after_restart(ClientOptions{.target = daemon->address()});
  EXPECT_EQ(after_restart.submit(request).id(), job.id());
  EXPECT_EQ(after_restart.list().size(), 1u);
  EXPECT_EQ(daemon->terminate(), 0);
}

// A preparation longer than prepare_timeout fails its job with an error that says so, and
// the worker goes on to the next job.
TEST_F(DaemonBudgetTest, APreparationOverTheTimeLimitFailsTheJob) {
  TesseradProcess daemon(data(), log(), 1, "127.0.0.1:0", config("prepare_timeout: 1ms\n"));
  Client client(ClientOptions{.target = daemon.address()});
  // 300,000 triangles: tens of milliseconds to build, far over 1 ms.
  const v1::Job slow =
      client.submit(with_identical_triangles(cornell(16, 16, 1, 16), 300'000, "slow"));
  try {
    client.stream_tiles(slow.id(), [](const v1::Tile&) {});
    ADD_FAILURE() << "the job completed";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::ABORTED) << e.what();
  }
  const v1::Job failed = client.get(slow.id());
  EXPECT_EQ(failed.state(), v1::JOB_STATE_FAILED);
  EXPECT_NE(failed.error().find("prepare_timeout"), std::string::npos) << failed.error();
  EXPECT_EQ(daemon.terminate(), 0);
}

// The estimate against what the daemon really reaches: one job per fresh daemon, its peak
// RSS above the idle daemon's compared with the estimate. The estimate must not fall short
// (a job it admits must fit), nor overshoot so far that it refuses what would fit easily.
TEST_F(DaemonBudgetTest, TheMemoryEstimateBoundsTheMeasuredPeak) {
  if (!kMeasuresMemory) GTEST_SKIP() << "resident memory is not measurable under a sanitizer";
  struct Case {
    std::string name;
    v1::SubmitJobRequest request;
    // Whether the estimate should be close. Repeats of one triangle are stored once, which
    // only building the scene finds out: the estimate counts every copy.
    bool close = true;
  };
  std::vector<Case> cases;
  cases.push_back({"cornell 256x256", make_submit_request(cornell(256, 256, 4, 32), "c", 0)});
  cases.push_back({"2M identical triangles",
                   with_identical_triangles(cornell(64, 64, 1, 32), 2'000'000, "identical"),
                   false});
  {
    // Two million distinct small triangles scattered in the box.
    v1::SubmitJobRequest request = make_submit_request(cornell(64, 64, 1, 32), "random", 0);
    v1::Geometry& geometry = *request.mutable_scene()->add_geometry();
    geometry.set_material(request.scene().materials(0).name());
    v1::TriangleMesh& mesh = *geometry.mutable_mesh();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> at(-1.0, 1.0), offset(-0.01, 0.01);
    constexpr int kTriangles = 2'000'000;
    for (int t = 0; t < kTriangles; ++t) {
      const double x = at(rng), y = at(rng), z = at(rng) - 3.0;
      for (int v = 0; v < 3; ++v) {
        mesh.add_positions(x + offset(rng));
        mesh.add_positions(y + offset(rng));
        mesh.add_positions(z + offset(rng));
        mesh.add_indices(static_cast<std::uint32_t>(t * 3 + v));
      }
    }
    cases.push_back({"2M random triangles", std::move(request)});
  }
  for (const Case& c : cases) {
    std::filesystem::remove_all(data());
    TesseradProcess daemon(data(), log(), 2);
    const std::size_t idle = daemon.status_bytes("VmHWM");
    Client client(ClientOptions{.target = daemon.address()});
    const v1::Job job = client.submit(c.request);
    client.stream_tiles(job.id(), [](const v1::Tile&) {});
    const std::size_t used = daemon.status_bytes("VmHWM") - idle;
    const MemoryEstimate estimate =
        estimate_memory(server::scene_size_of_proto(c.request.scene()),
                        settings_from_proto(c.request.settings()), EstimateOptions{2, false});
    const double ratio = static_cast<double>(estimate.total()) / static_cast<double>(used);
    std::cout << c.name << ": estimate " << estimate.describe() << ", measured peak above idle "
              << format_bytes(used) << ", estimate/measured " << ratio << "\n";
    EXPECT_EQ(client.get(job.id()).state(), v1::JOB_STATE_COMPLETED);
    // The request's own bytes (received and parsed) count in the measured peak but not in
    // the estimate: gRPC holds them before any budget can apply.
    EXPECT_GE(estimate.total() + 2 * c.request.ByteSizeLong(), used) << c.name;
    if (c.close && used > (std::size_t{64} << 20)) {
      EXPECT_LT(ratio, 3.0) << c.name;
    }
    EXPECT_EQ(daemon.terminate(), 0);
  }
}

}  // namespace
}  // namespace tessera
