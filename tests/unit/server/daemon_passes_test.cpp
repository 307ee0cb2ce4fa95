// Progressive passes and stream delivery through an in-process daemon: each pass of each
// tile is delivered exactly once and in pass order, the last pass equals the one-pass
// render bit for bit, re-attaching from a sequence number delivers only what follows, the
// accumulated state does not outlive the job, and a reader that never reads is cut off
// after the stream write timeout without holding a thread or stalling the workers.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <thread>

#include "server/daemon.hpp"
#include "server/sqlite_job_store.hpp"
#include "server/tile_state_codec.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/v1/render.grpc.pb.h"
#include "test_scenes.hpp"
#include "tests/support/loopback_daemon_config.hpp"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
using testing::tiny_scene;
using testing::tiny_settings;

// Every channel's floats of a tile's EXR, as bits (the file itself carries a capture date).
std::vector<std::uint32_t> tile_bits(const std::string& exr) {
  const std::vector<std::uint8_t> bytes(exr.begin(), exr.end());
  const ChannelImage image = decode_exr_channels(bytes);
  std::vector<std::uint32_t> bits(image.pixels.size());
  std::memcpy(bits.data(), image.pixels.data(), bits.size() * sizeof(float));
  return bits;
}

struct Delivered {
  std::vector<v1::Tile> tiles;
  grpc::Status status;
};

class DaemonPassesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    data_dir_ = std::filesystem::temp_directory_path() /
                ("tesserad-passes-test-" + std::to_string(::getpid()));
    std::filesystem::remove_all(data_dir_);
    start();
  }
  void TearDown() override {
    daemon_.reset();
    std::filesystem::remove_all(data_dir_);
  }

  void start(std::chrono::milliseconds write_timeout = 30s) {
    daemon_.reset();
    DaemonConfig config = test::loopback_daemon_config(data_dir_, 2);
    config.stream_write_timeout = write_timeout;
    daemon_ = std::make_unique<Daemon>(config);
    daemon_->start();
    stub_ = v1::RenderService::NewStub(
        grpc::CreateChannel(daemon_->address(), grpc::InsecureChannelCredentials()));
  }

  v1::Job submit(const v1::RenderSettings& settings) {
    grpc::ClientContext context;
    v1::SubmitJobRequest request;
    *request.mutable_scene() = tiny_scene();
    *request.mutable_settings() = settings;
    v1::SubmitJobResponse response;
    const grpc::Status status = stub_->SubmitJob(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response.job();
  }

  Delivered stream(const std::string& job_id, std::uint64_t after_sequence = 0) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + 300s);
    v1::StreamTilesRequest request;
    request.set_job_id(job_id);
    request.set_after_sequence(after_sequence);
    auto reader = stub_->StreamTiles(&context, request);
    Delivered result;
    v1::Tile tile;
    while (reader->Read(&tile)) result.tiles.push_back(tile);
    result.status = reader->Finish();
    return result;
  }

  v1::Job get(const std::string& job_id) {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(job_id);
    v1::Job job;
    EXPECT_TRUE(stub_->GetJob(&context, request, &job).ok());
    return job;
  }

  std::filesystem::path data_dir_;
  std::unique_ptr<Daemon> daemon_;
  std::unique_ptr<v1::RenderService::Stub> stub_;
};

// 3 x 2 tiles, 12 spp, every AOV (the variance's statistics cross the passes too).
v1::RenderSettings pass_settings(std::uint32_t passes) {
  v1::RenderSettings settings = tiny_settings(24, 16, 8);
  settings.set_samples_per_pixel(12);
  settings.set_max_depth(4);
  settings.set_seed(11);
  for (int aov = v1::AOV_ALBEDO; aov <= v1::AOV_SAMPLE_COUNT; ++aov)
    settings.add_aovs(static_cast<v1::Aov>(aov));
  settings.set_passes(passes);
  return settings;
}

