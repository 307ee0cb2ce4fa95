// The client against a real daemon running in this process on an ephemeral port: the
// streamed image equals the in-process render bit for bit, bad scenes are rejected without
// disturbing other jobs, cancellation ends the stream, and job state is reported.
#include <gtest/gtest.h>

#include <spdlog/spdlog.h>
#include "cornell_scene.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <thread>

#include "cli_run.hpp"
#include "client/client.hpp"
#include "client/commands.hpp"
#include "convert/scene_proto.hpp"
#include "server/daemon.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera {
namespace {

using test::cornell;
using test::kCornell;

// What a client receives for one job.
struct StreamedJob {
  std::vector<int> times_seen;  // per tile index
  std::vector<float> image;     // RGBA, assembled from the decoded tiles
  std::uint32_t tiles = 0;
  v1::JobProgress last_progress;
};

// Streams every tile of `job` and assembles them here, independently of the CLI's assembler.
StreamedJob stream_all(Client& client, const v1::Job& job) {
  const v1::RenderSettings& s = job.settings();
  const std::vector<TileRect> grid = make_tiles(s.width(), s.height(), s.tile_size());
  StreamedJob result;
  result.times_seen.assign(grid.size(), 0);
  result.image.assign(static_cast<std::size_t>(s.width()) * s.height() * 4, -1.0f);
  client.stream_tiles(job.id(), [&](const v1::Tile& tile) {
    EXPECT_EQ(tile.job_id(), job.id());
    EXPECT_EQ(tile.pass(), "beauty");
    const v1::TileRect& r = tile.rect();
    ASSERT_LT(r.index(), grid.size());
    ++result.times_seen[r.index()];
    ++result.tiles;
    const TileRect& expected = grid[r.index()];
    ASSERT_EQ(r.x(), expected.x);
    ASSERT_EQ(r.y(), expected.y);
    ASSERT_EQ(r.width(), expected.width);
    ASSERT_EQ(r.height(), expected.height);
    const RgbaImage pixels = decode_exr(
        std::span(reinterpret_cast<const std::uint8_t*>(tile.exr().data()), tile.exr().size()));
    ASSERT_EQ(pixels.width, r.width());
    ASSERT_EQ(pixels.height, r.height());
    for (std::uint32_t row = 0; row < r.height(); ++row)
      std::memcpy(&result.image[((r.y() + row) * s.width() + r.x()) * 4],
                  &pixels.pixels[row * r.width() * 4], r.width() * 4 * sizeof(float));
    EXPECT_EQ(tile.progress().tiles_total(), grid.size());
    EXPECT_GE(tile.progress().tiles_done(), result.last_progress.tiles_done());
    result.last_progress = tile.progress();
  });
  return result;
}

bool bit_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

class ClientServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server::DaemonConfig config;
    config.listen = "127.0.0.1:0";
    config.threads = 2;
    config.log_level = "warn";
    spdlog::set_level(spdlog::level::warn);  // job-by-job info lines would drown the test output
    // Small enough that the CLI test below can exceed it with a scene the client accepts.
    config.limits.max_width = 1024;
    config.limits.max_height = 1024;
    daemon_ = new server::Daemon(config);
    port_ = daemon_->start();
  }
  static void TearDownTestSuite() {
    daemon_->shutdown();
    delete daemon_;
    daemon_ = nullptr;
  }
  static std::string address() { return "127.0.0.1:" + std::to_string(port_); }

  Client client_{ClientOptions{.target = address()}};
  static server::Daemon* daemon_;
  static int port_;
};

server::Daemon* ClientServerTest::daemon_ = nullptr;
int ClientServerTest::port_ = 0;

TEST_F(ClientServerTest, StreamedImageEqualsTheInProcessRenderBitForBit) {
  const SceneDescription scene = cornell(64, 48, 4, 16);
  const v1::Job job = client_.submit(make_submit_request(scene, "cornell-small", 0));
  ASSERT_FALSE(job.id().empty());
  EXPECT_EQ(job.settings().width(), 64u);
  EXPECT_EQ(job.settings().height(), 48u);
  EXPECT_EQ(job.settings().samples_per_pixel(), 4u);
  EXPECT_EQ(job.settings().tile_size(), 16u);

  const StreamedJob streamed = stream_all(client_, job);
  ASSERT_EQ(streamed.times_seen.size(), 12u);
  for (std::size_t i = 0; i < streamed.times_seen.size(); ++i)
    EXPECT_EQ(streamed.times_seen[i], 1) << "tile " << i;
  EXPECT_EQ(streamed.last_progress.tiles_done(), 12u);
  EXPECT_GT(streamed.last_progress.rays_traced(), 64u * 48u * 4u);

  const std::vector<float> reference = render_image(*PreparedScene::build(scene));
  EXPECT_TRUE(bit_equal(streamed.image, reference));
}

