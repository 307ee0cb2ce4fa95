// Job control (PauseJob, ResumeJob, RetryJob, UpdateJob, label filters) and WatchJobs on an
// in-process daemon, through tessera::Client as a user's program would call them.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <future>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "client/client.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "server/daemon.hpp"
#include "server/sqlite_job_store.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tests/support/loopback_daemon_config.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;
using test::cornell;

bool finished(v1::JobState state) {
  return state == v1::JOB_STATE_COMPLETED || state == v1::JOB_STATE_FAILED ||
         state == v1::JOB_STATE_CANCELLED;
}

class JobControlTest : public ::testing::Test {
 protected:
  void SetUp() override { data_dir_ = test::make_test_dir("tesserad"); }
  void TearDown() override {
    client_.reset();
    daemon_.reset();
    std::filesystem::remove_all(data_dir_);
  }

  void start(const std::function<void(server::DaemonConfig&)>& adjust = {}) {
    client_.reset();
    daemon_.reset();
    server::DaemonConfig config = test::loopback_daemon_config(data_dir_, 2);
    if (adjust) adjust(config);
    daemon_ = std::make_unique<server::Daemon>(config);
    daemon_->start();
    client_ = std::make_unique<Client>(ClientOptions{.target = daemon_->address()});
  }

  v1::Job submit(const SceneDescription& scene, const std::string& name, int priority = 0,
                 const std::map<std::string, std::string>& labels = {}) {
    v1::SubmitJobRequest request = make_submit_request(scene, name, priority);
    for (const auto& [key, value] : labels) (*request.mutable_labels())[key] = value;
    request.set_submitter("tests");
    return client_->submit(request);
  }

  // Polls until `done(job)` holds; fails the test after 60 s.
  v1::Job wait_until(const std::string& id, const std::function<bool(const v1::Job&)>& done) {
    const auto give_up = std::chrono::steady_clock::now() + 60s;
    for (;;) {
      const v1::Job job = client_->get(id);
      if (done(job) || std::chrono::steady_clock::now() > give_up) return job;
      std::this_thread::sleep_for(2ms);
    }
  }

  // Every tile of the job, placed in one RGBA image; `times_seen` counts each tile.
  std::vector<float> stream_image(const std::string& id, std::vector<int>* times_seen = nullptr) {
    const v1::Job job = client_->get(id);
    const v1::RenderSettings& s = job.settings();
    std::vector<float> image(static_cast<std::size_t>(s.width()) * s.height() * 4, -1.0f);
    std::vector<int> seen(job.progress().tiles_total(), 0);
    client_->stream_tiles(id, [&](const v1::Tile& tile) {
      const v1::TileRect& r = tile.rect();
      ++seen.at(r.index());
      const RgbaImage pixels = decode_exr(
          std::span(reinterpret_cast<const std::uint8_t*>(tile.exr().data()), tile.exr().size()));
      for (std::uint32_t row = 0; row < r.height(); ++row)
        std::memcpy(&image[((r.y() + row) * s.width() + r.x()) * 4],
                    &pixels.pixels[row * r.width() * 4], r.width() * 4 * sizeof(float));
    });
    if (times_seen) *times_seen = seen;
    return image;
  }

  std::filesystem::path data_dir_;
  std::unique_ptr<server::Daemon> daemon_;
  std::unique_ptr<Client> client_;
};

bool bit_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::vector<std::string> names_of(const std::vector<v1::Job>& jobs) {
  std::vector<std::string> names;
  for (const v1::Job& job : jobs) names.push_back(job.name());
  return names;
}