TEST_F(DaemonPassesTest, EveryPassOfEveryTileOnceInPassOrderAndTheLastIsTheOnePassImage) {
  constexpr std::uint32_t kTiles = 6, kPasses = 4;
  const v1::Job job = submit(pass_settings(kPasses));
  EXPECT_EQ(job.progress().tiles_total(), kTiles * kPasses);
  EXPECT_EQ(job.settings().passes(), kPasses);
  const Delivered passes = stream(job.id());
  ASSERT_TRUE(passes.status.ok()) << passes.status.error_message();
  ASSERT_EQ(passes.tiles.size(), kTiles * kPasses);

  std::map<std::uint32_t, std::uint32_t> last_pass;  // tile -> last pass delivered
  std::map<std::uint32_t, std::string> final_exr, first_exr;
  std::uint32_t highest_pass = 0;
  for (std::size_t i = 0; i < passes.tiles.size(); ++i) {
    const v1::Tile& tile = passes.tiles[i];
    EXPECT_EQ(tile.sequence(), i + 1);  // the stream's positions, gap-free
    EXPECT_EQ(tile.progress().tiles_done(), i + 1);
    EXPECT_EQ(tile.pass(), "beauty");
    const std::uint32_t index = tile.rect().index();
    ASSERT_LT(index, kTiles);
    // Each tile's passes arrive once each, in order.
    EXPECT_EQ(tile.pass_index(), last_pass[index] + 1) << "tile " << index;
    last_pass[index] = tile.pass_index();
    // Pass-major: a later pass starts only as the earlier one ends (two workers).
    highest_pass = std::max(highest_pass, tile.pass_index());
    EXPECT_GE(tile.pass_index() + 1, highest_pass) << "delivery " << i;
    if (tile.pass_index() == 1) first_exr[index] = tile.exr();
    if (tile.pass_index() == kPasses) final_exr[index] = tile.exr();
    const std::vector<std::uint8_t> bytes(tile.exr().begin(), tile.exr().end());
    EXPECT_EQ(decode_exr(bytes).width, tile.rect().width());  // a displayable tile
  }
  for (const auto& [index, pass] : last_pass) EXPECT_EQ(pass, kPasses) << "tile " << index;

  const v1::Job one_pass = submit(pass_settings(1));
  EXPECT_EQ(one_pass.progress().tiles_total(), kTiles);
  const Delivered single = stream(one_pass.id());
  ASSERT_TRUE(single.status.ok()) << single.status.error_message();
  ASSERT_EQ(single.tiles.size(), kTiles);
  std::size_t refined = 0;
  for (const v1::Tile& tile : single.tiles) {
    EXPECT_EQ(tile.pass_index(), 1u);
    const std::uint32_t index = tile.rect().index();
    // Every channel, AOVs included, bit for bit.
    EXPECT_TRUE(tile_bits(final_exr[index]) == tile_bits(tile.exr())) << "tile " << index;
    if (tile_bits(first_exr[index]) != tile_bits(tile.exr())) ++refined;
  }
  EXPECT_EQ(refined, kTiles);  // pass 1 (3 spp) is not yet the final image
  EXPECT_EQ(get(job.id()).state(), v1::JOB_STATE_COMPLETED);

  // The accumulated state lives only between a tile's passes: none is left, and no pass
  // was committed twice.
  daemon_.reset();
  SqliteJobStore store(data_dir_ / SqliteJobStore::kFileName);
  for (std::uint32_t tile = 0; tile < kTiles; ++tile)
    EXPECT_FALSE(store.tile_pass_state(job.id(), tile).has_value()) << "tile " << tile;
  for (std::uint32_t unit = 0; unit < kTiles * kPasses; ++unit)
    EXPECT_EQ(store.tile_commit_count(job.id(), unit), 1u) << "unit " << unit;
}

