#include "client/cli_options.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>

#include "client/cli_completion.hpp"
#include "client/job_json.hpp"
#include "tessera/scene/scene_description.hpp"
#include "tessera/scene/schema/kinds.hpp"
#include "tessera/scene/schema/suggest.hpp"

namespace tessera {

std::optional<std::string> check_server_address(const std::string& address) {
  if (address.empty()) return "must not be empty; expected HOST:PORT";
  if (address.rfind("unix:", 0) == 0 || address.rfind("dns:", 0) == 0) return std::nullopt;
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) return "'" + address + "' has no port; expected HOST:PORT";
  const std::string host = address.substr(0, colon);
  const std::string port = address.substr(colon + 1);
  if (host.empty()) return "'" + address + "' has no host; expected HOST:PORT";
  if (host.front() == '[' ? host.back() != ']' || host.size() < 3
                          : host.find(':') != std::string::npos)
    return "'" + address + "': write an IPv6 host in brackets, e.g. [::1]:50051";
  if (port.empty() || port.size() > 5 ||
      !std::all_of(port.begin(), port.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
    return "'" + address + "' has no valid port; expected HOST:PORT with PORT in 1..65535";
  const int number = std::stoi(port);
  if (number < 1 || number > 65535) return "port " + port + " is out of range 1..65535";
  return std::nullopt;
}

namespace {

// "KEY=VALUE" with a non-empty key; the server checks the rest.
CLI::Validator label_validator() {
  return CLI::Validator(
      [](std::string& value) {
        const auto equals = value.find('=');
        if (equals == std::string::npos || equals == 0)
          return "'" + value + "' is not a label; expected KEY=VALUE";
        return std::string();
      },
      "KEY=VALUE");
}

CLI::Validator server_address_validator() {
  return CLI::Validator(
      [](std::string& value) {
        const auto problem = check_server_address(value);
        return problem ? *problem : std::string();
      },
      "HOST:PORT");
}

CLI::Validator extension_validator(std::string extension) {
  return CLI::Validator(
      [extension](std::string& value) {
        std::string ext = std::filesystem::path(value).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        if (ext != extension) return "'" + value + "' must end in " + extension;
        return std::string();
      },
      "FILE" + extension);
}

// The server's rule for SubmitJobRequest.request_id, checked before the scene is loaded.
CLI::Validator request_id_validator() {
  return CLI::Validator(
      [](std::string& value) {
        if (value.empty() || value.size() > 128)
          return "must be 1 to 128 characters, got " + std::to_string(value.size());
        for (const char c : value)
          if (c < 0x20 || c > 0x7e) return std::string("must be printable ASCII");
        return std::string();
      },
      "ID");
}

void add_request_id_option(CLI::App& command, std::string& request_id) {
  command
      .add_option("--request-id", request_id,
                  "idempotency key: resubmitting with the same id returns the job it created "
                  "instead of a new one (default: a random id, retried on timeouts)")
      ->check(request_id_validator());
}

// An EXR path, or "-" for standard output.
CLI::Validator exr_output_validator() {
  const CLI::Validator exr = extension_validator(".exr");
  return CLI::Validator(
      [exr](std::string& value) {
        if (value == kStdoutPath) return std::string();
        std::string copy = value;
        return exr(copy);
      },
      "FILE.exr|-");
}

CLI::Validator non_empty_validator() {
  return CLI::Validator(
      [](std::string& value) {
        return value.empty() ? std::string("must not be empty") : std::string();
      },
      "TEXT");
}

void add_server_option(CLI::App& command, std::string& server) {
  command.add_option("--server", server, "tesserad address (default: $TESSERA_SERVER, else this)")
      ->check(server_address_validator())
      ->capture_default_str();
}

// Range-checked integer options whose absence leaves the scene file's value.
class OverrideOptions {
 public:
  explicit OverrideOptions(CLI::App& command) {
    const SceneLimits limits;
    width_ = command.add_option("--width", width_value_, "image width in pixels")
                 ->check(CLI::Range(1u, limits.max_width));
    height_ = command.add_option("--height", height_value_, "image height in pixels")
                  ->check(CLI::Range(1u, limits.max_height));
    spp_ = command.add_option("--spp", spp_value_, "samples per pixel")
               ->check(CLI::Range(1u, limits.max_samples_per_pixel));
    depth_ = command.add_option("--max-depth", depth_value_, "maximum path length")
                 ->check(CLI::Range(1u, limits.max_depth));
    tile_ = command.add_option("--tile-size", tile_value_, "tile edge in pixels")
                ->check(CLI::Range(limits.min_tile_size, limits.max_tile_size));
    seed_ = command.add_option("--seed", seed_value_, "random seed");
    passes_ = command
                  .add_option("--passes", passes_value_,
                              "progressive passes: the server sends every tile after each pass "
                              "and the output is rewritten as each pass completes")
                  ->check(CLI::Range(0u, limits.max_samples_per_pixel));
    accel_builder_ =
        command
            .add_option("--accel-builder", accel_builder_value_,
                        "triangle structure: auto, spatial (spatial splits for every mesh) or "
                        "binned (shortest build, for previews); never changes the image")
            ->check(CLI::IsMember(
                schema::choice_names(schema::field_choices<schema::RenderKind>("accel_builder"))));
  }

  RenderOverrides values() const {
    RenderOverrides o;
    if (*width_) o.width = width_value_;
    if (*height_) o.height = height_value_;
    if (*spp_) o.samples_per_pixel = spp_value_;
    if (*depth_) o.max_depth = depth_value_;
    if (*tile_) o.tile_size = tile_value_;
    if (*seed_) o.seed = seed_value_;
    if (*passes_) o.passes = passes_value_;
    if (*accel_builder_) o.accel_builder = accel_builder_value_;
    return o;
  }

 private:
  std::uint32_t width_value_ = 0, height_value_ = 0, spp_value_ = 0, depth_value_ = 0,
                tile_value_ = 0, passes_value_ = 0;
  std::uint64_t seed_value_ = 0;
  std::string accel_builder_value_;
  CLI::Option *width_, *height_, *spp_, *depth_, *tile_, *seed_, *passes_, *accel_builder_;
};

// The PNG preview's exposure and tone curve (the EXR keeps the linear radiance).
void add_preview_options(CLI::App& command, CliCommand& cmd) {
  command
      .add_option("--exposure", cmd.preview_exposure,
                  "PNG preview exposure in stops (radiance times 2^stops)")
      ->check(CLI::Range(-32.0, 32.0));
  command
      .add_option("--tone", cmd.preview_tone,
                  "PNG preview tone curve: clamp (default) or aces (filmic highlight roll-off)")
      ->check(CLI::IsMember({"clamp", "aces"}));
}

// The API's job states as the CLI writes them ("queued", ...), from the protobuf enum.
std::vector<std::string> job_state_names() {
  std::vector<std::string> names;
  const google::protobuf::EnumDescriptor* states = v1::JobState_descriptor();
  for (int i = 0; i < states->value_count(); ++i) {
    const auto state = static_cast<v1::JobState>(states->value(i)->number());
    if (state != v1::JOB_STATE_UNSPECIFIED) names.push_back(job_state_name(state));
  }
  return names;
}

// "; for '--spd' did you mean '--spp'?" for the first argument that looks like a flag of `command`
// but is none, or "" when there is none or nothing is close.
std::string unknown_flag_hint(const CLI::App& command, int argc, const char* const* argv) {
  const std::vector<std::string> names = flag_names(command);
  std::vector<std::string_view> long_names;
  for (const std::string& name : names)
    if (name.rfind("--", 0) == 0) long_names.push_back(name);
  for (int i = 1; i < argc; ++i) {
    std::string_view word = argv[i];
    if (word.rfind("--", 0) != 0 || word.size() == 2) continue;
    word = word.substr(0, word.find('='));
    if (std::find(names.begin(), names.end(), word) != names.end()) continue;
    const std::string match = schema::closest_match(word, long_names);
    if (!match.empty()) return "; for '" + std::string(word) + "' did you mean '" + match + "'?";
  }
  return {};
}

// The TLS and token flags, on every command that has --server (so a command added later
// gets them too).
void add_security_options(CLI::App& command, ConnectionSecurity& security) {
  // Named FILE by type_name alone, not "FILE:FILE".
  const CLI::Validator existing_file = CLI::Validator(CLI::ExistingFile).description("");
  command
      .add_option("--token", security.token,
                  "bearer token for a server started with --tokens (default: $TESSERA_TOKEN, "
                  "which is safer: a flag shows in the process list)")
      ->type_name("TOKEN");
  command
      .add_option("--ca", security.ca_file,
                  "CA certificate (PEM) the server's TLS certificate must chain to; implies --tls "
                  "(default: $TESSERA_CA)")
      ->type_name("FILE")
      ->check(existing_file);
  CLI::Option* cert =
      command
          .add_option("--client-cert", security.client_cert_file,
                      "this client's certificate (PEM) for a server that requires one (mTLS); "
                      "implies --tls")
          ->type_name("FILE")
          ->check(existing_file);
  CLI::Option* key =
      command.add_option("--client-key", security.client_key_file, "the client certificate's key")
          ->type_name("FILE")
          ->check(existing_file);
  cert->needs(key);
  key->needs(cert);
  command.add_flag("--tls", security.tls,
                   "connect with TLS, checking the server against the system's CA certificates");
}

// TESSERA_TOKEN and TESSERA_CA where the flags are not given; why TESSERA_CA is unusable,
// or nothing. Read here rather than with CLI11's envname: CLI11 2.1 fills the environment
// into the options of every subcommand, parsed or not, and all of them write the same
// variable, so the environment would override the flag of the command that ran.
std::optional<std::string> apply_security_environment(ConnectionSecurity& security) {
  if (const char* token = std::getenv("TESSERA_TOKEN"); token && security.token.empty())
    security.token = token;
  if (const char* ca = std::getenv("TESSERA_CA"); ca && *ca && security.ca_file.empty()) {
    if (!std::filesystem::is_regular_file(ca))
      return std::string("TESSERA_CA: '") + ca + "' is not a file";
    security.ca_file = ca;
  }
  return std::nullopt;
}

}  // namespace

ParsedCommandLine parse_command_line(int argc, const char* const* argv, std::ostream& out,
                                     std::ostream& err) {
  CLI::App app("Tessera: submit scenes to tesserad and collect the rendered image.", "tessera");
  app.require_subcommand(1);
  CliCommand cmd;

  CLI::App* render =
      app.add_subcommand("render", "render a scene through the server (or --local) and save it");
  render->add_option("scene", cmd.scene_path, "scene YAML file")->required();
  render->add_option("-o,--output", cmd.output_exr, "output image (tiled EXR; - for stdout)")
      ->required()
      ->check(exr_output_validator());
  render->add_flag("--keep-partial", cmd.keep_partial,
                   "on Ctrl-C, write the tiles received so far (the rest black, alpha 0)");
  render->add_option("--png", cmd.preview_png, "also write an 8-bit sRGB PNG preview")
      ->check(extension_validator(".png"));
  add_preview_options(*render, cmd);
  OverrideOptions render_overrides(*render);
  CLI::Option* local =
      render->add_flag("--local", cmd.local, "render in this process instead of on a server");
  render
      ->add_option("--threads", cmd.threads,
                   "worker threads for --local (default: all hardware threads)")
      ->check(CLI::Range(1u, 1024u))
      ->needs(local);
  render->add_option("--name", cmd.name, "job name (default: the scene file's name)");
  render->add_option("--priority", cmd.priority, "higher runs first");
  render->add_flag("--lenient", cmd.lenient, "unknown scene keys are warnings, not errors");
  render->add_flag("--denoise", cmd.denoise,
                   "also render the albedo, normal and variance AOVs and add a denoised pass "
                   "(channels denoised.R/G/B; the PNG preview shows it)");
  add_request_id_option(*render, cmd.request_id);
  add_server_option(*render, cmd.server);

  CLI::App* submit =
      app.add_subcommand("submit", "queue a scene on the server and print the job id");
  submit->add_option("scene", cmd.scene_path, "scene YAML file")->required();
  OverrideOptions submit_overrides(*submit);
  submit->add_option("--name", cmd.name, "job name (default: the scene file's name)");
  submit->add_option("--priority", cmd.priority, "higher runs first");
  submit->add_flag("--lenient", cmd.lenient, "unknown scene keys are warnings, not errors");
  submit->add_option("--label", cmd.labels, "a label KEY=VALUE (repeatable)")
      ->check(label_validator());
  submit->add_option("--submitter", cmd.submitter, "who submits (default: this host)");
  add_request_id_option(*submit, cmd.request_id);
  submit->add_flag("--json", cmd.json, "print the job as JSON instead of its id");
  add_server_option(*submit, cmd.server);

  // The scene exactly as submit would send it, for programs in other languages (the Python
  // client): one YAML loader and one conversion, the C++ ones, for every route to the API.
  CLI::App* convert = app.add_subcommand(
      "convert", "write the SubmitJobRequest that submit would send for a scene (binary protobuf)");
  convert
      ->add_option("scene", cmd.scene_path,
                   "scene YAML file, or - for standard input (relative file paths in it then "
                   "resolve against the current directory)")
      ->required();
  convert->add_option("-o,--output", cmd.request_output, "output file, or - for standard output")
      ->required()
      ->check(non_empty_validator());
  OverrideOptions convert_overrides(*convert);
  convert->add_option("--name", cmd.name,
                      "job name (default: the scene file's name; none for standard input)");
  convert->add_option("--priority", cmd.priority, "higher runs first");
  convert->add_flag("--lenient", cmd.lenient, "unknown scene keys are warnings, not errors");
  convert->add_option("--label", cmd.labels, "a label KEY=VALUE (repeatable)")
      ->check(label_validator());
  convert->add_option("--submitter", cmd.submitter,
                      "who submits (default: the host that submits it)");

  CLI::App* watch =
      app.add_subcommand("watch", "stream a job's tiles into an image as they finish");
  watch->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  watch->add_option("-o,--output", cmd.output_exr, "output image (tiled EXR; - for stdout)")
      ->required()
      ->check(exr_output_validator());
  watch->add_flag("--keep-partial", cmd.keep_partial,
                  "on Ctrl-C, write the tiles received so far (the rest black, alpha 0)");
  watch->add_flag("--cancel", cmd.cancel_on_interrupt,
                  "on Ctrl-C, also cancel the job on the server (default: only stop watching)");
  watch->add_flag("--json", cmd.json, "one JSON object per line per tile and at the end");
  watch->add_option("--png", cmd.preview_png, "also write an 8-bit sRGB PNG preview")
      ->check(extension_validator(".png"));
  add_preview_options(*watch, cmd);
  add_server_option(*watch, cmd.server);

  CLI::App* list = app.add_subcommand("list", "list the server's jobs, newest first");
  list->add_option("--label", cmd.label_filter, "only jobs with this label (KEY=VALUE or KEY)");
  list->add_option("--name", cmd.name_filter, "only jobs with exactly this name");
  list->add_option("--submitter", cmd.submitter, "only jobs of this submitter");
  list->add_option("--state", cmd.state_filter, "only jobs in this state")
      ->check(CLI::IsMember(job_state_names()));
  list->add_option("--limit", cmd.limit, "at most this many jobs (the newest)")
      ->check(CLI::Range(1u, 1'000'000u));
  list->add_flag("--json", cmd.json, "print {\"jobs\": [...]} as JSON");
  add_server_option(*list, cmd.server);

  CLI::App* status = app.add_subcommand("status", "show one job");
  status->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  status->add_flag("--json", cmd.json, "print the job as JSON");
  add_server_option(*status, cmd.server);

  CLI::App* cancel = app.add_subcommand("cancel", "cancel a queued or running job");
  cancel->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  add_server_option(*cancel, cmd.server);

  CLI::App* remove =
      app.add_subcommand("delete", "delete a finished job and its tiles from the server");
  remove->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  add_server_option(*remove, cmd.server);

  CLI::App* pause =
      app.add_subcommand("pause", "stop handing out a job's tiles (those rendering finish)");
  pause->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  add_server_option(*pause, cmd.server);

  CLI::App* resume = app.add_subcommand("resume", "put a paused job back in the queue");
  resume->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  add_server_option(*resume, cmd.server);

  CLI::App* retry = app.add_subcommand(
      "retry", "queue a failed or cancelled job again; only its missing tiles are rendered");
  retry->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  add_server_option(*retry, cmd.server);

  CLI::App* update = app.add_subcommand("update", "change a job's priority, labels or submitter");
  update->add_option("job", cmd.job_id, "job id")->required()->check(non_empty_validator());
  update->add_option("--priority", cmd.new_priority, "new priority (higher runs first)");
  update->add_option("--label", cmd.labels, "set a label KEY=VALUE (repeatable)")
      ->check(label_validator());
  update->add_option("--remove-label", cmd.remove_labels, "remove the label KEY (repeatable)");
  update->add_option("--submitter", cmd.new_submitter, "new submitter")
      ->check(non_empty_validator());
  add_server_option(*update, cmd.server);

  CLI::App* events = app.add_subcommand(
      "events", "print job state changes as they happen (the current states first); Ctrl-C ends");
  events->add_option("--job", cmd.job_id, "only this job")->check(non_empty_validator());
  events->add_option("--submitter", cmd.submitter, "only jobs of this submitter");
  events->add_option("--label", cmd.label_filter, "only jobs with this label (KEY=VALUE or KEY)");
  add_server_option(*events, cmd.server);

  CLI::App* denoise = app.add_subcommand(
      "denoise", "add a denoised pass (denoised.R/G/B) to a render with the denoiser's AOVs");
  denoise->add_option("input", cmd.input_exr, "rendered EXR with albedo, normal and variance")
      ->required()
      ->check(CLI::ExistingFile);
  denoise->add_option("-o,--output", cmd.output_exr, "output EXR (default: rewrite the input)")
      ->check(extension_validator(".exr"));
  denoise->add_option("--png", cmd.preview_png, "also write an 8-bit sRGB PNG of the denoised pass")
      ->check(extension_validator(".png"));
  add_preview_options(*denoise, cmd);

  CLI::App* token = app.add_subcommand("token", "helpers for tesserad's bearer tokens");
  token->require_subcommand(1);
  CLI::App* token_hash = token->add_subcommand(
      "hash",
      "read a token from stdin and print its SHA-256 (hex) for tesserad's tokens file; one "
      "trailing newline is ignored");

  CLI::App* version = app.add_subcommand(
      "version", "print this client's version and the server's (when it can be reached)");
  add_server_option(*version, cmd.server);

  CLI::App* health = app.add_subcommand(
      "health", "check the server's gRPC health service: exit 0 when it is serving, 1 if not");
  health->add_option("--address", cmd.server, "tesserad address (the same as --server)")
      ->check(server_address_validator());
  add_server_option(*health, cmd.server);

  std::string completion_shell;
  CLI::App* completion =
      app.add_subcommand("completion", "print a shell completion script (bash or zsh)");
  completion->add_option("shell", completion_shell, "bash or zsh")
      ->required()
      ->check(CLI::IsMember(completion_shells()));

  std::vector<std::string_view> command_names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    command_names.push_back(sub->get_name());

  // `tessera --version [--server ADDR]` is `tessera version`: it asks the server too.
  std::vector<const char*> version_argv;
  if (argc >= 2 && std::string_view(argv[1]) == "--version") {
    version_argv.assign(argv, argv + argc);
    version_argv[1] = "version";
    argv = version_argv.data();
  }

  for (CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    if (command->get_option_no_throw("--server") != nullptr)
      add_security_options(*command, cmd.security);

  // CLI11 reports an unknown first word only as "A subcommand is required".
  const auto is_command = [&app](const std::string& word) {
    const auto commands = app.get_subcommands([](const CLI::App*) { return true; });
    return std::any_of(commands.begin(), commands.end(),
                       [&](const CLI::App* c) { return c->get_name() == word; });
  };
  std::string expected = "expected ";
  for (std::size_t i = 0; i < command_names.size(); ++i)
    expected += std::string(i == 0                          ? ""
                            : i + 1 == command_names.size() ? " or "
                                                            : ", ") +
                std::string(command_names[i]);
  expected += "; see 'tessera --help'";
  if (argc <= 1) {
    err << "tessera: no command given (" << expected << ")\n";
    return {std::nullopt, kExitUsage};
  }
  if (argv[1][0] != '-' && !is_command(argv[1])) {
    err << "tessera: unknown command '" << argv[1] << "'"
        << schema::did_you_mean(argv[1], command_names) << " (" << expected << ")\n";
    return {std::nullopt, kExitUsage};
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return {std::nullopt, app.exit(e, out, err)};
  } catch (const CLI::CallForAllHelp& e) {
    return {std::nullopt, app.exit(e, out, err)};
  } catch (const CLI::CallForVersion& e) {
    return {std::nullopt, app.exit(e, out, err)};
  } catch (const CLI::ParseError& e) {
    std::string where = "tessera";
    const CLI::App* command = &app;
    for (const CLI::App* sub : app.get_subcommands({})) {
      if (sub->parsed()) {
        where += " " + sub->get_name();
        command = sub;
      }
    }
    err << "tessera: " << e.what() << unknown_flag_hint(*command, argc, argv) << " (see '" << where
        << " --help')\n";
    return {std::nullopt, kExitUsage};
  }

  if (completion->parsed()) {
    out << completion_script(app, completion_shell, "tessera") << std::flush;
    return {std::nullopt, kExitOk};
  }
  if (const auto problem = apply_security_environment(cmd.security)) {
    err << "tessera: " << *problem << '\n';
    return {std::nullopt, kExitUsage};
  }
  // TESSERA_SERVER where no address flag was given. Read here, not with CLI11's envname,
  // for the reason apply_security_environment gives: there the variable overrode an
  // explicit --server.
  if (const char* server = std::getenv("TESSERA_SERVER"); server && *server) {
    bool given = false;
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
      for (const char* flag : {"--server", "--address"})
        if (const CLI::Option* option = command->get_option_no_throw(flag))
          given = given || option->count() > 0;
    if (!given) {
      if (const auto problem = check_server_address(server)) {
        err << "tessera: TESSERA_SERVER: " << *problem << '\n';
        return {std::nullopt, kExitUsage};
      }
      cmd.server = server;
    }
  }

  if (render->parsed()) {
    cmd.kind = CommandKind::kRender;
    cmd.overrides = render_overrides.values();
  } else if (submit->parsed()) {
    cmd.kind = CommandKind::kSubmit;
    cmd.overrides = submit_overrides.values();
  } else if (convert->parsed()) {
    cmd.kind = CommandKind::kConvert;
    cmd.overrides = convert_overrides.values();
  } else if (watch->parsed()) {
    cmd.kind = CommandKind::kWatch;
    if (cmd.json && cmd.output_exr == kStdoutPath) {
      err << "tessera: watch: --json and -o - would both write to stdout; name an output file\n";
      return {std::nullopt, kExitUsage};
    }
  } else if (list->parsed()) {
    cmd.kind = CommandKind::kList;
  } else if (status->parsed()) {
    cmd.kind = CommandKind::kStatus;
  } else if (cancel->parsed()) {
    cmd.kind = CommandKind::kCancel;
  } else if (pause->parsed()) {
    cmd.kind = CommandKind::kPause;
  } else if (resume->parsed()) {
    cmd.kind = CommandKind::kResume;
  } else if (retry->parsed()) {
    cmd.kind = CommandKind::kRetry;
  } else if (update->parsed()) {
    cmd.kind = CommandKind::kUpdate;
    if (!cmd.new_priority && !cmd.new_submitter && cmd.labels.empty() &&
        cmd.remove_labels.empty()) {
      err << "tessera: update: nothing to change; give --priority, --label, --remove-label or "
             "--submitter (see 'tessera update --help')\n";
      return {std::nullopt, kExitUsage};
    }
  } else if (events->parsed()) {
    cmd.kind = CommandKind::kEvents;
  } else if (version->parsed()) {
    cmd.kind = CommandKind::kVersion;
  } else if (health->parsed()) {
    cmd.kind = CommandKind::kHealth;
  } else if (token_hash->parsed()) {
    cmd.kind = CommandKind::kTokenHash;
  } else if (denoise->parsed()) {
    cmd.kind = CommandKind::kDenoise;
    if (cmd.output_exr.empty()) cmd.output_exr = cmd.input_exr;
  } else {
    cmd.kind = CommandKind::kDelete;
  }
  return {cmd, kExitOk};
}

}  // namespace tessera