TEST_F(ClientServerTest, BadSceneIsRejectedWhileAnotherJobRunsToCompletion) {
  const SceneDescription good_scene = cornell(128, 96, 16, 16);
  const v1::Job good = client_.submit(make_submit_request(good_scene, "good", 0));

  // Geometry entry 2 of the proto gets a negative radius, a mistake the server must name.
  SceneDescription bad = cornell(32, 32, 1, 16);
  v1::SubmitJobRequest request = make_submit_request(bad, "bad", 0);
  v1::Geometry* sphere = request.mutable_scene()->mutable_geometry(6);
  ASSERT_TRUE(sphere->has_sphere());
  request.mutable_scene()->mutable_geometry()->SwapElements(2, 6);
  request.mutable_scene()->mutable_geometry(2)->mutable_sphere()->set_radius(-0.5);
  try {
    client_.submit(request);
    FAIL() << "a sphere with radius -0.5 was accepted";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT) << e.what();
    EXPECT_NE(e.message().find("geometry[2]"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("radius"), std::string::npos) << e.what();
  }

  const StreamedJob streamed = stream_all(client_, good);
  EXPECT_EQ(streamed.tiles, 48u);
  for (int seen : streamed.times_seen) EXPECT_EQ(seen, 1);
  EXPECT_EQ(client_.get(good.id()).state(), v1::JOB_STATE_COMPLETED);
  EXPECT_TRUE(bit_equal(streamed.image, render_image(*PreparedScene::build(good_scene))));
}

TEST_F(ClientServerTest, CancelMidJobEndsTheStreamWithCancelled) {
  // Far more tiles than worker threads, so the job is still running when the first arrives.
  const v1::Job job = client_.submit(make_submit_request(cornell(256, 192, 64, 16), "long", 0));
  std::uint32_t received = 0;
  try {
    client_.stream_tiles(job.id(), [&](const v1::Tile&) {
      if (++received == 1) {
        const v1::Job after_cancel = client_.cancel(job.id());
        EXPECT_EQ(after_cancel.id(), job.id());
      }
    });
    FAIL() << "the stream of a cancelled job ended OK";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::CANCELLED) << e.what();
  }
  EXPECT_GE(received, 1u);
  EXPECT_LT(received, 192u);
  const v1::Job final_state = client_.get(job.id());
  EXPECT_EQ(final_state.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_GT(final_state.finished_unix_ms(), 0);
}

TEST_F(ClientServerTest, GetAndListReflectJobStates) {
  const v1::Job first = client_.submit(make_submit_request(cornell(32, 32, 2, 16), "first", 3));
  const v1::Job second = client_.submit(make_submit_request(cornell(32, 32, 2, 16), "second", -1));
  EXPECT_NE(first.id(), second.id());

  const v1::Job queried = client_.get(first.id());
  EXPECT_EQ(queried.name(), "first");
  EXPECT_EQ(queried.priority(), 3);
  EXPECT_TRUE(queried.state() == v1::JOB_STATE_QUEUED || queried.state() == v1::JOB_STATE_RUNNING ||
              queried.state() == v1::JOB_STATE_COMPLETED)
      << v1::JobState_Name(queried.state());
  EXPECT_EQ(queried.progress().tiles_total(), 4u);
  EXPECT_GT(queried.submitted_unix_ms(), 0);

  stream_all(client_, first);
  stream_all(client_, second);
  const v1::Job done = client_.get(first.id());
  EXPECT_EQ(done.state(), v1::JOB_STATE_COMPLETED);
  EXPECT_EQ(done.progress().tiles_done(), 4u);
  EXPECT_GE(done.finished_unix_ms(), done.submitted_unix_ms());
  EXPECT_TRUE(done.error().empty());

  // Newest first: `second` comes before `first`.
  const std::vector<v1::Job> jobs = client_.list();
  int first_at = -1, second_at = -1;
  for (int i = 0; i < static_cast<int>(jobs.size()); ++i) {
    if (jobs[i].id() == first.id()) first_at = i;
    if (jobs[i].id() == second.id()) second_at = i;
  }
  ASSERT_GE(first_at, 0);
  ASSERT_GE(second_at, 0);
  EXPECT_LT(second_at, first_at);
  EXPECT_EQ(jobs[second_at].state(), v1::JOB_STATE_COMPLETED);

  try {
    client_.get("no-such-job");
    FAIL() << "GetJob found a job that was never submitted";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::NOT_FOUND) << e.what();
  }
}

