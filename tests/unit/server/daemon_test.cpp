// The daemon in-process on an ephemeral port, driven through the generated gRPC stub.
#include "server/daemon.hpp"

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <condition_variable>
#include <future>
#include <regex>
#include <set>
#include <thread>

#include "tessera/image/exr.hpp"
#include "tessera/v1/render.grpc.pb.h"
#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::tiny_scene;
using testing::tiny_settings;

struct StreamResult {
  std::vector<v1::Tile> tiles;
  grpc::Status status;
};

class DaemonTest : public ::testing::Test {
 protected:
  void SetUp() override {
    data_dir_ = std::filesystem::temp_directory_path() /
                ("tesserad-daemon-test-" + std::to_string(::getpid()));
    DaemonConfig config;
    config.listen = "127.0.0.1:0";
    config.threads = 2;
    config.data_dir = data_dir_;
    config.log_level = "warn";
    daemon_ = std::make_unique<Daemon>(config);
    port_ = daemon_->start();
    channel_ = grpc::CreateChannel(daemon_->address(), grpc::InsecureChannelCredentials());
    stub_ = v1::RenderService::NewStub(channel_);
  }
  void TearDown() override {
    daemon_.reset();
    std::filesystem::remove_all(data_dir_);
  }

  grpc::Status submit(const v1::SubmitJobRequest& request, v1::Job* job = nullptr) {
    grpc::ClientContext context;
    v1::SubmitJobResponse response;
    const grpc::Status status = stub_->SubmitJob(&context, request, &response);
    if (job) *job = response.job();
    return status;
  }

  v1::Job submit_ok(v1::RenderSettings settings, const std::string& name = "test",
                    int priority = 0) {
    v1::SubmitJobRequest request;
    *request.mutable_scene() = tiny_scene();
    *request.mutable_settings() = settings;
    request.set_name(name);
    request.set_priority(priority);
    v1::Job job;
    const grpc::Status status = submit(request, &job);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return job;
  }

  // Reads the whole stream; `after_first` runs once the first tile has arrived.
  StreamResult stream(const std::string& job_id, std::function<void()> after_first = {},
                      std::chrono::milliseconds deadline = 30s) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + deadline);
    v1::StreamTilesRequest request;
    request.set_job_id(job_id);
    auto reader = stub_->StreamTiles(&context, request);
    StreamResult result;
    v1::Tile tile;
    while (reader->Read(&tile)) {
      result.tiles.push_back(tile);
      if (result.tiles.size() == 1 && after_first) after_first();
    }
    result.status = reader->Finish();
    return result;
  }

  grpc::Status cancel(const std::string& job_id, v1::Job* job = nullptr) {
    grpc::ClientContext context;
    v1::CancelJobRequest request;
    request.set_job_id(job_id);
    v1::CancelJobResponse response;
    const grpc::Status status = stub_->CancelJob(&context, request, &response);
    if (job) *job = response.job();
    return status;
  }

  v1::Job get(const std::string& job_id, grpc::Status* status_out = nullptr) {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(job_id);
    v1::Job job;
    const grpc::Status status = stub_->GetJob(&context, request, &job);
    if (status_out) *status_out = status;
    return job;
  }

  std::filesystem::path data_dir_;
  std::unique_ptr<Daemon> daemon_;
  int port_ = 0;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::RenderService::Stub> stub_;
};

// Enough tiles that a job is still running when the test acts on it.
v1::RenderSettings long_settings() {
  v1::RenderSettings settings = tiny_settings(512, 512, 8);  // 4096 tiles
  settings.set_samples_per_pixel(16);
  return settings;
}

TEST_F(DaemonTest, StartsOnAnEphemeralPortAndCreatesTheDataDirectory) {
  EXPECT_GT(port_, 0);
  EXPECT_EQ(daemon_->port(), port_);
  EXPECT_EQ(daemon_->address(), "127.0.0.1:" + std::to_string(port_));
  EXPECT_TRUE(std::filesystem::is_directory(data_dir_));
}

