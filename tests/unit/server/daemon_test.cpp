// The daemon in-process on an ephemeral port, driven through the generated gRPC stub.
#include "server/daemon.hpp"
#include "server/server_info.hpp"

#include "server/sqlite_job_store.hpp"

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <condition_variable>
#include <future>
#include <latch>
#include <regex>
#include <set>
#include <thread>

#include "tessera/image/exr.hpp"
#include "tessera/v1/render.grpc.pb.h"
#include "test_scenes.hpp"
#include "tests/support/loopback_daemon_config.hpp"

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
    std::filesystem::remove_all(data_dir_);
    restart();
  }

  // (Re)starts the daemon on the same data directory.
  void restart(const std::function<void(DaemonConfig&)>& adjust = {}) {
    daemon_.reset();
    DaemonConfig config = test::loopback_daemon_config(data_dir_, 2);
    if (adjust) adjust(config);
    daemon_ = std::make_unique<Daemon>(config);
    port_ = daemon_->start();
    channel_ = grpc::CreateChannel(daemon_->address(), grpc::InsecureChannelCredentials());
    stub_ = v1::RenderService::NewStub(channel_);
  }

  grpc::Status remove(const std::string& job_id) {
    grpc::ClientContext context;
    v1::DeleteJobRequest request;
    request.set_job_id(job_id);
    v1::DeleteJobResponse response;
    return stub_->DeleteJob(&context, request, &response);
  }

  // Sends `bytes` as the request of unary `method`, as a client with a broken encoder would.
  grpc::Status raw_unary_call(const std::string& method, const std::string& bytes) {
    grpc::GenericStub generic(channel_);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + 10s);
    grpc::Slice slice(bytes);
    grpc::ByteBuffer request(&slice, 1);
    grpc::ByteBuffer response;
    std::promise<grpc::Status> done;
    generic.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                      [&](grpc::Status s) { done.set_value(std::move(s)); });
    return done.get_future().get();
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

  v1::Job submit_ok(v1::RenderSettings settings, const std::string& name = "test", int priority = 0,
                    const std::string& submitter = "") {
    v1::SubmitJobRequest request;
    *request.mutable_scene() = tiny_scene();
    *request.mutable_settings() = settings;
    request.set_name(name);
    request.set_priority(priority);
    request.set_submitter(submitter);
    v1::Job job;
    const grpc::Status status = submit(request, &job);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return job;
  }

  // Reads the whole stream; `after_first` runs once the first tile has arrived.
  StreamResult stream(const std::string& job_id, std::function<void()> after_first = {},
                      std::chrono::milliseconds deadline = 30s, std::uint32_t after_tiles = 0) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + deadline);
    v1::StreamTilesRequest request;
    request.set_job_id(job_id);
    request.set_after_tiles(after_tiles);
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
  EXPECT_EQ(submitted.settings().max_depth(), 16u);
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

// A client that lost its stream re-attaches after the last tile it got (its
// progress.tiles_done) and receives exactly the rest, in the same order.
TEST_F(DaemonTest, StreamTilesReattachesAfterTheTilesAlreadyReceived) {
  const v1::Job job = submit_ok(tiny_settings(24, 16, 8), "reattach");  // 6 tiles
  const StreamResult all = stream(job.id());
  ASSERT_TRUE(all.status.ok());
  ASSERT_EQ(all.tiles.size(), 6u);
  const StreamResult rest = stream(job.id(), {}, 30s, all.tiles[3].progress().tiles_done());
  ASSERT_TRUE(rest.status.ok()) << rest.status.error_message();
  ASSERT_EQ(rest.tiles.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rest.tiles[i].rect().index(), all.tiles[4 + i].rect().index());
    EXPECT_EQ(rest.tiles[i].exr(), all.tiles[4 + i].exr());
    EXPECT_EQ(rest.tiles[i].progress().tiles_done(), 5 + i);
  }
  EXPECT_TRUE(stream(job.id(), {}, 30s, 6).tiles.empty());
  const StreamResult beyond = stream(job.id(), {}, 30s, 7);
  EXPECT_EQ(beyond.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(beyond.status.error_message(), "after_tiles: must be at most the job's 6 tiles, got 7");
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

TEST_F(DaemonTest, ShutdownKeepsJobsForTheNextStartAndEndsTheirStreams) {
  const v1::Job job = submit_ok(long_settings(), "long");
  StreamResult result;
  std::promise<void> streaming;
  std::thread watcher([&] { result = stream(job.id(), [&] { streaming.set_value(); }); });
  // Shut down once the stream is live on the server (it has delivered a tile).
  const bool live = streaming.get_future().wait_for(30s) == std::future_status::ready;
  daemon_->shutdown();
  watcher.join();
  ASSERT_TRUE(live);
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::UNAVAILABLE)
      << result.status.error_message();
  EXPECT_NE(result.status.error_message().find("resumes when it restarts"), std::string::npos);
  daemon_->wait();      // returns at once: already stopped
  daemon_->shutdown();  // idempotent

  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + 2s);
  v1::ListJobsResponse list;
  EXPECT_FALSE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());

  // The job is still in the store, unfinished, with the tiles it had.
  daemon_.reset();
  SqliteJobStore store(data_dir_ / SqliteJobStore::kFileName);
  const auto record = store.find_job(job.id());
  ASSERT_TRUE(record);
  EXPECT_FALSE(is_finished(record->state)) << to_string(record->state);
  EXPECT_GE(record->tiles_done, result.tiles.size());
}