// ---- The CLI against the daemon -----------------------------------------------------------

using test::CliRun;
using test::run_cli;

class CliAgainstDaemonTest : public ClientServerTest {
 protected:
  void SetUp() override { dir_ = test::make_test_dir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CliCommand render_command() const {
    CliCommand c;
    c.kind = CommandKind::kRender;
    c.server = address();
    c.scene_path = kCornell;
    c.output_exr = (dir_ / "cornell.exr").string();
    c.preview_png = (dir_ / "cornell.png").string();
    c.overrides.width = 48;
    c.overrides.height = 40;
    c.overrides.samples_per_pixel = 2;
    c.overrides.tile_size = 16;
    return c;
  }
  std::filesystem::path dir_;
};

TEST_F(CliAgainstDaemonTest, RenderAndWatchWriteTheInProcessImage) {
  const std::vector<float> reference = render_image(*PreparedScene::build(cornell(48, 40, 2, 16)));

  const CliRun render = run_cli(render_command());
  ASSERT_EQ(render.exit_code, kExitOk) << render.err;
  EXPECT_EQ(render.out.rfind("tessera: rendered 48x40 at 2 spp in ", 0), 0u) << render.out;
  EXPECT_NE(render.err.find("tessera: 100% (9/9 tiles)"), std::string::npos) << render.err;
  const RgbaImage rendered = read_image(render_command().output_exr);
  EXPECT_TRUE(bit_equal(rendered.pixels, reference));
  EXPECT_EQ(read_image(render_command().preview_png).width, 48u);

  // submit + watch: the same image through the other path.
  CliCommand submit = render_command();
  submit.kind = CommandKind::kSubmit;
  submit.name = "watched";
  const CliRun submitted = run_cli(submit);
  ASSERT_EQ(submitted.exit_code, kExitOk) << submitted.err;
  const std::string job_id = submitted.out.substr(0, submitted.out.find('\n'));
  ASSERT_FALSE(job_id.empty());
  EXPECT_EQ(client_.get(job_id).name(), "watched");

  CliCommand watch;
  watch.kind = CommandKind::kWatch;
  watch.server = address();
  watch.job_id = job_id;
  watch.output_exr = (dir_ / "watched.exr").string();
  const CliRun watched = run_cli(watch);
  ASSERT_EQ(watched.exit_code, kExitOk) << watched.err;
  EXPECT_TRUE(bit_equal(read_image(watch.output_exr).pixels, reference));

  CliCommand status;
  status.kind = CommandKind::kStatus;
  status.server = address();
  status.job_id = job_id;
  const CliRun shown = run_cli(status);
  ASSERT_EQ(shown.exit_code, kExitOk) << shown.err;
  EXPECT_NE(shown.out.find("state      completed"), std::string::npos) << shown.out;

  CliCommand list;
  list.kind = CommandKind::kList;
  list.server = address();
  const CliRun listed = run_cli(list);
  ASSERT_EQ(listed.exit_code, kExitOk) << listed.err;
  EXPECT_NE(listed.out.find(job_id), std::string::npos) << listed.out;
}

// --passes: the daemon streams every pass of every tile, the CLI shows the pass and
// rewrites its files per pass, and the file it ends with is the one-pass image bit for bit;
// submit --passes + watch takes the same path.
TEST_F(CliAgainstDaemonTest, RenderWithPassesWritesTheOnePassImage) {
  const std::vector<float> reference = render_image(*PreparedScene::build(cornell(48, 40, 6, 16)));
  CliCommand render = render_command();
  render.overrides.samples_per_pixel = 6;
  render.overrides.passes = 3;
  const CliRun rendered = run_cli(render);
  ASSERT_EQ(rendered.exit_code, kExitOk) << rendered.err;
  EXPECT_NE(rendered.err.find("27 tile passes in 3 passes"), std::string::npos) << rendered.err;
  EXPECT_NE(rendered.err.find("tessera: 100% (27/27 tile passes  pass 3/3)"), std::string::npos)
      << rendered.err;
  EXPECT_TRUE(bit_equal(read_image(render.output_exr).pixels, reference));
  EXPECT_EQ(read_image(render.preview_png).width, 48u);

  CliCommand submit = render;
  submit.kind = CommandKind::kSubmit;
  const CliRun submitted = run_cli(submit);
  ASSERT_EQ(submitted.exit_code, kExitOk) << submitted.err;
  const std::string job_id = submitted.out.substr(0, submitted.out.find('\n'));
  EXPECT_EQ(client_.get(job_id).settings().passes(), 3u);
  CliCommand watch;
  watch.kind = CommandKind::kWatch;
  watch.server = address();
  watch.job_id = job_id;
  watch.output_exr = (dir_ / "watched.exr").string();
  const CliRun watched = run_cli(watch);
  ASSERT_EQ(watched.exit_code, kExitOk) << watched.err;
  EXPECT_TRUE(bit_equal(read_image(watch.output_exr).pixels, reference));

  CliCommand status;
  status.kind = CommandKind::kStatus;
  status.server = address();
  status.job_id = job_id;
  const CliRun shown = run_cli(status);
  ASSERT_EQ(shown.exit_code, kExitOk) << shown.err;
  EXPECT_NE(shown.out.find(", 3 passes (progress counts tile passes)"), std::string::npos)
      << shown.out;
}

TEST_F(CliAgainstDaemonTest, ServerRejectionPrintsCodeAndMessage) {
  // Valid for the client's default limits, beyond this daemon's max_width of 1024.
  CliCommand command = render_command();
  command.overrides.width = 2000;
  const CliRun r = run_cli(command);
  EXPECT_EQ(r.exit_code, kExitFailed);
  EXPECT_EQ(r.err.rfind("tessera: server rejected the scene: INVALID_ARGUMENT: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("width"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(command.output_exr));
}

TEST_F(CliAgainstDaemonTest, CancelledJobMakesWatchFail) {
  const v1::Job job =
      client_.submit(make_submit_request(cornell(256, 192, 64, 16), "to-cancel", 0));
  CliCommand cancel;
  cancel.kind = CommandKind::kCancel;
  cancel.server = address();
  cancel.job_id = job.id();
  const CliRun cancelled = run_cli(cancel);
  ASSERT_EQ(cancelled.exit_code, kExitOk) << cancelled.err;
  EXPECT_EQ(cancelled.out, "job " + job.id() + ": cancelled\n");

  CliCommand watch;
  watch.kind = CommandKind::kWatch;
  watch.server = address();
  watch.job_id = job.id();
  watch.output_exr = (dir_ / "never.exr").string();
  const CliRun watched = run_cli(watch);
  EXPECT_EQ(watched.exit_code, kExitFailed);
  EXPECT_EQ(watched.err.rfind("tessera: job " + job.id() + " was cancelled", 0), 0u) << watched.err;
  EXPECT_FALSE(std::filesystem::exists(watch.output_exr));
}

// `tessera delete JOB` removes a finished job; the daemon forgets it.
TEST_F(CliAgainstDaemonTest, DeleteRemovesAFinishedJob) {
  const char* argv[] = {"tessera", "delete", "job-x", "--server", "127.0.0.1:1"};
  std::ostringstream parse_out, parse_err;
  const ParsedCommandLine parsed = parse_command_line(5, argv, parse_out, parse_err);
  ASSERT_TRUE(parsed.command) << parse_err.str();
  EXPECT_EQ(parsed.command->kind, CommandKind::kDelete);
  EXPECT_EQ(parsed.command->job_id, "job-x");

  const v1::Job job = client_.submit(make_submit_request(cornell(16, 16, 1, 16), "short", 0));
  stream_all(client_, job);
  CliCommand remove;
  remove.kind = CommandKind::kDelete;
  remove.server = address();
  remove.job_id = job.id();
  const CliRun removed = run_cli(remove);
  ASSERT_EQ(removed.exit_code, kExitOk) << removed.err;
  EXPECT_EQ(removed.out, "job " + job.id() + ": deleted\n");
  try {
    client_.get(job.id());
    FAIL() << "a deleted job was found";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::NOT_FOUND) << e.what();
  }
  const CliRun again = run_cli(remove);
  EXPECT_EQ(again.exit_code, kExitFailed);
  EXPECT_NE(again.err.find("NOT_FOUND"), std::string::npos) << again.err;
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Integrator and AOVs travel through the API: the CLI's remote render of a transparency
// scene, and of a path-traced scene with every AOV, write the same EXR channels and pixels
// as --local.
TEST_F(CliAgainstDaemonTest, RemoteIntegratorsAndAovsMatchLocalRendering) {
  for (const char* render_section :
       {"{ integrator: transparency }", "{ aovs: [albedo, normal, depth, primitive_id] }"}) {
    const std::filesystem::path scene = dir_ / "scene.yaml";
    std::ifstream cornell_file(kCornell);
    std::string text((std::istreambuf_iterator<char>(cornell_file)),
                     std::istreambuf_iterator<char>());
    text = text.substr(0, text.find("\nrender:")) + "\nrender: " + render_section + "\n";
    std::ofstream(scene) << text;

    CliCommand remote = render_command();
    remote.scene_path = scene.string();
    remote.preview_png.clear();
    remote.output_exr = (dir_ / "remote.exr").string();
    CliCommand local = remote;
    local.local = true;
    local.output_exr = (dir_ / "local.exr").string();
    ASSERT_EQ(run_cli(remote).exit_code, kExitOk) << render_section;
    ASSERT_EQ(run_cli(local).exit_code, kExitOk) << render_section;
    const ChannelImage a = decode_exr_channels(read_bytes(remote.output_exr));
    const ChannelImage b = decode_exr_channels(read_bytes(local.output_exr));
    EXPECT_EQ(a.channels.size(),
              std::string(render_section).find("aovs") != std::string::npos ? 12u : 4u);
    EXPECT_EQ(a.channels, b.channels) << render_section;
    EXPECT_TRUE(bit_equal(a.pixels, b.pixels)) << render_section;
  }
}

const std::string kShapes = std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/shapes.yaml";
const std::string kPatches = std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/patches.yaml";
const std::string kTextures = std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/textures.yaml";

// Every shape type, every kind of transform, a mesh with normals and uvs: the client's
// conversion followed by the server's gives back the description exactly.
TEST(ProtoRoundTrip, SceneToProtoThenSceneFromProtoIsTheIdentity) {
  SceneDescription scene = load_scene_file(kShapes).scene;
  TriangleMeshDesc mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5}};
  mesh.indices = {0, 1, 2, 2, 1, 3};
  mesh.normals = {{0, 0, 1}, {0, 0.1, 1}, {0.1, 0, 1}, {0, 0, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  mesh.material = 1;
  mesh.visible = false;
  mesh.source_index =
      static_cast<std::uint32_t>(scene.analytic_shape_count() + scene.meshes.size());
  mesh.transform = TransformDesc{{1, 2, 3}, {0.3, 0.4, 0.5}, -17.5, {1, 2, 0.5}};
  scene.meshes.push_back(mesh);
  scene.tori.back().transform = TransformDesc{{0, 0, 0}, {1, 0, 0}, 90.0, {1, 1, 3}};
  ASSERT_TRUE(validate_scene(scene).empty());

  const SceneConversion back =
      scene_from_proto(scene_to_proto(scene), settings_to_proto(scene.render));
  ASSERT_TRUE(back.ok()) << describe_issues(back.issues);
  const SceneDescription& d = *back.scene;
  EXPECT_TRUE(d.spheres == scene.spheres);
  EXPECT_TRUE(d.quads == scene.quads);
  EXPECT_TRUE(d.meshes == scene.meshes);
  EXPECT_TRUE(d.planes == scene.planes);
  EXPECT_TRUE(d.disks == scene.disks);
  EXPECT_TRUE(d.cylinders == scene.cylinders);
  EXPECT_TRUE(d.cones == scene.cones);
  EXPECT_TRUE(d.tori == scene.tori);
  EXPECT_TRUE(d.sdf_boxes == scene.sdf_boxes);
  EXPECT_TRUE(d.sdf_tori == scene.sdf_tori);
  EXPECT_TRUE(d.sdf_capsules == scene.sdf_capsules);
  EXPECT_TRUE(d.patches == scene.patches);
  EXPECT_TRUE(d.trimmed_faces == scene.trimmed_faces);
  EXPECT_TRUE(d == scene);
}

// examples/scenes/shapes.yaml through the daemon and locally: the same image bit for bit,
// and not an empty one.
TEST(ProtoRoundTrip, PatchesAndTrimmedFacesSurviveTheRoundTrip) {
  SceneDescription scene = load_scene_file(kPatches).scene;
  ASSERT_FALSE(scene.patches.empty());
  ASSERT_FALSE(scene.trimmed_faces.empty());
  // Explicit knots, and one trimmed face of every other surface kind.
  scene.patches[0].knots_v = {-1, -1, -1, -1, 2, 2, 2, 2};
  TrimmedFaceDesc face = scene.trimmed_faces[0];
  auto index = static_cast<std::uint32_t>(scene.analytic_shape_count() + scene.meshes.size());
  PlaneDesc plane;
  plane.normal = {0.1, 1, 0};
  DiskDesc disk;
  disk.inner_radius = 0.2;
  CylinderDesc cylinder;
  cylinder.axis = {0, 0, 1};
  ConeDesc cone;
  cone.top_radius = 0.3;
  TorusDesc torus;
  torus.minor_radius = 0.3;
  for (const TrimmedSurfaceDesc& surface :
       {TrimmedSurfaceDesc(plane), TrimmedSurfaceDesc(disk), TrimmedSurfaceDesc(cylinder),
        TrimmedSurfaceDesc(cone), TrimmedSurfaceDesc(torus)}) {
    face.surface = surface;
    face.source_index = index++;
    face.loops = {{{0.1, 0.1}, {0.4, 0.1}, {0.4, 0.3}}};
    scene.trimmed_faces.push_back(face);
  }
  ASSERT_TRUE(validate_scene(scene).empty());

  const SceneConversion back =
      scene_from_proto(scene_to_proto(scene), settings_to_proto(scene.render));
  ASSERT_TRUE(back.ok()) << describe_issues(back.issues);
  EXPECT_TRUE(back.scene->patches == scene.patches);
  EXPECT_TRUE(back.scene->trimmed_faces == scene.trimmed_faces);
  EXPECT_TRUE(*back.scene == scene);
}

// Renders `scene_path` once through the daemon and once with --local: the two images must
// be equal bit for bit, and not black (red and blue channels summed).
void expect_daemon_render_equals_local(CliCommand remote, const std::string& scene_path,
                                       const std::filesystem::path& dir) {
  remote.scene_path = scene_path;
  remote.preview_png.clear();
  remote.overrides.samples_per_pixel = 1;
  remote.output_exr = (dir / "remote.exr").string();
  CliCommand local = remote;
  local.local = true;
  local.output_exr = (dir / "local.exr").string();
  const CliRun remote_run = run_cli(remote);
  ASSERT_EQ(remote_run.exit_code, kExitOk) << remote_run.err;
  const CliRun local_run = run_cli(local);
  ASSERT_EQ(local_run.exit_code, kExitOk) << local_run.err;
  const RgbaImage a = read_image(remote.output_exr);
  const RgbaImage b = read_image(local.output_exr);
  EXPECT_TRUE(bit_equal(a.pixels, b.pixels));
  double sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) sum += a.pixels[i] + a.pixels[i + 2];
  EXPECT_GT(sum, 0.0);
}

TEST_F(CliAgainstDaemonTest, PatchesSceneRendersThroughTheDaemonAsLocally) {
  expect_daemon_render_equals_local(render_command(), kPatches, dir_);
}

TEST_F(CliAgainstDaemonTest, ShapesSceneRendersThroughTheDaemonAsLocally) {
  expect_daemon_render_equals_local(render_command(), kShapes, dir_);
}

// Image textures travel as pixels and checkers as fields: the same image either way.
TEST_F(CliAgainstDaemonTest, TexturesSceneRendersThroughTheDaemonAsLocally) {
  expect_daemon_render_equals_local(render_command(), kTextures, dir_);
}

}  // namespace
}  // namespace tessera
