// tesserad as a separate process, killed and restarted the way a machine or an operator
// would: kill -9 at random points of a job, SIGTERM mid-job, a cancel of a tile far too big
// to finish. What must hold: nothing acknowledged is lost, no stored tile is rendered
// again (the store counts every commit of a tile), and the image equals a local render
// bit for bit.
#include <fcntl.h>
#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include "cornell_scene.hpp"
#include "tesserad_process.hpp"

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <thread>

#include "client/client.hpp"
#include "convert/scene_proto.hpp"
#include "server/sqlite_job_store.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;
using server::SqliteJobStore;

using test::cornell;
using test::kCornell;
using test::TesseradProcess;

// What the stream of a job delivered, assembled into an image.
struct Streamed {
  std::vector<float> image;
  std::vector<int> times_seen;
};

Streamed stream_all(Client& client, const v1::Job& job) {
  const v1::RenderSettings& s = job.settings();
  Streamed result;
  result.image.assign(static_cast<std::size_t>(s.width()) * s.height() * 4, -1.0f);
  result.times_seen.assign(make_tiles(s.width(), s.height(), s.tile_size()).size(), 0);
  client.stream_tiles(job.id(), [&](const v1::Tile& tile) {
    const v1::TileRect& r = tile.rect();
    ++result.times_seen.at(r.index());
    const RgbaImage pixels = decode_exr(
        std::span(reinterpret_cast<const std::uint8_t*>(tile.exr().data()), tile.exr().size()));
    for (std::uint32_t row = 0; row < r.height(); ++row)
      std::memcpy(&result.image[((r.y() + row) * s.width() + r.x()) * 4],
                  &pixels.pixels[row * r.width() * 4], r.width() * 4 * sizeof(float));
  });
  return result;
}

bool bit_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

class DaemonProcessTest : public test::TesseradDirTest {
 protected:
  std::filesystem::path store_file() const { return data() / SqliteJobStore::kFileName; }

  // The job as the store holds it, read while no daemon runs.
  server::JobRecord stored(const std::string& id) const {
    SqliteJobStore store(store_file());
    const auto record = store.find_job(id);
    if (!record) throw std::runtime_error("job " + id + " is not in the store");
    return *record;
  }

  // Every tile of the job is stored and was committed exactly once.
  void expect_every_tile_committed_once(const std::string& id, std::uint32_t tiles) const {
    SqliteJobStore store(store_file());
    for (std::uint32_t i = 0; i < tiles; ++i)
      EXPECT_EQ(store.tile_commit_count(id, i), 1u) << "tile " << i;
  }
};

// Polls until the job has at least `tiles` stored tiles (or has finished).
v1::Job wait_for_tiles(Client& client, const std::string& id, std::uint32_t tiles) {
  for (;;) {
    const v1::Job job = client.get(id);
    if (job.progress().tiles_done() >= tiles || job.state() == v1::JOB_STATE_COMPLETED ||
        job.state() == v1::JOB_STATE_FAILED || job.state() == v1::JOB_STATE_CANCELLED)
      return job;
    std::this_thread::sleep_for(2ms);
  }
}

