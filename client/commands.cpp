#include "client/commands.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "client/client.hpp"
#include "client/client_connection.hpp"
#include "client/denoise_file.hpp"
#include "client/job_json.hpp"
#include "client/local_render.hpp"
#include "client/progress.hpp"
#include "client/tile_assembler.hpp"
#include "client/token_hash.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/output_channels.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/scene/yaml_loader.hpp"

namespace tessera {

namespace {

using Clock = std::chrono::steady_clock;

// A failure that ends the command: printed as `tessera: <message>`, exits with `exit_code`.
struct CommandFailure {
  int exit_code;
  std::string message;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---- Ctrl-C -------------------------------------------------------------------------------

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
  // A second Ctrl-C ends the process the usual way.
  std::signal(SIGINT, SIG_DFL);
}

// While alive, Ctrl-C raises g_interrupted instead of killing the process, so a render can
// cancel its job on the server (or stop its local workers) and exit cleanly.
class InterruptScope {
 public:
  InterruptScope() {
    g_interrupted.store(false);
    previous_ = std::signal(SIGINT, on_interrupt);
  }
  ~InterruptScope() { std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_); }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  void (*previous_)(int) = SIG_DFL;
};

// On Ctrl-C: cancels `job_id` on the server when `cancel_job` (render, watch --cancel), and
// ends the tile stream either way (Client::stop_streams), so the command stops at once even
// when the job has no tile to send. gRPC cannot be called from a signal handler, hence the
// polling thread.
class StopOnInterrupt {
 public:
  // `interactive`: a progress line may be open on `err` and must be ended first.
  StopOnInterrupt(Client& client, std::string job_id, bool cancel_job, std::ostream& err,
                  bool interactive)
      : client_(client),
        job_id_(std::move(job_id)),
        cancel_job_(cancel_job),
        err_(err),
        interactive_(interactive),
        thread_([this] { run(); }) {}
  ~StopOnInterrupt() { stop(); }

  // Stops watching for Ctrl-C, after finishing what a Ctrl-C already started (the cancel),
  // so interrupted() and cancelled() are final.
  void stop() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  // Whether Ctrl-C was pressed (and the stream stopped).
  bool interrupted() const { return interrupted_.load(); }
  // Whether the job was cancelled on the server because of it.
  bool cancelled() const { return cancelled_.load(); }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    // A Ctrl-C pressed just before stop() is still handled: the user asked for it.
    for (bool last = false; !last;) {
      wake_.wait_for(lock, std::chrono::milliseconds(100));
      last = done_;
      if (!g_interrupted.exchange(false)) continue;
      interrupted_.store(true);
      err_ << (interactive_ ? "\n" : "") << "tessera: interrupted"
           << (cancel_job_ ? "; cancelling job " + job_id_ : "") << '\n'
           << std::flush;
      if (cancel_job_) {
        try {
          client_.cancel(job_id_);
          cancelled_.store(true);
        } catch (const ClientError& e) {
          err_ << "tessera: could not cancel job " << job_id_ << ": " << e.what() << '\n'
               << std::flush;
        }
      }
      client_.stop_streams();
    }
  }