TEST_F(DaemonPassesTest, ReattachingAfterASequenceDeliversOnlyWhatFollows) {
  const v1::Job job = submit(pass_settings(3));  // 18 deliveries
  const Delivered all = stream(job.id());
  ASSERT_TRUE(all.status.ok());
  ASSERT_EQ(all.tiles.size(), 18u);
  for (const std::uint64_t after : {0u, 1u, 7u, 17u, 18u}) {
    const Delivered rest = stream(job.id(), after);
    ASSERT_TRUE(rest.status.ok()) << rest.status.error_message();
    ASSERT_EQ(rest.tiles.size(), 18u - after);
    for (std::size_t i = 0; i < rest.tiles.size(); ++i) {
      const v1::Tile& expected = all.tiles[after + i];
      EXPECT_EQ(rest.tiles[i].sequence(), expected.sequence());
      EXPECT_EQ(rest.tiles[i].rect().index(), expected.rect().index());
      EXPECT_EQ(rest.tiles[i].pass_index(), expected.pass_index());
      EXPECT_EQ(rest.tiles[i].exr(), expected.exr());
    }
  }
  const Delivered beyond = stream(job.id(), 19);
  EXPECT_EQ(beyond.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(beyond.status.error_message(),
            "after_sequence: must be at most the job's 18 deliveries, got 19");
}

// A shutdown while a job with passes runs, then a restart: the job completes from the
// stored passes and states with the one-pass image (the kill -9 version runs the daemon as
// a process: tests/integration/daemon_process_test.cpp).
TEST_F(DaemonPassesTest, ARestartMidJobContinuesFromTheStoredPasses) {
  constexpr std::uint32_t kTiles = 256, kUnits = kTiles * 4;
  v1::RenderSettings settings = pass_settings(4);
  settings.set_width(128);
  settings.set_height(128);  // 256 tiles, 1024 tile passes
  settings.set_samples_per_pixel(64);
  const v1::Job job = submit(settings);
  const auto started = std::chrono::steady_clock::now();
  std::uint32_t done = 0;
  while ((done = get(job.id()).progress().tiles_done()) < 300 &&
         std::chrono::steady_clock::now() - started < 60s)
    std::this_thread::sleep_for(5ms);
  EXPECT_LT(done, kUnits);  // stopped mid-job (between passes 2 and 3 or so)
  start();
  const Delivered resumed = stream(job.id());
  ASSERT_TRUE(resumed.status.ok()) << resumed.status.error_message();
  ASSERT_EQ(resumed.tiles.size(), kUnits);
  const v1::Job one_pass = submit([&] {
    v1::RenderSettings s = settings;
    s.set_passes(1);
    return s;
  }());
  const Delivered single = stream(one_pass.id());
  ASSERT_TRUE(single.status.ok());
  std::map<std::uint32_t, std::string> final_exr;
  for (const v1::Tile& tile : resumed.tiles)
    if (tile.pass_index() == 4) final_exr[tile.rect().index()] = tile.exr();
  ASSERT_EQ(final_exr.size(), kTiles);
  for (const v1::Tile& tile : single.tiles)
    EXPECT_TRUE(tile_bits(final_exr[tile.rect().index()]) == tile_bits(tile.exr()))
        << "tile " << tile.rect().index();
  daemon_.reset();
  SqliteJobStore store(data_dir_ / SqliteJobStore::kFileName);
  for (std::uint32_t unit = 0; unit < kUnits; ++unit)
    EXPECT_EQ(store.tile_commit_count(job.id(), unit), 1u) << "unit " << unit;
}

// A client that opens StreamTiles on a job with megabytes of tiles and never reads: once
// flow control fills its window the server's Write blocks, and the write timeout ends the
// call. Meanwhile the workers finish the job and other calls are served.
TEST_F(DaemonPassesTest, AReaderThatNeverReadsIsCutOffAfterTheWriteTimeout) {
  start(500ms);
  v1::RenderSettings settings = pass_settings(1);
  settings.set_width(512);
  settings.set_height(512);  // 1024 tiles of 16 x 16, every AOV: several MB of EXR
  settings.set_tile_size(16);
  settings.set_samples_per_pixel(1);
  settings.set_max_depth(1);
  const v1::Job job = submit(settings);

  // No BDP probing and a 64 KiB window: the client's buffers stay far below the job's size.
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 65536);
  const auto stalled_channel =
      grpc::CreateCustomChannel(daemon_->address(), grpc::InsecureChannelCredentials(), args);
  const auto stalled_stub = v1::RenderService::NewStub(stalled_channel);
  grpc::ClientContext stalled_context;
  v1::StreamTilesRequest request;
  request.set_job_id(job.id());
  auto stalled = stalled_stub->StreamTiles(&stalled_context, request);

  // The workers are not held up by the stalled stream: the job completes.
  const auto started = std::chrono::steady_clock::now();
  while (get(job.id()).state() != v1::JOB_STATE_COMPLETED &&
         std::chrono::steady_clock::now() - started < 120s)
    std::this_thread::sleep_for(20ms);
  EXPECT_EQ(get(job.id()).state(), v1::JOB_STATE_COMPLETED);
  // The server ends the stalled call: its thread is free and the stream count drops.
  while ((daemon_->open_streams() != 0 || daemon_->stream_write_timeouts() == 0) &&
         std::chrono::steady_clock::now() - started < 120s)
    std::this_thread::sleep_for(20ms);
  EXPECT_EQ(daemon_->open_streams(), 0);
  EXPECT_EQ(daemon_->stream_write_timeouts(), 1u);
  // Another client is served meanwhile.
  const Delivered other = stream(job.id(), 1000);
  EXPECT_TRUE(other.status.ok()) << other.status.error_message();
  EXPECT_EQ(other.tiles.size(), 24u);
  // The stalled client, once it looks, finds its call ended (not OK) and can re-attach from
  // the last sequence it read (on a daemon with the default timeout, so that a busy test
  // machine cannot stall this reader for 500 ms).
  v1::Tile tile;
  std::uint64_t read = 0;
  while (stalled->Read(&tile)) read = tile.sequence();
  const grpc::Status status = stalled->Finish();
  EXPECT_FALSE(status.ok());
  EXPECT_LT(read, 1024u);
  start();
  const Delivered rest = stream(job.id(), read);
  EXPECT_TRUE(rest.status.ok()) << rest.status.error_message();
  ASSERT_EQ(rest.tiles.size(), 1024u - read);
  EXPECT_EQ(rest.tiles.front().sequence(), read + 1);
}