// A paused job takes no new tiles (those in flight may land), keeps what it has, and after
// resume finishes with the image an uninterrupted render gives, bit for bit.
TEST_F(JobControlTest, PauseStopsNewTilesAndResumeFinishesTheSameImage) {
  start();
  const SceneDescription scene = cornell(128, 128, 64, 16);  // 64 tiles
  const v1::Job job = submit(scene, "paused");
  wait_until(job.id(), [](const v1::Job& j) { return j.progress().tiles_done() >= 2; });
  const v1::Job paused = client_->pause(job.id());
  EXPECT_EQ(paused.state(), v1::JOB_STATE_PAUSED);
  // Pausing again answers with the job as it is.
  EXPECT_EQ(client_->pause(job.id()).state(), v1::JOB_STATE_PAUSED);

  // Tiles in flight when it was paused (at most one per worker) may still land; then none.
  std::this_thread::sleep_for(500ms);
  const std::uint32_t settled = client_->get(job.id()).progress().tiles_done();
  EXPECT_LE(settled, paused.progress().tiles_done() + 2);
  std::this_thread::sleep_for(1s);
  const v1::Job still = client_->get(job.id());
  EXPECT_EQ(still.state(), v1::JOB_STATE_PAUSED);
  EXPECT_EQ(still.progress().tiles_done(), settled);
  ASSERT_LT(settled, 64u) << "the job finished before it could be paused";
  std::cout << "paused at " << paused.progress().tiles_done() << "/64 tiles; "
            << settled - paused.progress().tiles_done() << " in flight landed after the pause\n";

  EXPECT_EQ(client_->resume(job.id()).state(), v1::JOB_STATE_QUEUED);
  std::vector<int> seen;
  const std::vector<float> image = stream_image(job.id(), &seen);
  EXPECT_EQ(client_->get(job.id()).state(), v1::JOB_STATE_COMPLETED);
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "tile " << i;
  EXPECT_TRUE(bit_equal(image, render_image(*PreparedScene::build(scene))));

  // A finished job can be neither paused nor resumed.
  try {
    client_->pause(job.id());
    ADD_FAILURE() << "pausing a completed job succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.message();
  }
  try {
    client_->resume(job.id());
    ADD_FAILURE() << "resuming a completed job succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.message();
  }
  client_.reset();
  daemon_.reset();
  server::SqliteJobStore store(data_dir_ / server::SqliteJobStore::kFileName);
  for (std::uint32_t i = 0; i < 64; ++i)
    EXPECT_EQ(store.tile_commit_count(job.id(), i), 1u) << "tile " << i;
}