TEST_F(DaemonProcessTest, KillNineAtRandomPointsLosesNothingAndRendersNoTileTwice) {
  const SceneDescription scene = cornell(128, 128, 16, 16);  // 64 tiles
  const std::uint32_t tiles = 64;
  const unsigned seed = std::random_device{}();
  std::mt19937 rng(seed);
  RecordProperty("seed", static_cast<int>(seed));
  SCOPED_TRACE("random seed " + std::to_string(seed));

  std::string id;
  int kills_mid_job = 0;
  {
    auto daemon = std::make_unique<TesseradProcess>(data(), log());
    auto client = std::make_unique<Client>(ClientOptions{.target = daemon->address()});
    id = client->submit(make_submit_request(scene, "survivor", 0)).id();
    std::uint32_t done = 0;
    for (int round = 0; round < 4; ++round) {
      if (round == 2) {
        // At a random instant just after a start: while the job is being resumed.
        std::this_thread::sleep_for(std::chrono::milliseconds(rng() % 40));
      } else {
        // At a random point of the job: once a random number more tiles are stored, plus a
        // random few milliseconds, so the kill lands anywhere in a tile's life.
        const std::uint32_t target = done + 1 + rng() % 8;
        wait_for_tiles(*client, id, target);
        std::this_thread::sleep_for(std::chrono::microseconds(rng() % 20'000));
      }
      daemon->kill_now();
      const server::JobRecord record = stored(id);
      done = record.tiles_done;
      if (done > 0 && done < tiles) ++kills_mid_job;
      EXPECT_FALSE(server::is_finished(record.state) && done < tiles);
      std::cout << "kill -9 " << round + 1 << ": " << done << "/" << tiles << " tiles stored\n";
      daemon = std::make_unique<TesseradProcess>(data(), log());
      client = std::make_unique<Client>(ClientOptions{.target = daemon->address()});
    }
    const Streamed streamed = stream_all(*client, client->get(id));
    EXPECT_EQ(client->get(id).state(), v1::JOB_STATE_COMPLETED);
    for (std::size_t i = 0; i < streamed.times_seen.size(); ++i)
      EXPECT_EQ(streamed.times_seen[i], 1) << "tile " << i;
    EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(scene))));
    EXPECT_EQ(daemon->terminate(), 0);
  }
  EXPECT_GE(kills_mid_job, 2);
  expect_every_tile_committed_once(id, tiles);
}

// The same with progressive passes: each pass of a tile is a stored unit and the tile's
// accumulated state is stored with it, so kills between and inside passes must neither lose
// a pass nor render one twice, and the final pass must still equal the one-pass local render
// bit for bit.
TEST_F(DaemonProcessTest, KillNineDuringAJobWithPassesRendersNoPassTwice) {
  constexpr std::uint32_t kTiles = 64, kPasses = 4, kUnits = kTiles * kPasses;
  SceneDescription scene = cornell(128, 128, 16, 16);  // 64 tiles, 4 spp per pass
  scene.render.passes = kPasses;
  const unsigned seed = std::random_device{}();
  std::mt19937 rng(seed);
  RecordProperty("seed", static_cast<int>(seed));
  SCOPED_TRACE("random seed " + std::to_string(seed));

  std::string id;
  int kills_mid_job = 0;
  {
    auto daemon = std::make_unique<TesseradProcess>(data(), log());
    auto client = std::make_unique<Client>(ClientOptions{.target = daemon->address()});
    id = client->submit(make_submit_request(scene, "passes", 0)).id();
    std::uint32_t done = 0;
    for (int round = 0; round < 4; ++round) {
      // Spread over the passes (64 tile passes each), inside and across their boundaries.
      const std::uint32_t target = done + 10 + rng() % 50;
      wait_for_tiles(*client, id, target);
      std::this_thread::sleep_for(std::chrono::microseconds(rng() % 20'000));
      daemon->kill_now();
      const server::JobRecord record = stored(id);
      done = record.tiles_done;
      if (done > 0 && done < kUnits) ++kills_mid_job;
      std::cout << "kill -9 " << round + 1 << ": " << done << "/" << kUnits
                << " tile passes stored\n";
      daemon = std::make_unique<TesseradProcess>(data(), log());
      client = std::make_unique<Client>(ClientOptions{.target = daemon->address()});
    }
    // Every pass of every tile, each once and in order; the last pass is the final image.
    std::vector<std::uint32_t> last_pass(kTiles, 0);
    std::vector<float> image(128 * 128 * 4, -1.0f);
    client->stream_tiles(id, [&](const v1::Tile& tile) {
      const v1::TileRect& r = tile.rect();
      EXPECT_EQ(tile.pass_index(), last_pass.at(r.index()) + 1) << "tile " << r.index();
      last_pass.at(r.index()) = tile.pass_index();
      if (tile.pass_index() != kPasses) return;
      const RgbaImage pixels = decode_exr(
          std::span(reinterpret_cast<const std::uint8_t*>(tile.exr().data()), tile.exr().size()));
      for (std::uint32_t row = 0; row < r.height(); ++row)
        std::memcpy(&image[((r.y() + row) * 128 + r.x()) * 4], &pixels.pixels[row * r.width() * 4],
                    r.width() * 4 * sizeof(float));
    });
    EXPECT_EQ(client->get(id).state(), v1::JOB_STATE_COMPLETED);
    for (std::uint32_t i = 0; i < kTiles; ++i) EXPECT_EQ(last_pass[i], kPasses) << "tile " << i;
    SceneDescription one_pass = scene;
    one_pass.render.passes = 1;
    EXPECT_TRUE(bit_equal(image, render_image(*PreparedScene::build(one_pass))));
    EXPECT_EQ(daemon->terminate(), 0);
  }
  EXPECT_GE(kills_mid_job, 2);
  expect_every_tile_committed_once(id, kUnits);
  SqliteJobStore store(store_file());
  for (std::uint32_t tile = 0; tile < kTiles; ++tile)
    EXPECT_FALSE(store.tile_pass_state(id, tile).has_value()) << "tile " << tile;
}

TEST_F(DaemonProcessTest, SigtermMidJobExitsCleanlyAndARestartCompletesTheJob) {
  const SceneDescription scene = cornell(64, 64, 16, 16);  // 16 tiles
  std::string id;
  {
    TesseradProcess daemon(data(), log());
    Client client(ClientOptions{.target = daemon.address()});
    id = client.submit(make_submit_request(scene, "stopped", 0)).id();
    wait_for_tiles(client, id, 3);
    const auto signalled = std::chrono::steady_clock::now();
    EXPECT_EQ(daemon.terminate(), 0);
    std::cout << "SIGTERM mid-job to exit: "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count()
              << " s\n";
  }
  const server::JobRecord record = stored(id);
  EXPECT_FALSE(server::is_finished(record.state)) << server::to_string(record.state);
  EXPECT_GE(record.tiles_done, 3u);
  {
    TesseradProcess daemon(data(), log());
    Client client(ClientOptions{.target = daemon.address()});
    const Streamed streamed = stream_all(client, client.get(id));
    EXPECT_EQ(client.get(id).state(), v1::JOB_STATE_COMPLETED);
    EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(scene))));
    EXPECT_EQ(daemon.terminate(), 0);
  }
  expect_every_tile_committed_once(id, 16);
  std::ifstream in(log());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("resuming 1 unfinished jobs"), std::string::npos) << text;
}