TEST_F(DaemonTest, SubmitThenStreamEveryTileOnce) {
  v1::RenderSettings settings = tiny_settings(24, 16, 8);  // 3 x 2 tiles
  settings.clear_max_depth();                              // server default
  const v1::Job submitted = submit_ok(settings, "first", 3);
  EXPECT_TRUE(std::regex_match(submitted.id(), std::regex("job-[0-9a-f]{12}"))) << submitted.id();
  EXPECT_EQ(submitted.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(submitted.name(), "first");
  EXPECT_EQ(submitted.priority(), 3);
  EXPECT_EQ(submitted.settings().max_depth(), 6u);
  EXPECT_EQ(submitted.settings().width(), 24u);
  EXPECT_EQ(submitted.progress().tiles_total(), 6u);
  EXPECT_GT(submitted.submitted_unix_ms(), 0);

  const StreamResult result = stream(submitted.id());
  EXPECT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.tiles.size(), 6u);
  std::set<std::uint32_t> indices;
  for (const v1::Tile& tile : result.tiles) {
    indices.insert(tile.rect().index());
    EXPECT_EQ(tile.job_id(), submitted.id());
    EXPECT_EQ(tile.pass(), "beauty");
    const std::vector<std::uint8_t> bytes(tile.exr().begin(), tile.exr().end());
    const RgbaImage image = decode_exr(bytes);
    EXPECT_EQ(image.width, tile.rect().width());
    EXPECT_EQ(image.height, tile.rect().height());
  }
  EXPECT_EQ(indices.size(), 6u);
  EXPECT_EQ(result.tiles.back().progress().tiles_done(), 6u);
  EXPECT_GT(result.tiles.back().progress().rays_traced(), 0u);

  // A second stream after completion replays every tile, then ends OK.
  const StreamResult replay = stream(submitted.id());
  EXPECT_TRUE(replay.status.ok());
  EXPECT_EQ(replay.tiles.size(), 6u);

  const v1::Job done = get(submitted.id());
  EXPECT_EQ(done.state(), v1::JOB_STATE_COMPLETED);
  EXPECT_EQ(done.progress().tiles_done(), 6u);
  EXPECT_GE(done.finished_unix_ms(), done.submitted_unix_ms());
  EXPECT_GT(done.progress().rays_per_second(), 0.0);
}

TEST_F(DaemonTest, AnInvalidSceneIsInvalidArgumentNamingTheField) {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = tiny_scene();
  request.mutable_scene()->mutable_geometry(0)->mutable_sphere()->set_radius(-1);
  const grpc::Status status = submit(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "geometry[0].sphere.radius: must be > 0, got -1");

  const grpc::Status missing = submit(v1::SubmitJobRequest());
  EXPECT_EQ(missing.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(missing.error_message(), "scene: is required but missing");

  grpc::ClientContext context;
  v1::ListJobsResponse list;
  ASSERT_TRUE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());
  EXPECT_EQ(list.jobs_size(), 0);  // rejected requests make no job
}