// A daemon started on the same data directory finishes the job; tiles stored before the
// restart are streamed from the store and not rendered again.
TEST_F(DaemonTest, ARestartedDaemonFinishesTheJob) {
  v1::RenderSettings settings = tiny_settings(64, 64, 8);  // 64 tiles
  settings.set_samples_per_pixel(64);
  const v1::Job job = submit_ok(settings, "resumed");
  std::promise<void> first_tile;
  StreamResult before;
  std::thread watcher([&] { before = stream(job.id(), [&] { first_tile.set_value(); }); });
  ASSERT_EQ(first_tile.get_future().wait_for(30s), std::future_status::ready);
  daemon_->shutdown();
  watcher.join();

  restart();
  const StreamResult after = stream(job.id());
  ASSERT_TRUE(after.status.ok()) << after.status.error_message();
  std::set<std::uint32_t> indices;
  for (const v1::Tile& tile : after.tiles) indices.insert(tile.rect().index());
  EXPECT_EQ(indices.size(), 64u);
  EXPECT_EQ(after.tiles.size(), 64u);
  EXPECT_EQ(get(job.id()).state(), v1::JOB_STATE_COMPLETED);
  daemon_.reset();
  SqliteJobStore store(data_dir_ / SqliteJobStore::kFileName);
  for (std::uint32_t i = 0; i < 64; ++i) EXPECT_EQ(store.tile_commit_count(job.id(), i), 1u) << i;
}

// Bytes that are not a protobuf message: INVALID_ARGUMENT saying so, for every method.
TEST_F(DaemonTest, MalformedRequestBytesAreInvalidArgument) {
  // A field tag followed by a length running past the end of the message.
  const std::string garbage("\x0a\xff\xff\xff\x0f\x01", 6);
  for (const char* method : {"SubmitJob", "GetJob", "ListJobs", "CancelJob", "DeleteJob"}) {
    const grpc::Status status =
        raw_unary_call(std::string("/tessera.v1.RenderService/") + method, garbage);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << method;
    EXPECT_NE(status.error_message().find("not a valid tessera.v1."), std::string::npos)
        << method << ": " << status.error_message();
  }
}