  InterruptScope scope_;
  Client& client_;
  std::string job_id_;
  bool cancel_job_;
  std::ostream& err_;
  bool interactive_;
  std::atomic<bool> interrupted_{false};
  std::atomic<bool> cancelled_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

// ---- Messages -----------------------------------------------------------------------------

// A gRPC failure as the user should read it: what we were doing, the code and the message.
std::string describe(const ClientError& e, const std::string& server, const std::string& doing) {
  switch (e.code()) {
    case grpc::StatusCode::UNAVAILABLE:
      if (e.message().find("andshake failed") != std::string::npos)
        return "the TLS handshake with the server at " + server +
               " failed (does --ca name the CA that signed its certificate? does it require "
               "--client-cert?): " +
               e.what();
      return "cannot reach the server at " + server +
             " (is tesserad running? if it serves TLS, give --ca or --tls): " + e.what();
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return "the server at " + server + " did not answer in time: " + e.what();
    default:
      return doing + ": " + e.what();
  }
}

// "key=value" arguments (checked by the parser to hold '=') into a label map.
void add_labels(const std::vector<std::string>& labels,
                google::protobuf::Map<std::string, std::string>& out) {
  for (const std::string& label : labels) {
    const auto equals = label.find('=');
    out[label.substr(0, equals)] = label.substr(equals + 1);
  }
}

std::string labels_text(const google::protobuf::Map<std::string, std::string>& labels) {
  std::vector<std::string> pairs;
  for (const auto& [key, value] : labels) pairs.push_back(key + "=" + value);
  std::sort(pairs.begin(), pairs.end());
  std::string text;
  for (const std::string& pair : pairs) {
    if (!text.empty()) text += ',';
    text += pair;
  }
  return text.empty() ? "-" : text;
}

std::string format_unix_ms(std::int64_t unix_ms) {
  if (unix_ms <= 0) return "-";
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm local{};
  localtime_r(&seconds, &local);
  std::ostringstream text;
  text << std::put_time(&local, "%Y-%m-%d %H:%M:%S");
  return text.str();
}

ProgressSnapshot snapshot_of(const v1::JobProgress& p) {
  return {p.tiles_done(),      p.tiles_total(),     p.rays_traced(),
          p.elapsed_seconds(), p.rays_per_second(), p.eta_seconds()};
}

// With the pass the image is in, for a job with progressive passes.
ProgressSnapshot snapshot_of(const v1::JobProgress& p, const TileAssembler& assembler) {
  ProgressSnapshot snapshot = snapshot_of(p);
  snapshot.passes = assembler.passes();
  snapshot.passes_done = assembler.passes_done();
  return snapshot;
}

std::string settings_summary(std::uint32_t width, std::uint32_t height, std::uint32_t spp) {
  return std::to_string(width) + "x" + std::to_string(height) + " at " + std::to_string(spp) +
         " spp";
}

// ---- Scenes -------------------------------------------------------------------------------

void apply_overrides(RenderSettings& settings, const RenderOverrides& o) {
  if (o.width) settings.width = *o.width;
  if (o.height) settings.height = *o.height;
  if (o.samples_per_pixel) settings.samples_per_pixel = *o.samples_per_pixel;
  if (o.max_depth) settings.max_depth = *o.max_depth;
  if (o.tile_size) settings.tile_size = *o.tile_size;
  if (o.seed) settings.seed = *o.seed;
  if (o.passes) settings.passes = *o.passes;
  if (o.accel_builder) settings.accel_builder = *o.accel_builder;
}

// "-" for a scene or an output file: standard input or output.
constexpr const char* kStandardStream = "-";
constexpr const char* kStandardInputName = "<stdin>";

std::string read_standard_input() {
  std::ostringstream text;
  text << std::cin.rdbuf();
  if (std::cin.bad())
    throw CommandFailure{kExitFailed, "cannot read the scene from standard input"};
  return text.str();
}

// Loads the scene, prints the loader's warnings and applies the command-line overrides.
// Scene problems end the command with exit code 2 and the loader's `file:line: field: reason`.
SceneDescription load_scene(const CliCommand& cmd, std::ostream& err) {
  LoadedScene loaded;
  try {
    SceneLoadOptions options;
    options.lenient = cmd.lenient;
    loaded = cmd.scene_path == kStandardStream
                 ? load_scene_yaml(read_standard_input(), kStandardInputName,
                                   std::filesystem::current_path(), options)
                 : load_scene_file(cmd.scene_path, options);
  } catch (const SceneError& e) {
    throw CommandFailure{kExitUsage, e.what()};
  }
  for (const SceneIssue& warning : loaded.warnings)
    err << "tessera: warning: " << warning.to_string() << '\n';
  apply_overrides(loaded.scene.render, cmd.overrides);
  if (cmd.denoise) loaded.scene.render.aovs |= kAovAlbedo | kAovNormal | kAovVariance;
  const std::vector<SceneIssue> issues = validate_scene(loaded.scene);
  if (!issues.empty()) {
    SceneIssue first = issues.front();
    first.file = cmd.scene_path == kStandardStream ? kStandardInputName : cmd.scene_path;
    throw CommandFailure{kExitUsage, first.to_string() + " (after command-line overrides)"};
  }
  return std::move(loaded.scene);
}

// load_scene() for a scene that goes to a server, which must receive everything that
// decides its pixels.
SceneDescription load_scene_for_server(const CliCommand& cmd, std::ostream& err) {
  return load_scene(cmd, err);
}

std::string job_name(const CliCommand& cmd) {
  if (!cmd.name.empty() || cmd.scene_path == kStandardStream) return cmd.name;
  return std::filesystem::path(cmd.scene_path).stem().string();
}

// ---- Output -------------------------------------------------------------------------------

// Where the image goes, as the user named it ("stdout" for -o -).
std::string output_name(const CliCommand& cmd) {
  return cmd.output_to_stdout ? "stdout" : cmd.output_exr;
}

void create_parent_directory(const std::string& file) {
  const std::filesystem::path parent = std::filesystem::path(file).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  if (ec)
    throw CommandFailure{kExitFailed,
                         "cannot create directory " + parent.string() + ": " + ec.message()};
}

std::unique_ptr<TileAssembler> open_output(const CliCommand& cmd, std::uint32_t width,
                                           std::uint32_t height, std::uint32_t tile_size,
                                           std::uint32_t aovs, std::uint32_t passes = 1) {
  create_parent_directory(cmd.output_exr);
  if (!cmd.preview_png.empty()) create_parent_directory(cmd.preview_png);
  try {
    return std::make_unique<TileAssembler>(width, height, tile_size,
                                           std::filesystem::path(cmd.output_exr),
                                           output_channels(aovs), passes);
  } catch (const std::exception& e) {
    throw CommandFailure{kExitFailed, e.what()};
  }
}

// Gives up on an incomplete output: a file with missing tiles would pass for a result.
void discard_output(TileAssembler& assembler, const CliCommand& cmd) {
  assembler.abandon();
  std::error_code ec;
  std::filesystem::remove(cmd.output_exr, ec);
}

// The EXR header of a render: what made it, from which scene and job, and the camera
// (`scene` is null when only the job is known, as for `tessera watch`).
ImageMetadata output_metadata(const std::string& scene_name, const std::string& job_id,
                              std::uint32_t samples_per_pixel, const SceneDescription* scene) {
  ImageMetadata metadata;
  metadata.software = std::string("Tessera ") + TESSERA_VERSION;
  metadata.scene_name = scene_name;
  metadata.job_id = job_id;
  metadata.samples_per_pixel = samples_per_pixel;
  if (scene) {
    const CameraMatrices m =
        camera_matrices(scene->camera, scene->render.width, scene->render.height);
    // glm's column-major memory is Imath's row-vector matrix, as OpenEXR stores it.
    const auto as_exr = [](const glm::dmat4& matrix) {
      std::array<float, 16> out{};
      for (int column = 0; column < 4; ++column)
        for (int row = 0; row < 4; ++row)
          out[static_cast<std::size_t>(column * 4 + row)] = static_cast<float>(matrix[column][row]);
      return out;
    };
    metadata.world_to_camera = as_exr(m.world_to_camera);
    metadata.world_to_screen = as_exr(m.world_to_screen);
    metadata.world_to_ndc = as_exr(m.world_to_ndc);
  }
  return metadata;
}

PreviewOptions preview_options(const CliCommand& cmd) {
  PreviewOptions options;
  options.exposure = static_cast<float>(cmd.preview_exposure);
  options.curve = cmd.preview_tone == "aces" ? ToneCurve::kAces : ToneCurve::kClamp;
  return options;
}

// Closes the EXR (rewritten with `metadata` and `seconds`, the render time), writes the PNG
// preview and prints the summary line.
void finish_output(TileAssembler& assembler, const CliCommand& cmd, const std::string& what,
                   double seconds, double rays_per_second, std::ostream& out,
                   ImageMetadata metadata) {
  try {
    metadata.render_seconds = seconds;
    assembler.finish(metadata);
    if (!cmd.preview_png.empty())
      write_image(cmd.preview_png, assembler.image(), preview_options(cmd));
    if (cmd.denoise)
      denoise_exr_file(cmd.output_exr, cmd.output_exr, cmd.preview_png, preview_options(cmd));
  } catch (const std::exception& e) {
    discard_output(assembler, cmd);
    throw CommandFailure{kExitFailed, e.what()};
  }
  out << "tessera: rendered " << what << " in " << format_duration(seconds) << ", "
      << format_rate(rays_per_second) << ": " << output_name(cmd);
  if (!cmd.preview_png.empty()) out << ", " << cmd.preview_png;
  out << '\n' << std::flush;
}

// ---- Streaming ----------------------------------------------------------------------------

// Turns one streamed tile into pixels, checking that the EXR holds what the rect says.
// Returns true when the tile completed a pass of the whole image.
bool add_streamed_tile(TileAssembler& assembler, const v1::Tile& tile) {
  const v1::TileRect& r = tile.rect();
  const TileRect rect{r.index(), r.x(), r.y(), r.width(), r.height()};
  const std::string& bytes = tile.exr();
  ChannelImage pixels;
  try {
    pixels = decode_exr_channels(
        std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  } catch (const std::exception& e) {
    throw std::runtime_error("tile " + std::to_string(rect.index) + ": " + e.what());
  }
  if (pixels.width != rect.width || pixels.height != rect.height)
    throw std::runtime_error("tile " + std::to_string(rect.index) + " is " +
                             std::to_string(rect.width) + "x" + std::to_string(rect.height) +
                             " but its EXR holds " + std::to_string(pixels.width) + "x" +
                             std::to_string(pixels.height) + " pixels");
  try {
    pixels = select_channels(pixels, assembler.channels());
  } catch (const std::exception& e) {
    throw std::runtime_error("tile " + std::to_string(rect.index) + ": " + e.what());
  }
  // A daemon from before passes sends no pass_index: its tiles are pass 1 of 1.
  return assembler.add_tile(rect, pixels.pixels, std::max(tile.pass_index(), 1u));
}

// Streams `job`'s tiles into the output until the job ends; Ctrl-C stops it (and cancels
// the job when `cancel_on_interrupt`), exiting 130.
// `scene`: the scene submitted, for the camera in the EXR header; null when unknown.
int stream_job(Client& client, const v1::Job& job, const CliCommand& cmd,
               std::unique_ptr<TileAssembler> assembler, bool cancel_on_interrupt,
               const CommandOutput& io, const SceneDescription* scene = nullptr) {
  const v1::RenderSettings& s = job.settings();
  const std::uint32_t aovs = aov_mask_from_proto(s);
  // The output was opened from the scene's settings; the server's are the ones that count.
  const std::uint32_t passes = std::max(s.passes(), 1u);
  if (!assembler || assembler->tile_size() != s.tile_size() ||
      assembler->image().width != s.width() || assembler->image().height != s.height() ||
      assembler->channels() != output_channels(aovs) || assembler->passes() != passes) {
    assembler.reset();  // close before reopening the same path
    assembler = open_output(cmd, s.width(), s.height(), s.tile_size(), aovs, passes);
  }

  ProgressReporter progress(io.err, io.interactive);
  v1::JobProgress last = job.progress();
  const auto print_json = [&](const nlohmann::json& event) {
    if (cmd.json) io.out << event.dump() << '\n' << std::flush;
  };
  std::optional<StopOnInterrupt> stopper;
  stopper.emplace(client, job.id(), cancel_on_interrupt, io.err, io.interactive);
  try {
    client.stream_tiles(job.id(), [&](const v1::Tile& tile) {
      // Each completed pass but the last rewrote the EXR; the preview follows it (the last
      // pass's files are written by finish_output).
      if (add_streamed_tile(*assembler, tile) && assembler->passes_done() < passes &&
          !cmd.preview_png.empty())
        write_image(cmd.preview_png, assembler->image(), preview_options(cmd));
      last = tile.progress();
      progress.update(snapshot_of(last, *assembler));
      print_json(tile_event_json(tile));
    });
  } catch (const ClientError& e) {
    progress.finish();
    const std::string received = std::to_string(assembler->tiles_received()) + " of " +
                                 std::to_string(assembler->tiles_total()) + " tiles";
    // A Ctrl-C's cancel may end the stream (CANCELLED) before the cancel call returns.
    stopper->stop();
    if (stopper->interrupted()) {
      const bool cancelled = stopper->cancelled();
      stopper.reset();
      std::string kept;
      if (cmd.keep_partial && assembler->tiles_received() > 0) {
        try {
          ImageMetadata metadata =
              output_metadata(job.name(), job.id(), s.samples_per_pixel(), scene);
          metadata.render_seconds = last.elapsed_seconds();
          assembler->finish_partial(metadata);
          if (!cmd.preview_png.empty())
            write_image(cmd.preview_png, assembler->image(), preview_options(cmd));
          kept = "; kept " + received + " in " + output_name(cmd);
        } catch (const std::exception& write_error) {
          discard_output(*assembler, cmd);
          kept = "; could not keep the partial image: " + std::string(write_error.what());
        }
      } else {
        discard_output(*assembler, cmd);
      }
      const std::string what = cancelled ? "job " + job.id() + " cancelled"
                               : cancel_on_interrupt
                                   ? "job " + job.id() + " may still run (the cancel failed)"
                                   : "stopped watching job " + job.id() + " (it goes on)";
      print_json({{"event", "interrupted"},
                  {"job_id", job.id()},
                  {"cancelled", cancelled},
                  {"tiles_received", assembler->tiles_received()},
                  {"partial_output", kept.rfind("; kept", 0) == 0 ? output_name(cmd) : ""}});
      throw CommandFailure{kExitInterrupted, "interrupted: " + what + kept};
    }
    discard_output(*assembler, cmd);
    const bool job_cancelled = e.code() == grpc::StatusCode::CANCELLED;
    const bool job_failed = e.code() == grpc::StatusCode::ABORTED;
    print_json({{"event", job_cancelled ? "cancelled"
                          : job_failed  ? "failed"
                                        : "error"},
                {"job_id", job.id()},
                {"message", e.message()}});
    // The server's message already names the job and the reason ("job X was cancelled (...)").
    if (job_cancelled)
      throw CommandFailure{
          kExitFailed, (e.message().empty() ? "job " + job.id() + " was cancelled" : e.message()) +
                           "; " + received + " received"};
    if (job_failed)
      throw CommandFailure{kExitFailed,
                           e.message().empty() ? "job " + job.id() + " failed" : e.message()};
    throw CommandFailure{kExitFailed,
                         describe(e, cmd.server, "streaming tiles of job " + job.id() + " failed")};
  } catch (const std::exception& e) {
    progress.finish();
    discard_output(*assembler, cmd);
    print_json({{"event", "error"}, {"job_id", job.id()}, {"message", e.what()}});
    throw CommandFailure{kExitFailed, "job " + job.id() + ": " + e.what()};
  }
  stopper.reset();
  progress.finish();
  // The job's time as the server measured it (from its first tile's start to its finish),
  // so `watch` and `status` agree whenever the watch began; the last tile's if GetJob fails.
  v1::Job finished = job;
  try {
    finished = client.get(job.id());
  } catch (const ClientError&) {
    finished.mutable_progress()->CopyFrom(last);
  }
  const v1::JobProgress& final_progress = finished.progress();
  const double seconds = final_progress.elapsed_seconds() > 0.0 ? final_progress.elapsed_seconds()
                                                                : last.elapsed_seconds();
  const double rays_per_second =
      final_progress.rays_per_second() > 0.0 ? final_progress.rays_per_second()
      : seconds > 0.0 ? static_cast<double>(final_progress.rays_traced()) / seconds
                      : 0.0;
  finish_output(*assembler, cmd, settings_summary(s.width(), s.height(), s.samples_per_pixel()),
                seconds, rays_per_second, cmd.json ? io.err : io.out,
                output_metadata(job.name(), job.id(), s.samples_per_pixel(), scene));
  nlohmann::json done = {{"event", "completed"},
                         {"job", job_to_json(finished)},
                         {"elapsed_seconds", seconds},
                         {"output", output_name(cmd)}};
  if (!cmd.preview_png.empty()) done["png"] = cmd.preview_png;
  print_json(done);
  return kExitOk;
}

// ---- Commands -----------------------------------------------------------------------------

int render_remote(const CliCommand& cmd, const CommandOutput& io) {
  const SceneDescription scene = load_scene_for_server(cmd, io.err);
  // Open the output before queueing work, so an unwritable path fails fast.
  auto assembler = open_output(cmd, scene.render.width, scene.render.height, scene.render.tile_size,
                               scene.render.aovs, scene.render.pass_count());
  Client client(client_options(cmd));
  v1::Job job;
  try {
    v1::SubmitJobRequest request = make_submit_request(scene, job_name(cmd), cmd.priority);
    request.set_request_id(cmd.request_id.empty() ? make_request_id() : cmd.request_id);
    job = client.submit(request);
  } catch (const ClientError& e) {
    discard_output(*assembler, cmd);
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "server rejected the scene")};
  }
  io.err << "tessera: job " << job.id() << " submitted to " << cmd.server << " ("
         << settings_summary(job.settings().width(), job.settings().height(),
                             job.settings().samples_per_pixel())
         << ", " << job.progress().tiles_total()
         << (job.settings().passes() > 1
                 ? " tile passes in " + std::to_string(job.settings().passes()) + " passes)\n"
                 : std::string(" tiles)\n"))
         << std::flush;
  return stream_job(client, job, cmd, std::move(assembler), true, io, &scene);
}