// The bytes kept between passes give back the very state they were made from.
TEST(TileStateCodec, RoundTripsEveryPlaneAndRejectsForeignBytes) {
  TileAccumulation state;
  state.samples_done = 3;
  state.samples_total = 12;
  state.sums.beauty = {1.0f, -0.0f, 3.5f, 1e-30f};
  state.sums.aovs[2] = {std::numeric_limits<float>::infinity(), 2.0f, 3.0f, 4.0f};
  state.running_mean = {0.5f, 0.25f, 0.125f, 0.0f};
  state.running_m2 = {9.0f, 8.0f, 7.0f, 6.0f};
  const std::vector<std::uint8_t> bytes = encode_tile_state(state);
  const TileAccumulation back = decode_tile_state(bytes);
  EXPECT_EQ(back.samples_done, 3u);
  EXPECT_EQ(back.samples_total, 12u);
  EXPECT_EQ(back.sums.beauty, state.sums.beauty);
  EXPECT_TRUE(std::signbit(back.sums.beauty[1]));
  for (std::size_t i = 0; i < kAovCount; ++i) EXPECT_EQ(back.sums.aovs[i], state.sums.aovs[i]);
  EXPECT_EQ(back.running_mean, state.running_mean);
  EXPECT_EQ(back.running_m2, state.running_m2);
  std::vector<std::uint8_t> cut(bytes.begin(), bytes.end() - 1);
  EXPECT_THROW(decode_tile_state(cut), std::runtime_error);
  EXPECT_THROW(decode_tile_state({'E', 'X', 'R', '!'}), std::runtime_error);
}

}  // namespace
}  // namespace tessera::server