// A cancelled job retried keeps its tiles: only the missing ones are rendered (the store
// counts one commit per tile), and the image is the uninterrupted one.
TEST_F(JobControlTest, RetryRendersOnlyTheMissingTiles) {
  start();
  const SceneDescription scene = cornell(128, 128, 64, 16);  // 64 tiles
  const v1::Job job = submit(scene, "retried");
  wait_until(job.id(), [](const v1::Job& j) { return j.progress().tiles_done() >= 3; });
  client_->cancel(job.id());
  const v1::Job cancelled =
      wait_until(job.id(), [](const v1::Job& j) { return finished(j.state()); });
  ASSERT_EQ(cancelled.state(), v1::JOB_STATE_CANCELLED);
  const std::uint32_t kept = cancelled.progress().tiles_done();
  ASSERT_LT(kept, 64u);

  const v1::Job retried = client_->retry(job.id());
  EXPECT_EQ(retried.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(retried.progress().tiles_done(), kept);
  EXPECT_EQ(retried.error(), "");
  std::vector<int> seen;
  const std::vector<float> image = stream_image(job.id(), &seen);
  EXPECT_EQ(client_->get(job.id()).state(), v1::JOB_STATE_COMPLETED);
  EXPECT_TRUE(bit_equal(image, render_image(*PreparedScene::build(scene))));

  // Only failed and cancelled jobs are retried.
  try {
    client_->retry(job.id());
    ADD_FAILURE() << "retrying a completed job succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::FAILED_PRECONDITION) << e.message();
  }
  client_.reset();
  daemon_.reset();
  server::SqliteJobStore store(data_dir_ / server::SqliteJobStore::kFileName);
  for (std::uint32_t i = 0; i < 64; ++i)
    EXPECT_EQ(store.tile_commit_count(job.id(), i), 1u) << "tile " << i;
}

// One worker busy with a long job; of two small jobs queued behind it, the one raised by
// UpdateJob runs first: it completes while the other has not started.
TEST_F(JobControlTest, UpdatingThePriorityReordersTheQueue) {
  start([](server::DaemonConfig& c) { c.threads = 1; });
  const v1::Job blocker = submit(cornell(128, 128, 256, 16), "blocker");
  const v1::Job first = submit(cornell(32, 32, 4, 16), "first");
  const v1::Job second = submit(cornell(32, 32, 4, 16), "second");
  wait_until(blocker.id(), [](const v1::Job& j) { return j.progress().tiles_done() >= 1; });

  v1::UpdateJobRequest raise;
  raise.set_job_id(second.id());
  raise.set_priority(5);
  const v1::Job raised = client_->update(raise);
  EXPECT_EQ(raised.priority(), 5);

  const v1::Job second_done =
      wait_until(second.id(), [](const v1::Job& j) { return finished(j.state()); });
  EXPECT_EQ(second_done.state(), v1::JOB_STATE_COMPLETED);
  const v1::Job first_now = client_->get(first.id());
  EXPECT_EQ(first_now.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(first_now.progress().tiles_done(), 0u);
  EXPECT_NE(client_->get(blocker.id()).state(), v1::JOB_STATE_COMPLETED)
      << "the blocker finished before the raised job could overtake it; make it longer";
  client_->cancel(blocker.id());
}

// A retried job is unfinished again: it counts against its submitter's cap.
TEST_F(JobControlTest, RetryRespectsThePerSubmitterCap) {
  start([](server::DaemonConfig& c) { c.max_jobs_per_submitter = 1; });
  const v1::Job first = submit(cornell(128, 128, 256, 16), "first");
  client_->cancel(first.id());
  const v1::Job second = submit(cornell(128, 128, 256, 16), "second");
  try {
    client_->retry(first.id());
    ADD_FAILURE() << "a retry passed the cap";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << e.message();
    EXPECT_NE(e.message().find("max_jobs_per_submitter"), std::string::npos) << e.message();
  }
  EXPECT_EQ(client_->get(first.id()).state(), v1::JOB_STATE_CANCELLED);
  client_->cancel(second.id());
  EXPECT_EQ(client_->retry(first.id()).state(), v1::JOB_STATE_QUEUED);
  client_->cancel(first.id());
}

TEST_F(JobControlTest, LabelsAreStoredUpdatedAndFilterListJobs) {
  start();
  const SceneDescription scene = cornell(16, 16, 1, 16);
  submit(scene, "a", 0, {{"shot", "010"}, {"dept", "fx"}});
  submit(scene, "b", 0, {{"shot", "020"}});
  const v1::Job c = submit(scene, "c");

  const auto list = [&](const std::string& label, const std::string& name = "") {
    v1::ListJobsRequest request;
    request.set_label(label);
    request.set_name(name);
    return names_of(client_->list(request));
  };
  EXPECT_EQ(list("shot=010"), (std::vector<std::string>{"a"}));
  EXPECT_EQ(list("shot"), (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(list("dept=lighting"), (std::vector<std::string>{}));
  EXPECT_EQ(list("", "b"), (std::vector<std::string>{"b"}));
  EXPECT_EQ(list("shot", "b"), (std::vector<std::string>{"b"}));

  v1::UpdateJobRequest update;
  update.set_job_id(c.id());
  (*update.mutable_set_labels())["shot"] = "010";
  update.set_submitter("someone-else");
  const v1::Job updated = client_->update(update);
  EXPECT_EQ(updated.labels().at("shot"), "010");
  EXPECT_EQ(updated.submitter(), "someone-else");
  EXPECT_EQ(list("shot=010"), (std::vector<std::string>{"c", "a"}));
  EXPECT_EQ(client_->get(c.id()).labels().at("shot"), "010");

  v1::UpdateJobRequest remove;
  remove.set_job_id(c.id());
  remove.add_remove_labels("shot");
  EXPECT_EQ(client_->update(remove).labels_size(), 0);
  EXPECT_EQ(list("shot=010"), (std::vector<std::string>{"a"}));

  // Bad labels and filters are refused naming the field.
  const auto expect_invalid = [](const std::function<void()>& call, const std::string& field) {
    try {
      call();
      ADD_FAILURE() << "accepted a bad " << field;
    } catch (const ClientError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT) << e.message();
      EXPECT_EQ(e.message().rfind(field, 0), 0u) << e.message();
    }
  };
  expect_invalid([&] { submit(scene, "bad", 0, {{"has space", "x"}}); }, "labels");
  expect_invalid([&] { submit(scene, "bad", 0, {{"k", "line\nbreak"}}); }, "labels");
  expect_invalid([&] { list("=x"); }, "label");
  v1::UpdateJobRequest bad;
  bad.set_job_id(c.id());
  bad.set_submitter(std::string(129, 's'));
  expect_invalid([&] { client_->update(bad); }, "submitter");
  v1::UpdateJobRequest too_many;
  too_many.set_job_id(c.id());
  for (int i = 0; i < 65; ++i)
    (*too_many.mutable_set_labels())[std::string("k") + std::to_string(i)] = "v";
  expect_invalid([&] { client_->update(too_many); }, "set_labels");
}

// Collects WatchJobs events on a thread until the watch ends (the daemon shuts down: call
// Daemon::shutdown() before an EventLog goes out of scope).
class EventLog {
 public:
  EventLog(Client& client, v1::WatchJobsRequest request) {
    thread_ = std::thread([this, &client, request] {
      try {
        client.watch_jobs(request, [this](const v1::JobEvent& event) {
          std::lock_guard lock(mutex_);
          events_.push_back(event);
          return !stop_;
        });
      } catch (const ClientError& e) {
        std::lock_guard lock(mutex_);
        error_ = e.message();
      }
    });
  }
  ~EventLog() {
    stop_ = true;
    thread_.join();
  }
  std::vector<v1::JobEvent> events() const {
    std::lock_guard lock(mutex_);
    return events_;
  }
  // Waits until `done(events)` holds (60 s at most).
  std::vector<v1::JobEvent> wait(
      const std::function<bool(const std::vector<v1::JobEvent>&)>& done) {
    const auto give_up = std::chrono::steady_clock::now() + 60s;
    for (;;) {
      auto now = events();
      if (done(now) || std::chrono::steady_clock::now() > give_up) return now;
      std::this_thread::sleep_for(5ms);
    }
  }

 private:
  mutable std::mutex mutex_;
  std::vector<v1::JobEvent> events_;
  std::string error_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST_F(JobControlTest, WatchJobsStartsWithTheCurrentStateThenSeesEachChangeInOrder) {
  start();
  // A paused job exists before the watch begins: the snapshot must show it.
  const v1::Job parked = submit(cornell(64, 64, 64, 16), "parked");
  client_->pause(parked.id());
  EventLog log(*client_, {});
  log.wait([](const auto& events) { return !events.empty(); });

  const v1::Job job = submit(cornell(32, 32, 4, 16), "watched");
  const auto states_of = [&](const std::vector<v1::JobEvent>& events, const std::string& id) {
    std::vector<v1::JobState> states;
    for (const v1::JobEvent& event : events)
      if (event.job().id() == id && !event.snapshot()) states.push_back(event.job().state());
    return states;
  };
  const auto events = log.wait([&](const auto& now) {
    const auto states = states_of(now, job.id());
    return !states.empty() && finished(states.back());
  });
  ASSERT_FALSE(events.empty());
  EXPECT_TRUE(events.front().snapshot());
  EXPECT_EQ(events.front().job().id(), parked.id());
  EXPECT_EQ(events.front().job().state(), v1::JOB_STATE_PAUSED);
  EXPECT_EQ(states_of(events, job.id()),
            (std::vector<v1::JobState>{v1::JOB_STATE_QUEUED, v1::JOB_STATE_RUNNING,
                                       v1::JOB_STATE_COMPLETED}));

  // Filtered by job: that job's snapshot, then its changes only; deletion is an event too.
  v1::WatchJobsRequest one;
  one.set_job_id(parked.id());
  EventLog parked_log(*client_, one);
  parked_log.wait([](const auto& now) { return !now.empty(); });
  client_->cancel(parked.id());
  client_->remove(parked.id());
  const auto parked_events =
      parked_log.wait([](const auto& now) { return !now.empty() && now.back().deleted(); });
  std::vector<std::pair<v1::JobState, bool>> seen;
  for (const v1::JobEvent& event : parked_events) {
    EXPECT_EQ(event.job().id(), parked.id());
    seen.emplace_back(event.job().state(), event.deleted());
  }
  EXPECT_EQ(seen, (std::vector<std::pair<v1::JobState, bool>>{{v1::JOB_STATE_PAUSED, false},
                                                              {v1::JOB_STATE_CANCELLED, false},
                                                              {v1::JOB_STATE_CANCELLED, true}}));
  daemon_->shutdown();  // ends both watches
}

// A client that opens a watch and never reads: once a write to it has waited longer than
// watch_write_timeout the daemon drops the watcher, and its handler thread returns.
TEST_F(JobControlTest, AWatcherThatDoesNotReadIsDropped) {
  start([](server::DaemonConfig& c) {
    c.watch_write_timeout = 300ms;
    c.watch_buffer = 4096;
  });
  const v1::Job job = submit(cornell(16, 16, 1, 16), "noisy");
  auto channel = make_channel(daemon_->address());
  auto stub = v1::RenderService::NewStub(channel);
  grpc::ClientContext context;
  v1::WatchJobsRequest request;
  auto reader = stub->WatchJobs(&context, request);  // never read until the end
  const auto give_up = std::chrono::steady_clock::now() + 60s;
  while (daemon_->watcher_count() == 0 && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(5ms);
  ASSERT_EQ(daemon_->watcher_count(), 1u);

  // Each update is an event of about 20 KB (64 labels of 256 bytes), so the transport's
  // buffers fill after a few hundred and the daemon's write to this watcher blocks.
  v1::UpdateJobRequest update;
  update.set_job_id(job.id());
  for (int i = 0; i < 64; ++i)
    (*update.mutable_set_labels())[std::string("k") + std::to_string(i)] = std::string(256, 'x');
  int updates = 0;
  while (daemon_->watcher_count() > 0 && std::chrono::steady_clock::now() < give_up) {
    update.set_priority(updates++ % 3);
    client_->update(update);
  }
  EXPECT_EQ(daemon_->watcher_count(), 0u) << "still watching after " << updates << " updates";
  std::cout << "watcher dropped after " << updates << " updates\n";
  // The daemon still serves others.
  EXPECT_EQ(client_->get(job.id()).id(), job.id());
  context.TryCancel();
  v1::JobEvent event;
  while (reader->Read(&event)) {
  }
  EXPECT_FALSE(reader->Finish().ok());
}

}  // namespace
}  // namespace tessera