// render.passes is ignored here: the tiles render in one pass, which gives the image the
// last of the passes would (passes only change what a watcher of a daemon's job sees).
int render_in_process(const CliCommand& cmd, const CommandOutput& io) {
  const Clock::time_point start = Clock::now();
  const SceneDescription scene = load_scene(cmd, io.err);
  auto assembler = open_output(cmd, scene.render.width, scene.render.height, scene.render.tile_size,
                               scene.render.aovs);
  std::shared_ptr<const PreparedScene> prepared;
  try {
    prepared = PreparedScene::build(scene);
  } catch (const SceneError& e) {
    discard_output(*assembler, cmd);
    throw CommandFailure{kExitUsage, e.what()};
  }
  const unsigned threads =
      cmd.threads > 0 ? cmd.threads : std::max(1u, std::thread::hardware_concurrency());
  io.err << "tessera: rendering "
         << settings_summary(scene.render.width, scene.render.height,
                             scene.render.samples_per_pixel)
         << " locally on " << threads << " threads (" << assembler->tiles_total() << " tiles)\n"
         << std::flush;

  ProgressReporter progress(io.err, io.interactive);
  const Clock::time_point render_start = Clock::now();
  ProgressSnapshot snapshot;
  snapshot.tiles_total = assembler->tiles_total();
  InterruptScope interrupt_scope;
  LocalRenderResult result;
  try {
    result = render_local(
        *prepared, threads,
        [&](const TileRect& tile, std::span<const float> rgba, std::uint64_t rays) {
          assembler->add_tile(tile, rgba);
          ++snapshot.tiles_done;
          snapshot.rays += rays;
          snapshot.elapsed_seconds = seconds_since(render_start);
          snapshot.rays_per_second =
              snapshot.elapsed_seconds > 0.0
                  ? static_cast<double>(snapshot.rays) / snapshot.elapsed_seconds
                  : 0.0;
          snapshot.eta_seconds = snapshot.elapsed_seconds / snapshot.tiles_done *
                                 static_cast<double>(snapshot.tiles_total - snapshot.tiles_done);
          progress.update(snapshot);
        },
        &g_interrupted);
  } catch (const std::exception& e) {
    progress.finish();
    discard_output(*assembler, cmd);
    throw CommandFailure{kExitFailed, e.what()};
  }
  progress.finish();
  if (result.stopped) {
    if (cmd.keep_partial && assembler->tiles_received() > 0) {
      ImageMetadata metadata =
          output_metadata(job_name(cmd), "", scene.render.samples_per_pixel, &scene);
      metadata.render_seconds = seconds_since(start);
      try {
        assembler->finish_partial(metadata);
      } catch (const std::exception& e) {
        discard_output(*assembler, cmd);
        throw CommandFailure{kExitInterrupted, "interrupted; could not keep the partial image: " +
                                                   std::string(e.what())};
      }
      throw CommandFailure{kExitInterrupted, "interrupted; kept " +
                                                 std::to_string(assembler->tiles_received()) +
                                                 " of " + std::to_string(assembler->tiles_total()) +
                                                 " tiles in " + output_name(cmd)};
    }
    discard_output(*assembler, cmd);
    throw CommandFailure{kExitInterrupted, "interrupted"};
  }
  const double rays_per_second =
      result.seconds > 0.0 ? static_cast<double>(result.rays) / result.seconds : 0.0;
  finish_output(
      *assembler, cmd,
      settings_summary(scene.render.width, scene.render.height, scene.render.samples_per_pixel),
      seconds_since(start), rays_per_second, io.out,
      output_metadata(job_name(cmd), "", scene.render.samples_per_pixel, &scene));
  return kExitOk;
}