TEST_F(DaemonTest, JobIdsAreLengthLimitedAndNotEchoedRaw) {
  const std::string long_id(10'000, 'x');
  grpc::Status status;
  get(long_id, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "job_id: must be at most 64 bytes, got 10000");
  EXPECT_EQ(cancel(long_id).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(stream(long_id).status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  // A short unknown id comes back escaped: no raw newline in the message.
  get("job-1\n[critical] forged", &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(status.error_message(), "job 'job-1\\x0a[critical] forged' not found");
}

TEST_F(DaemonTest, ListJobsPagesNewestFirstAndFiltersByState) {
  std::vector<std::string> submitted;  // oldest first
  for (int i = 0; i < 5; ++i) {
    const v1::Job job = submit_ok(tiny_settings(), "done-" + std::to_string(i));
    ASSERT_TRUE(stream(job.id()).status.ok());
    submitted.push_back(job.id());
  }
  for (int i = 0; i < 2; ++i) {
    const v1::Job job = submit_ok(long_settings(), "cancelled-" + std::to_string(i));
    ASSERT_TRUE(cancel(job.id()).ok());
    submitted.push_back(job.id());
  }
  const auto list = [&](const v1::ListJobsRequest& request, grpc::Status* status = nullptr) {
    grpc::ClientContext context;
    v1::ListJobsResponse response;
    const grpc::Status s = stub_->ListJobs(&context, request, &response);
    if (status) *status = s;
    return response;
  };

  // Pages of 3: 3 + 3 + 1, newest first, each job once, the last page without a token.
  std::vector<std::string> paged;
  v1::ListJobsRequest request;
  request.set_page_size(3);
  int pages = 0;
  for (;;) {
    const v1::ListJobsResponse page = list(request);
    ++pages;
    for (const v1::Job& job : page.jobs()) paged.push_back(job.id());
    if (page.next_page_token().empty()) break;
    EXPECT_EQ(page.jobs_size(), 3);
    request.set_page_token(page.next_page_token());
  }
  EXPECT_EQ(pages, 3);
  EXPECT_EQ(paged, std::vector<std::string>(submitted.rbegin(), submitted.rend()));

  v1::ListJobsRequest by_state;
  by_state.set_state(v1::JOB_STATE_CANCELLED);
  const v1::ListJobsResponse cancelled = list(by_state);
  ASSERT_EQ(cancelled.jobs_size(), 2);
  EXPECT_EQ(cancelled.jobs(0).id(), submitted[6]);
  EXPECT_EQ(cancelled.jobs(1).id(), submitted[5]);
  by_state.set_state(v1::JOB_STATE_COMPLETED);
  EXPECT_EQ(list(by_state).jobs_size(), 5);

  grpc::Status status;
  v1::ListJobsRequest bad;
  bad.set_page_token("not-a-token\n");
  list(bad, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "page_token: not a token this server issued");
  bad.Clear();
  bad.set_state(static_cast<v1::JobState>(99));
  list(bad, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(DaemonTest, DeleteJobRemovesFinishedJobsOnly) {
  const v1::Job running = submit_ok(long_settings(), "long");
  grpc::Status status = remove(running.id());
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION) << status.error_message();
  ASSERT_TRUE(cancel(running.id()).ok());
  EXPECT_TRUE(remove(running.id()).ok());
  get(running.id(), &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(remove(running.id()).error_code(), grpc::StatusCode::NOT_FOUND);

  const v1::Job done = submit_ok(tiny_settings(), "done");
  ASSERT_TRUE(stream(done.id()).status.ok());
  EXPECT_TRUE(remove(done.id()).ok());
  EXPECT_EQ(stream(done.id()).status.error_code(), grpc::StatusCode::NOT_FOUND);
}

// max_jobs: finished jobs beyond the limit are deleted, oldest first; the unfinished one
// stays even though it is the oldest.
TEST_F(DaemonTest, RetentionDeletesTheOldestFinishedJobsOnly) {
  restart([](DaemonConfig& config) { config.max_jobs = 3; });
  const v1::Job running = submit_ok(long_settings(), "long", 10);
  std::vector<std::string> finished;
  for (int i = 0; i < 5; ++i) {
    // Lower priority than the long job, so they wait for it: raise theirs instead.
    const v1::Job job = submit_ok(tiny_settings(), "done-" + std::to_string(i), 20);
    ASSERT_TRUE(stream(job.id()).status.ok());
    finished.push_back(job.id());
  }
  // Retention runs on its own thread once a job is released; wait for it to catch up.
  grpc::Status status;
  for (int attempt = 0; attempt < 3000; ++attempt) {
    get(finished[2], &status);
    if (status.error_code() == grpc::StatusCode::NOT_FOUND) break;
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  for (int i = 0; i < 3; ++i) {
    get(finished[static_cast<std::size_t>(i)], &status);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND) << i;
  }
  for (int i = 3; i < 5; ++i) {
    get(finished[static_cast<std::size_t>(i)], &status);
    EXPECT_TRUE(status.ok()) << i;
  }
  EXPECT_EQ(get(running.id(), &status).state(), v1::JOB_STATE_RUNNING);
  EXPECT_TRUE(status.ok());
  EXPECT_TRUE(cancel(running.id()).ok());
}

// max_jobs_per_submitter caps each submitter's unfinished jobs, not anyone else's; a
// submitter without a name is known by its host.
TEST_F(DaemonTest, UnfinishedJobsArePerSubmitterCapped) {
  restart([](DaemonConfig& config) { config.max_jobs_per_submitter = 2; });
  const v1::Job first = submit_ok(long_settings(), "a1", 0, "alice");
  EXPECT_EQ(first.submitter(), "alice");
  submit_ok(long_settings(), "a2", 0, "alice");
  v1::SubmitJobRequest request;
  *request.mutable_scene() = tiny_scene();
  *request.mutable_settings() = tiny_settings();
  request.set_submitter("alice");
  grpc::Status status = submit(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(status.error_message().find("submitter 'alice'"), std::string::npos)
      << status.error_message();
  const v1::Job bobs = submit_ok(long_settings(), "b", 0, "bob");
  const v1::Job anonymous = submit_ok(tiny_settings(), "anonymous");
  EXPECT_EQ(anonymous.submitter(), "ipv4:127.0.0.1");
  ASSERT_TRUE(cancel(first.id()).ok());
  EXPECT_TRUE(submit(request).ok());  // a place freed up

  grpc::ClientContext context;
  v1::ListJobsRequest by_submitter;
  by_submitter.set_submitter("bob");
  v1::ListJobsResponse list;
  ASSERT_TRUE(stub_->ListJobs(&context, by_submitter, &list).ok());
  ASSERT_EQ(list.jobs_size(), 1);
  EXPECT_EQ(list.jobs(0).id(), bobs.id());

  request.set_submitter(std::string(129, 's'));
  status = submit(request);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "submitter: must be at most 128 bytes, got 129");
}

// SubmitJob with a request id is idempotent per submitter: the same request again returns
// the first job and creates none (also after a restart), another scene under the id is
// ALREADY_EXISTS naming the job, and a malformed id is INVALID_ARGUMENT naming the field.
TEST_F(DaemonTest, ARequestIdMakesSubmitJobIdempotent) {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = tiny_scene();
  *request.mutable_settings() = long_settings();
  request.set_name("first");
  request.set_submitter("alice");
  request.set_request_id("3f2a9c0e4b1d4c8e");
  v1::Job first;
  ASSERT_TRUE(submit(request, &first).ok());
  EXPECT_EQ(first.request_id(), "3f2a9c0e4b1d4c8e");
  const auto job_count = [&] {
    grpc::ClientContext context;
    v1::ListJobsResponse list;
    EXPECT_TRUE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());
    return list.jobs_size();
  };

  // A retry may rename; it is still the first job, as it is now.
  request.set_name("renamed by the retry");
  v1::Job again;
  ASSERT_TRUE(submit(request, &again).ok());
  EXPECT_EQ(again.id(), first.id());
  EXPECT_EQ(again.name(), "first");
  EXPECT_EQ(job_count(), 1);

  v1::SubmitJobRequest different = request;
  different.mutable_settings()->set_samples_per_pixel(2);
  grpc::Status status = submit(different);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::ALREADY_EXISTS);
  EXPECT_NE(status.error_message().find("request_id: '3f2a9c0e4b1d4c8e' already created job " +
                                        first.id()),
            std::string::npos)
      << status.error_message();
  EXPECT_EQ(job_count(), 1);

  // Another submitter's id is its own.
  v1::SubmitJobRequest bobs = request;
  bobs.set_submitter("bob");
  v1::Job bob_job;
  ASSERT_TRUE(submit(bobs, &bob_job).ok());
  EXPECT_NE(bob_job.id(), first.id());

  v1::SubmitJobRequest bad = request;
  bad.set_request_id(std::string(129, 'r'));
  status = submit(bad);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(), "request_id: must be at most 128 characters, got 129");
  bad.set_request_id("line\nbreak");
  EXPECT_EQ(submit(bad).error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  restart();
  ASSERT_TRUE(submit(request, &again).ok());
  EXPECT_EQ(again.id(), first.id());
  EXPECT_EQ(job_count(), 2);

  // Deleting the job frees its id.
  ASSERT_TRUE(cancel(first.id()).ok());
  ASSERT_TRUE(remove(first.id()).ok());
  ASSERT_TRUE(submit(request, &again).ok());
  EXPECT_NE(again.id(), first.id());
  EXPECT_TRUE(cancel(again.id()).ok());
  EXPECT_TRUE(cancel(bob_job.id()).ok());
}

// Attempts of one request that arrive together (a client's retry while its first attempt
// is still being checked) make one job between them, and each is answered with it,
// whichever attempt stored it. This is the race DaemonBudgetTest's resubmission of a
// 3-million-triangle scene provokes, on a scene small enough for `make tsan` to run.
TEST_F(DaemonTest, ConcurrentAttemptsOfOneRequestIdMakeOneJob) {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = tiny_scene();
  *request.mutable_settings() = long_settings();
  request.set_name("raced");
  request.set_submitter("alice");
  request.set_request_id("7d41c2e09a6b4f13");
  constexpr std::size_t kAttempts = 8;
  std::vector<v1::Job> jobs(kAttempts);
  std::vector<grpc::Status> statuses(kAttempts);
  std::latch all_ready(kAttempts);
  std::vector<std::thread> attempts;
  for (std::size_t i = 0; i < kAttempts; ++i)
    attempts.emplace_back([&, i] {
      all_ready.arrive_and_wait();
      statuses[i] = submit(request, &jobs[i]);
    });
  for (std::thread& attempt : attempts) attempt.join();

  for (std::size_t i = 0; i < kAttempts; ++i) {
    ASSERT_TRUE(statuses[i].ok()) << "attempt " << i << ": " << statuses[i].error_message();
    EXPECT_EQ(jobs[i].id(), jobs[0].id()) << "attempt " << i;
  }
  grpc::ClientContext context;
  v1::ListJobsResponse list;
  ASSERT_TRUE(stub_->ListJobs(&context, v1::ListJobsRequest(), &list).ok());
  EXPECT_EQ(list.jobs_size(), 1);
  EXPECT_TRUE(cancel(jobs[0].id()).ok());
}

// The GPUs the scheduler renders on follow the CPU entry, one worker each (a daemon in a
// test has none, so the answer is built directly).
TEST(ServerInfo, GpusFollowTheCpuEntry) {
  DaemonConfig config;
  config.threads = 3;
  const v1::ServerInfo info = make_server_info(config, {"gpu0 A", "gpu1 B"});
  ASSERT_EQ(info.devices_size(), 3);
  EXPECT_EQ(info.devices(0).kind(), "cpu");
  EXPECT_EQ(info.devices(0).threads(), 3u);
  EXPECT_EQ(info.devices(1).kind(), "gpu");
  EXPECT_EQ(info.devices(1).name(), "gpu0 A");
  EXPECT_EQ(info.devices(2).name(), "gpu1 B");
  EXPECT_EQ(info.devices(2).threads(), 1u);
}

// GetServerInfo reports the configured limits (not the defaults), the worker threads, the
// version, and capabilities read from the renderer's tables.
TEST_F(DaemonTest, GetServerInfoReportsVersionLimitsDevicesAndCapabilities) {
  restart([](DaemonConfig& config) {
    config.limits.max_width = 2048;
    config.limits.max_samples_per_pixel = 1024;
    config.memory_budget = std::size_t{3} << 30;
    config.max_jobs_per_submitter = 7;
    config.max_receive_message_bytes = std::size_t{64} << 20;
  });
  grpc::ClientContext context;
  v1::ServerInfo info;
  const grpc::Status status = stub_->GetServerInfo(&context, v1::GetServerInfoRequest(), &info);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(info.version(), TESSERA_VERSION);
  EXPECT_FALSE(info.build().compiler().empty());
  ASSERT_EQ(info.devices_size(), 1);
  EXPECT_EQ(info.devices(0).kind(), "cpu");
  EXPECT_EQ(info.devices(0).threads(), 2u);
  EXPECT_EQ(info.limits().max_width(), 2048u);
  EXPECT_EQ(info.limits().max_height(), SceneLimits().max_height);
  EXPECT_EQ(info.limits().max_samples_per_pixel(), 1024u);
  EXPECT_EQ(info.limits().memory_budget_bytes(), std::uint64_t{3} << 30);
  EXPECT_EQ(info.limits().max_jobs_per_submitter(), 7u);
  EXPECT_EQ(info.limits().max_receive_message_bytes(), std::uint64_t{64} << 20);
  EXPECT_EQ(info.limits().prepare_timeout_seconds(), 600.0);

  const v1::Capabilities& c = info.capabilities();
  EXPECT_EQ(static_cast<std::size_t>(c.integrators_size()), integrator_names().size());
  EXPECT_EQ(static_cast<std::size_t>(c.material_types_size()), material_type_names().size());
  EXPECT_EQ(static_cast<std::size_t>(c.aovs_size()), aov_names().size());
  const auto has = [](const auto& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  EXPECT_TRUE(has(c.integrators(), "path"));
  EXPECT_TRUE(has(c.samplers(), "sobol"));
  EXPECT_TRUE(has(c.light_strategies(), "mis"));
  EXPECT_TRUE(has(c.material_types(), "glass"));
  EXPECT_TRUE(has(c.pixel_filters(), "blackman_harris"));
  EXPECT_TRUE(has(c.texture_types(), "checker"));
  EXPECT_EQ(std::vector<std::string>(c.accel_builders().begin(), c.accel_builders().end()),
            (std::vector<std::string>{"auto", "spatial", "binned"}));
  // Every shape of the API's Geometry oneof, and nothing else.
  const auto* shape = v1::Geometry::descriptor()->FindOneofByName("shape");
  ASSERT_NE(shape, nullptr);
  ASSERT_EQ(c.geometry_kinds_size(), shape->field_count());
  for (int i = 0; i < shape->field_count(); ++i)
    EXPECT_TRUE(has(c.geometry_kinds(), shape->field(i)->name())) << shape->field(i)->name();
  EXPECT_TRUE(c.progressive_passes());
  EXPECT_TRUE(c.idempotent_submit());
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