// A client streaming a job while the daemon restarts (SIGTERM, then a new process on the
// same port) re-attaches after the tiles it has and receives every tile exactly once.
TEST_F(DaemonProcessTest, AStreamReattachesAcrossADaemonRestart) {
  const SceneDescription scene = cornell(64, 64, 16, 16);  // 16 tiles
  auto daemon = std::make_unique<TesseradProcess>(data(), log());
  const std::string address = daemon->address();
  Client client(ClientOptions{.target = address});
  const v1::Job job = client.submit(make_submit_request(scene, "watched", 0));
  Streamed streamed;
  std::string stream_error;
  std::thread watcher([&] {
    try {
      streamed = stream_all(client, job);
    } catch (const std::exception& e) {
      stream_error = e.what();
    }
  });
  wait_for_tiles(client, job.id(), 3);
  EXPECT_EQ(daemon->terminate(), 0);
  daemon = std::make_unique<TesseradProcess>(data(), log(), 2, address);
  watcher.join();
  EXPECT_EQ(stream_error, "");
  for (std::size_t i = 0; i < streamed.times_seen.size(); ++i)
    EXPECT_EQ(streamed.times_seen[i], 1) << "tile " << i;
  EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(scene))));
  EXPECT_EQ(daemon->terminate(), 0);
}