int submit(const CliCommand& cmd, const CommandOutput& io) {
  const SceneDescription scene = load_scene_for_server(cmd, io.err);
  Client client(client_options(cmd));
  try {
    v1::SubmitJobRequest request = make_submit_request(scene, job_name(cmd), cmd.priority);
    add_labels(cmd.labels, *request.mutable_labels());
    request.set_submitter(cmd.submitter);
    request.set_request_id(cmd.request_id.empty() ? make_request_id() : cmd.request_id);
    const v1::Job job = client.submit(request);
    if (cmd.json)
      io.out << job_to_json(job).dump() << '\n' << std::flush;
    else
      io.out << job.id() << '\n' << std::flush;
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "server rejected the scene")};
  }
  return kExitOk;
}

// The request submit would send, written for another program (the Python client) to send:
// the scene goes through this loader and conversion whatever the language of the caller.
int convert(const CliCommand& cmd, const CommandOutput& io) {
  const SceneDescription scene = load_scene_for_server(cmd, io.err);
  v1::SubmitJobRequest request = make_submit_request(scene, job_name(cmd), cmd.priority);
  add_labels(cmd.labels, *request.mutable_labels());
  request.set_submitter(cmd.submitter);
  std::string bytes;
  if (!request.SerializeToString(&bytes))
    throw CommandFailure{kExitFailed, "cannot encode the request (" +
                                          std::to_string(request.ByteSizeLong()) + " bytes)"};
  if (cmd.request_output == kStandardStream) {
    io.out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    io.out.flush();
    if (!io.out) throw CommandFailure{kExitFailed, "cannot write the request to standard output"};
    return kExitOk;
  }
  create_parent_directory(cmd.request_output);
  std::ofstream file(cmd.request_output, std::ios::binary | std::ios::trunc);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file)
    throw CommandFailure{kExitFailed,
                         "cannot write " + cmd.request_output + ": " + std::strerror(errno)};
  return kExitOk;
}

