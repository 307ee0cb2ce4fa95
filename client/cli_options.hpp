#pragma once
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace tessera {

inline constexpr const char* kDefaultServer = "127.0.0.1:50051";

enum class CommandKind {
  kRender,
  kSubmit,
  kWatch,
  kList,
  kStatus,
  kCancel,
  kDelete,
  kDenoise,
  kPause,
  kResume,
  kRetry,
  kUpdate,
  kEvents,
  kConvert,
  kVersion,  // tessera --version, tessera version
  kHealth,
  kTokenHash
};

// How every command that talks to a server (those with --server) authenticates and
// encrypts (client_connection.hpp turns it into ClientOptions).
struct ConnectionSecurity {
  std::string token;             // --token or TESSERA_TOKEN: the bearer token; empty: none
  std::string ca_file;           // --ca or TESSERA_CA: the server's CA (PEM); implies TLS
  std::string client_cert_file;  // --client-cert: this client's certificate (PEM), mTLS
  std::string client_key_file;   // --client-key: its private key (PEM)
  bool tls = false;              // --tls: TLS with the system's roots, no --ca needed
};

// Values given on the command line replace the scene file's `render` section.
struct RenderOverrides {
  std::optional<std::uint32_t> width;
  std::optional<std::uint32_t> height;
  std::optional<std::uint32_t> samples_per_pixel;
  std::optional<std::uint32_t> max_depth;
  std::optional<std::uint32_t> tile_size;
  std::optional<std::uint64_t> seed;
  std::optional<std::uint32_t> passes;
  std::optional<std::string> accel_builder;  // auto, spatial or binned
};

// One parsed and validated `tessera` invocation.
struct CliCommand {
  CommandKind kind = CommandKind::kList;
  std::string server = kDefaultServer;
  std::string scene_path;   // render, submit, convert ("-": standard input)
  std::string job_id;       // watch, status, cancel, delete, pause, resume, retry, update, events
  std::string input_exr;    // denoise
  std::string output_exr;   // render, watch, denoise
  std::string preview_png;  // render, watch, denoise; empty: none
  double preview_exposure = 0.0;       // stops, applied to the PNG preview only
  std::string preview_tone = "clamp";  // the PNG preview's tone curve: clamp or aces
  RenderOverrides overrides;
  bool local = false;    // render in-process instead of through a server
  unsigned threads = 0;  // --local worker threads; 0: all hardware threads
  std::string name;      // job name; empty: the scene file's stem
  std::int32_t priority = 0;
  bool lenient = false;  // unknown scene keys are warnings instead of errors
  bool denoise = false;  // render: add the denoiser's AOVs and denoised.R/G/B channels
  // submit, update: labels to set, each "key=value".
  std::vector<std::string> labels;
  std::vector<std::string> remove_labels;    // update: label keys to remove
  std::optional<std::int32_t> new_priority;  // update
  std::optional<std::string> new_submitter;  // update
  std::string submitter;                     // submit; list and events: filter
  std::string label_filter;                  // list, events: "key=value" or "key"
  std::string name_filter;                   // list
  std::string request_output;  // convert: file for the SubmitJobRequest bytes; "-": stdout
  // render, submit: SubmitJobRequest.request_id; empty: a random one per invocation.
  std::string request_id;
  bool json = false;                 // submit, list, status, watch: machine-readable output
  std::string state_filter;          // list: queued, running, paused, completed, failed, cancelled
  std::uint32_t limit = 0;           // list: at most this many jobs, newest first; 0: all
  bool keep_partial = false;         // render, watch: on Ctrl-C, write the tiles received so far
  bool cancel_on_interrupt = false;  // watch: Ctrl-C also cancels the job (render always does)
  // Set by the commands for `-o -`: output_exr is then a temporary file copied to stdout.
  bool output_to_stdout = false;
  ConnectionSecurity security;
};

// The exit code of a command ended by Ctrl-C (128 + SIGINT, as shells report it).
inline constexpr int kExitInterrupted = 130;
// `-o -`: the EXR goes to standard output.
inline constexpr const char* kStdoutPath = "-";

struct ParsedCommandLine {
  std::optional<CliCommand> command;  // empty: nothing to run, exit with exit_code
  int exit_code = 0;
};

// Exit codes of `tessera`.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;  // job failed or was cancelled, server or I/O error
inline constexpr int kExitUsage = 2;   // bad arguments or a bad scene

// Parses argv. Help goes to `out` (exit 0); a usage error is one line `tessera: <message>`
// on `err` (exit 2).
ParsedCommandLine parse_command_line(int argc, const char* const* argv, std::ostream& out,
                                     std::ostream& err);

// Why `address` is not a usable server address, or nothing if it is: "HOST:PORT" with a
// port in 1..65535 ("[::1]:PORT" for IPv6), or a gRPC "unix:" / "dns:" target.
std::optional<std::string> check_server_address(const std::string& address);

}  // namespace tessera