TEST_F(DaemonTest, UnknownJobsAreNotFound) {
  EXPECT_EQ(stream("job-000000000000").status.error_code(), grpc::StatusCode::NOT_FOUND);
  grpc::Status status;
  get("job-000000000000", &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(cancel("job-000000000000").error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(stream("").status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(DaemonTest, CancellingEndsTheStreamWithCancelled) {
  const v1::Job job = submit_ok(long_settings(), "long");
  v1::Job cancelled;
  grpc::Status cancel_status;
  const StreamResult result =
      stream(job.id(), [&] { cancel_status = cancel(job.id(), &cancelled); });
  EXPECT_TRUE(cancel_status.ok()) << cancel_status.error_message();
  EXPECT_EQ(cancelled.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_NE(result.status.error_message().find("was cancelled"), std::string::npos);
  EXPECT_LT(result.tiles.size(), 4096u);

  // No tile is added after the cancel: the job's count is what the stream delivered.
  const v1::Job after = get(job.id());
  EXPECT_EQ(after.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(after.progress().tiles_done(), result.tiles.size());
  EXPECT_TRUE(cancel(job.id()).ok());  // idempotent

  // Cancelling a finished job is refused.
  const v1::Job small = submit_ok(tiny_settings());
  EXPECT_TRUE(stream(small.id()).status.ok());
  EXPECT_EQ(cancel(small.id()).error_code(), grpc::StatusCode::FAILED_PRECONDITION);
}

TEST_F(DaemonTest, AStreamPastItsDeadlineReleasesTheServer) {
  const v1::Job job = submit_ok(long_settings(), "long");
  const StreamResult result = stream(job.id(), {}, 200ms);
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);
  EXPECT_TRUE(cancel(job.id()).ok());
  // The daemon keeps serving: a new job completes.
  const v1::Job small = submit_ok(tiny_settings());
  EXPECT_TRUE(stream(small.id()).status.ok());
}

TEST_F(DaemonTest, ListJobsIsNewestFirst) {
  const v1::Job a = submit_ok(tiny_settings(), "a");
  const v1::Job b = submit_ok(tiny_settings(), "b");
  const v1::Job c = submit_ok(tiny_settings(), "c");
  grpc::ClientContext context;
  v1::ListJobsResponse list;
  ASSERT_TRUE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());
  ASSERT_EQ(list.jobs_size(), 3);
  EXPECT_EQ(list.jobs(0).id(), c.id());
  EXPECT_EQ(list.jobs(1).id(), b.id());
  EXPECT_EQ(list.jobs(2).id(), a.id());
}

TEST_F(DaemonTest, HealthServiceReportsServing) {
  grpc::GenericStub generic(channel_);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + 10s);
  // HealthCheckRequest{service: "tessera.v1.RenderService"}, encoded by hand: field 1, bytes.
  const std::string service = "tessera.v1.RenderService";
  std::string encoded = std::string("\x0a", 1) + static_cast<char>(service.size()) + service;
  grpc::Slice slice(encoded);
  grpc::ByteBuffer request(&slice, 1);
  grpc::ByteBuffer response;
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  grpc::Status status;
  generic.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request,
                    &response, [&](grpc::Status s) {
                      std::lock_guard lock(mutex);
                      status = std::move(s);
                      done = true;
                      done_cv.notify_all();
                    });
  std::unique_lock lock(mutex);
  done_cv.wait(lock, [&] { return done; });
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::vector<grpc::Slice> slices;
  ASSERT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));  // HealthCheckResponse{status: SERVING}
}

TEST_F(DaemonTest, ShutdownCancelsRunningJobsAndEndsTheirStreams) {
  const v1::Job job = submit_ok(long_settings(), "long");
  StreamResult result;
  std::promise<void> streaming;
  std::thread watcher([&] { result = stream(job.id(), [&] { streaming.set_value(); }); });
  // Shut down once the stream is live on the server (it has delivered a tile).
  const bool live = streaming.get_future().wait_for(30s) == std::future_status::ready;
  daemon_->shutdown();
  watcher.join();
  ASSERT_TRUE(live);
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::CANCELLED)
      << result.status.error_message();
  EXPECT_NE(result.status.error_message().find("daemon shutting down"), std::string::npos);
  daemon_->wait();      // returns at once: already stopped
  daemon_->shutdown();  // idempotent

  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + 2s);
  v1::ListJobsResponse list;
  EXPECT_FALSE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());
}

TEST(Daemon, ShutdownFromAnotherThreadReleasesWait) {
  DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.threads = 1;
  Daemon daemon(config);
  daemon.start();
  std::thread stopper([&] {
    std::this_thread::sleep_for(50ms);
    daemon.shutdown();
  });
  daemon.wait();
  stopper.join();
  SUCCEED();
}

TEST(Daemon, StartFailsWhenThePortIsTaken) {
  DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.threads = 1;
  Daemon first(config);
  const int port = first.start();
  config.listen = "127.0.0.1:" + std::to_string(port);
  Daemon second(config);
  EXPECT_THROW(second.start(), std::runtime_error);
}

TEST(Daemon, StartRejectsABadConfig) {
  DaemonConfig config;
  config.listen = "127.0.0.1:0";
  config.threads = 0;
  Daemon daemon(config);
  EXPECT_THROW(daemon.start(), ConfigError);
}

}  // namespace
}  // namespace tessera::server