int watch(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  v1::Job job;
  try {
    job = client.get(cmd.job_id);
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "cannot watch job " + cmd.job_id)};
  }
  // Ctrl-C stops watching; the job is not ours to cancel unless --cancel says so.
  return stream_job(client, job, cmd, nullptr, cmd.cancel_on_interrupt, io);
}

std::string progress_cell(const v1::Job& job) {
  const v1::JobProgress& p = job.progress();
  return std::to_string(p.tiles_done()) + "/" + std::to_string(p.tiles_total()) + " (" +
         std::to_string(percent_done(snapshot_of(p))) + "%)";
}

int list(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  std::vector<v1::Job> jobs;
  v1::ListJobsRequest filters;
  filters.set_label(cmd.label_filter);
  filters.set_name(cmd.name_filter);
  filters.set_submitter(cmd.submitter);
  if (!cmd.state_filter.empty()) {
    v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
    std::string name = "JOB_STATE_" + cmd.state_filter;
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return std::toupper(c); });
    if (!v1::JobState_Parse(name, &state))
      throw CommandFailure{kExitUsage, "--state: unknown state '" + cmd.state_filter + "'"};
    filters.set_state(state);
  }
  try {
    if (cmd.limit == 0) {
      jobs = client.list(filters);
    } else {
      // Page by page, newest first, until the limit: no more is fetched than printed.
      filters.set_page_size(std::min<std::uint32_t>(cmd.limit, 1000));
      for (;;) {
        const v1::ListJobsResponse page = client.list_page(filters);
        for (const v1::Job& job : page.jobs())
          if (jobs.size() < cmd.limit) jobs.push_back(job);
        if (jobs.size() >= cmd.limit || page.next_page_token().empty()) break;
        filters.set_page_token(page.next_page_token());
      }
    }
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "listing jobs failed")};
  }
  if (cmd.json) {
    nlohmann::json array = nlohmann::json::array();
    for (const v1::Job& job : jobs) array.push_back(job_to_json(job));
    io.out << nlohmann::json{{"jobs", array}}.dump() << '\n' << std::flush;
    return kExitOk;
  }
  if (jobs.empty()) {
    io.out << "no jobs\n";
    return kExitOk;
  }
  const std::vector<std::string> header = {"ID",       "NAME",     "STATE",
                                           "PROGRESS", "PRIORITY", "SUBMITTED"};
  std::vector<std::vector<std::string>> rows = {header};
  for (const v1::Job& job : jobs)
    rows.push_back({job.id(), job.name().empty() ? "-" : job.name(), job_state_name(job.state()),
                    progress_cell(job), std::to_string(job.priority()),
                    format_unix_ms(job.submitted_unix_ms())});
  std::vector<std::size_t> widths(header.size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      io.out << row[c];
      if (c + 1 < row.size()) io.out << std::string(widths[c] - row[c].size() + 2, ' ');
    }
    io.out << '\n';
  }
  io.out << std::flush;
  return kExitOk;
}