// One worker, busy with a single 1024x1024 tile at 65,536 spp (hours of work). After a
// cancel, a small job must get that worker: it can only if the cancel reached the tile.
TEST_F(DaemonProcessTest, CancellingAHugeRunningTileFreesTheWorker) {
  TesseradProcess daemon(data(), log(), 1);
  Client client(ClientOptions{.target = daemon.address()});
  const v1::Job huge =
      client.submit(make_submit_request(cornell(1024, 1024, 65536, 1024), "huge", 0));
  while (client.get(huge.id()).state() != v1::JOB_STATE_RUNNING) std::this_thread::sleep_for(5ms);
  std::this_thread::sleep_for(200ms);  // well into the tile

  const auto cancelled_at = std::chrono::steady_clock::now();
  EXPECT_EQ(client.cancel(huge.id()).state(), v1::JOB_STATE_CANCELLED);
  const SceneDescription small = cornell(32, 32, 1, 16);
  const v1::Job next = client.submit(make_submit_request(small, "next", 0));
  const Streamed streamed = stream_all(client, next);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - cancelled_at).count();
  EXPECT_EQ(client.get(next.id()).state(), v1::JOB_STATE_COMPLETED);
  EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(small))));
  std::cout << "from the cancel of the huge tile to the next job's completion: " << seconds
            << " s\n";
  RecordProperty("seconds_from_cancel_to_next_job_done", std::to_string(seconds));
  EXPECT_EQ(daemon.terminate(), 0);
}

// A job name carrying a newline and a fake log header must stay inside its own log line.
TEST_F(DaemonProcessTest, AJobNameCannotForgeALogLine) {
  {
    TesseradProcess daemon(data(), log());
    Client client(ClientOptions{.target = daemon.address()});
    const std::string forged = "x\n[2001-01-01 00:00:00.000] [tesserad] [critical] forged";
    const v1::Job job = client.submit(make_submit_request(cornell(16, 16, 1, 16), forged, 0));
    stream_all(client, job);
    EXPECT_EQ(client.get(job.id()).name(), forged);  // stored as given, escaped only in logs
    EXPECT_EQ(daemon.terminate(), 0);
  }
  std::ifstream in(log());
  std::string line;
  bool found_escaped = false;
  while (std::getline(in, line)) {
    EXPECT_NE(line.rfind("[2001-01-01", 0), 0u) << "forged line: " << line;
    if (line.find("x\\x0a[2001-01-01") != std::string::npos) found_escaped = true;
  }
  EXPECT_TRUE(found_escaped);
}

// A paused job is still paused after a SIGTERM and a restart (no worker takes its tiles),
// and after ResumeJob completes with the image of an uninterrupted render, every tile
// committed once.
TEST_F(DaemonProcessTest, APausedJobStaysPausedAcrossARestartAndCompletesAfterResume) {
  const SceneDescription scene = cornell(128, 128, 64, 16);  // 64 tiles, a few seconds
  std::string id;
  std::uint32_t kept = 0;
  {
    TesseradProcess daemon(data(), log());
    Client client(ClientOptions{.target = daemon.address()});
    id = client.submit(make_submit_request(scene, "parked", 0)).id();
    wait_for_tiles(client, id, 2);
    EXPECT_EQ(client.pause(id).state(), v1::JOB_STATE_PAUSED);
    EXPECT_EQ(daemon.terminate(), 0);
  }
  {
    const server::JobRecord record = stored(id);
    EXPECT_EQ(record.state, server::JobState::kPaused) << server::to_string(record.state);
    kept = record.tiles_done;
    ASSERT_LT(kept, 64u) << "the job finished before it was paused";
  }
  {
    TesseradProcess daemon(data(), log());
    Client client(ClientOptions{.target = daemon.address()});
    // A restarted daemon does not run it: still paused, no tile added, after a while.
    std::this_thread::sleep_for(1s);
    const v1::Job after_restart = client.get(id);
    EXPECT_EQ(after_restart.state(), v1::JOB_STATE_PAUSED);
    EXPECT_EQ(after_restart.progress().tiles_done(), kept);
    EXPECT_EQ(client.resume(id).state(), v1::JOB_STATE_QUEUED);
    const Streamed streamed = stream_all(client, client.get(id));
    EXPECT_EQ(client.get(id).state(), v1::JOB_STATE_COMPLETED);
    for (std::size_t i = 0; i < streamed.times_seen.size(); ++i)
      EXPECT_EQ(streamed.times_seen[i], 1) << "tile " << i;
    EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(scene))));
    EXPECT_EQ(daemon.terminate(), 0);
  }
  expect_every_tile_committed_once(id, 64);
}

}  // namespace
}  // namespace tessera