int status(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  v1::Job job;
  try {
    job = client.get(cmd.job_id);
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "cannot get job " + cmd.job_id)};
  }
  if (cmd.json) {
    io.out << job_to_json(job).dump() << '\n' << std::flush;
    return kExitOk;
  }
  const v1::RenderSettings& s = job.settings();
  const v1::JobProgress& p = job.progress();
  io.out << "job        " << job.id() << '\n'
         << "name       " << (job.name().empty() ? "-" : job.name()) << '\n'
         << "state      " << job_state_name(job.state()) << '\n'
         << "priority   " << job.priority() << '\n'
         << "submitter  " << (job.submitter().empty() ? "-" : job.submitter()) << '\n'
         << "labels     " << labels_text(job.labels()) << '\n'
         << "image      " << settings_summary(s.width(), s.height(), s.samples_per_pixel())
         << ", max depth " << s.max_depth() << ", tiles of " << s.tile_size() << ", seed "
         << s.seed()
         << (s.passes() > 1
                 ? ", " + std::to_string(s.passes()) + " passes (progress counts tile passes)"
                 : std::string())
         << '\n'
         << "progress   " << format_progress_line(snapshot_of(p)) << '\n'
         << "elapsed    " << format_duration(p.elapsed_seconds()) << ", " << p.rays_traced()
         << " rays\n"
         << "submitted  " << format_unix_ms(job.submitted_unix_ms()) << '\n'
         << "finished   " << format_unix_ms(job.finished_unix_ms()) << '\n';
  if (!job.error().empty()) io.out << "error      " << job.error() << '\n';
  io.out << std::flush;
  return kExitOk;
}

int cancel(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  try {
    const v1::Job job = client.cancel(cmd.job_id);
    io.out << "job " << job.id() << ": " << job_state_name(job.state()) << '\n' << std::flush;
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "cannot cancel job " + cmd.job_id)};
  }
  return kExitOk;
}

int remove(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  try {
    client.remove(cmd.job_id);
    io.out << "job " << cmd.job_id << ": deleted\n" << std::flush;
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "cannot delete job " + cmd.job_id)};
  }
  return kExitOk;
}

// pause, resume, retry: one call naming a job; prints the job's state after it.
template <typename Call>
int control(const CliCommand& cmd, const CommandOutput& io, const std::string& verb, Call&& call) {
  Client client(client_options(cmd));
  try {
    const v1::Job job = call(client);
    io.out << "job " << job.id() << ": " << job_state_name(job.state()) << '\n' << std::flush;
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed,
                         describe(e, cmd.server, "cannot " + verb + " job " + cmd.job_id)};
  }
  return kExitOk;
}

int update(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  v1::UpdateJobRequest request;
  request.set_job_id(cmd.job_id);
  if (cmd.new_priority) request.set_priority(*cmd.new_priority);
  if (cmd.new_submitter) request.set_submitter(*cmd.new_submitter);
  add_labels(cmd.labels, *request.mutable_set_labels());
  for (const std::string& key : cmd.remove_labels) request.add_remove_labels(key);
  try {
    const v1::Job job = client.update(request);
    io.out << "job " << job.id() << ": priority " << job.priority() << ", submitter "
           << job.submitter() << ", labels " << labels_text(job.labels()) << '\n'
           << std::flush;
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "cannot update job " + cmd.job_id)};
  }
  return kExitOk;
}

// One line per event: time, job, state, progress, name; "(snapshot)" for the opening ones.
int events(const CliCommand& cmd, const CommandOutput& io) {
  Client client(client_options(cmd));
  v1::WatchJobsRequest request;
  request.set_job_id(cmd.job_id);
  request.set_submitter(cmd.submitter);
  request.set_label(cmd.label_filter);
  // Ctrl-C ends the process the usual way: a watch has nothing to clean up.
  try {
    client.watch_jobs(request, [&](const v1::JobEvent& event) {
      const v1::Job& job = event.job();
      io.out << format_unix_ms(std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count())
             << "  " << job.id() << "  "
             << (event.deleted() ? std::string("deleted") : job_state_name(job.state()));
      if (!event.deleted())
        io.out << "  " << progress_cell(job) << "  " << (job.name().empty() ? "-" : job.name());
      if (event.snapshot()) io.out << "  (snapshot)";
      if (!job.error().empty()) io.out << "  error: " << job.error();
      io.out << '\n' << std::flush;
      return true;
    });
  } catch (const ClientError& e) {
    throw CommandFailure{kExitFailed, describe(e, cmd.server, "watching jobs failed")};
  }
  return kExitOk;
}

// The client's version, then the server's. The exit status is 0 whether or not the server
// answers: the client's version is always known, and `tessera health` is the reachability
// check.
int version(const CliCommand& cmd, const CommandOutput& io) {
  io.out << "tessera " << TESSERA_VERSION << '\n';
  ClientOptions options = client_options(cmd);
  options.unary_deadline = std::chrono::seconds(3);
  Client client(options);
  try {
    const v1::ServerInfo info = client.server_info();
    const v1::BuildInfo& build = info.build();
    std::string details = build.git_commit().empty() ? "" : "commit " + build.git_commit();
    for (const std::string& part : {build.compiler(), build.build_type()})
      if (!part.empty()) details += (details.empty() ? "" : ", ") + part;
    io.out << "server: tesserad " << info.version() << " at " << cmd.server
           << (details.empty() ? "" : " (" + details + ")") << '\n';
  } catch (const ClientError& e) {
    io.out << "server: "
           << (e.code() == grpc::StatusCode::UNIMPLEMENTED
                   ? "a tesserad without GetServerInfo (older than this client)"
                   : "unreachable")
           << " (" << cmd.server << ": " << e.what() << ")\n";
  }
  io.out << std::flush;
  return kExitOk;
}

// grpc.health.v1 Check of the RenderService: exit 0 when SERVING, 1 otherwise (not serving,
// unreachable, or an error), with one line saying which.
int health(const CliCommand& cmd, const CommandOutput& io) {
  ClientOptions options = client_options(cmd);
  options.unary_deadline = std::chrono::seconds(5);
  Client client(options);
  try {
    if (client.healthy()) {
      io.out << "tesserad at " << cmd.server << ": serving\n" << std::flush;
      return kExitOk;
    }
    io.err << "tessera: tesserad at " << cmd.server << " is not serving\n" << std::flush;
  } catch (const ClientError& e) {
    io.err << "tessera: " << describe(e, cmd.server, "health check failed") << '\n' << std::flush;
  }
  return kExitFailed;
}

int denoise_file(const CliCommand& cmd, const CommandOutput& io) {
  const Clock::time_point start = Clock::now();
  create_parent_directory(cmd.output_exr);
  if (!cmd.preview_png.empty()) create_parent_directory(cmd.preview_png);
  try {
    denoise_exr_file(cmd.input_exr, cmd.output_exr, cmd.preview_png, preview_options(cmd));
  } catch (const std::exception& e) {
    throw CommandFailure{kExitFailed, e.what()};
  }
  io.out << "tessera: denoised " << cmd.input_exr << " in " << format_duration(seconds_since(start))
         << ": " << cmd.output_exr;
  if (!cmd.preview_png.empty()) io.out << ", " << cmd.preview_png;
  io.out << '\n' << std::flush;
  return kExitOk;
}

// `-o -`: the command writes a temporary EXR, copied to stdout once it is complete (the
// EXR is rewritten whole when it finishes, so it cannot be streamed as it is made); the
// summary line goes to stderr so that stdout holds the image alone.
int run_with_stdout_image(const CliCommand& command, const CommandOutput& io) {
  CliCommand to_file = command;
  std::random_device random;
  const std::filesystem::path temporary =
      std::filesystem::temp_directory_path() /
      ("tessera-stdout-" + std::to_string(::getpid()) + "-" + std::to_string(random()) + ".exr");
  to_file.output_exr = temporary.string();
  to_file.output_to_stdout = true;
  struct RemoveTemporary {
    std::filesystem::path path;
    ~RemoveTemporary() {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  } remove_temporary{temporary};
  const int code = run_command(to_file, CommandOutput{io.err, io.err, io.interactive});
  std::error_code missing;
  if ((code == kExitOk || code == kExitInterrupted) &&
      std::filesystem::exists(temporary, missing)) {
    std::ifstream in(temporary, std::ios::binary);
    io.out << in.rdbuf() << std::flush;
    if (!io.out) {
      io.err << "tessera: cannot write the image to stdout\n" << std::flush;
      return kExitFailed;
    }
  }
  return code;
}

int run_render(const CliCommand& command, const CommandOutput& io) {
  return command.local ? render_in_process(command, io) : render_remote(command, io);
}

int token_hash(const CommandOutput& io) {
  std::string digest;
  try {
    digest = hash_token(std::cin);
  } catch (const std::invalid_argument& e) {
    throw CommandFailure{kExitUsage, std::string("token hash: ") + e.what()};
  }
  io.out << digest << '\n' << std::flush;
  return kExitOk;
}

}  // namespace

int run_command(const CliCommand& command, const CommandOutput& io) {
  if ((command.kind == CommandKind::kRender || command.kind == CommandKind::kWatch) &&
      command.output_exr == kStdoutPath)
    return run_with_stdout_image(command, io);
  try {
    switch (command.kind) {
      case CommandKind::kRender:
        return run_render(command, io);
      case CommandKind::kSubmit:
        return submit(command, io);
      case CommandKind::kWatch:
        return watch(command, io);
      case CommandKind::kList:
        return list(command, io);
      case CommandKind::kStatus:
        return status(command, io);
      case CommandKind::kCancel:
        return cancel(command, io);
      case CommandKind::kDelete:
        return remove(command, io);
      case CommandKind::kDenoise:
        return denoise_file(command, io);
      case CommandKind::kPause:
        return control(command, io, "pause", [&](Client& c) { return c.pause(command.job_id); });
      case CommandKind::kResume:
        return control(command, io, "resume", [&](Client& c) { return c.resume(command.job_id); });
      case CommandKind::kRetry:
        return control(command, io, "retry", [&](Client& c) { return c.retry(command.job_id); });
      case CommandKind::kUpdate:
        return update(command, io);
      case CommandKind::kEvents:
        return events(command, io);
      case CommandKind::kConvert:
        return convert(command, io);
      case CommandKind::kVersion:
        return version(command, io);
      case CommandKind::kHealth:
        return health(command, io);
      case CommandKind::kTokenHash:
        return token_hash(io);
    }
    return kExitUsage;
  } catch (const CommandFailure& failure) {
    io.err << "tessera: " << failure.message << '\n' << std::flush;
    return failure.exit_code;
  } catch (const ClientError& e) {
    io.err << "tessera: " << describe(e, command.server, "request failed") << '\n' << std::flush;
    return kExitFailed;
  } catch (const std::exception& e) {
    io.err << "tessera: " << e.what() << '\n' << std::flush;
    return kExitFailed;
  }
}

}  // namespace tessera
