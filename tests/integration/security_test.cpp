// TLS, mutual TLS and bearer tokens against a real daemon on loopback, through
// tessera::Client as a user's program would connect: what a client without the right
// certificate or token gets, what a submit token may see and do, what an admin may, and
// which configurations tesserad refuses to start with.
#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <future>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "cli_run.hpp"
#include "client/cli_options.hpp"
#include "client/client.hpp"
#include "client/commands.hpp"
#include "client/token_hash.hpp"
#include "convert/scene_proto.hpp"
#include "cornell_scene.hpp"
#include "server/config.hpp"
#include "server/daemon.hpp"
#include "tesserad_process.hpp"
#include "test_certificates.hpp"
#include "tests/support/loopback_daemon_config.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;
using test::cornell;

constexpr const char* kAliceToken = "alice-7f3c9d1e2b4a6f80";
constexpr const char* kBobToken = "bob-0a1b2c3d4e5f6a7b";
constexpr const char* kAdminToken = "admin-9e8d7c6b5a4f3e2d";

// The ClientError code of `call`, or OK when it did not throw.
grpc::StatusCode code_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.code();
  }
  return grpc::StatusCode::OK;
}

// The message of the ClientError `call` throws ("" when it does not).
std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.message();
  }
  return "";
}

// Runs a command line with a time limit; its exit status and what it wrote.
std::pair<int, std::string> run(const std::string& command) {
  std::FILE* pipe = ::popen(("timeout 60 " + command + " 2>&1").c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed");
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

class SecurityTest : public test::TesseradDirTest {
 protected:
  void TearDown() override {
    daemon_.reset();
    test::TesseradDirTest::TearDown();
  }

  const test::TestCertificates& certificates() {
    if (!certificates_) certificates_.emplace(dir_ / "certs");
    return *certificates_;
  }

  // The tokens file of alice and bob (submit) and root (admin), its digests made by the
  // CLI's `token hash` code, so the test also shows the two sides agree.
  std::filesystem::path tokens_file() {
    const auto path = dir_ / "tokens.yaml";
    std::ofstream(path) << "- {name: alice, sha256: " << sha256_hex(kAliceToken)
                        << ", role: submit}\n"
                        << "- {name: bob, sha256: " << sha256_hex(kBobToken) << ", role: submit}\n"
                        << "- {name: root, sha256: " << sha256_hex(kAdminToken)
                        << ", role: admin}\n";
    return path;
  }

  server::DaemonConfig base_config() const { return test::loopback_daemon_config(data(), 1); }

  void start(const server::DaemonConfig& config) {
    daemon_ = std::make_unique<server::Daemon>(config);
    daemon_->start();
  }

  void start_with_tls(bool require_client_certificates) {
    server::DaemonConfig config = base_config();
    config.tls_cert = certificates().server_cert();
    config.tls_key = certificates().server_key();
    if (require_client_certificates) config.tls_client_ca = certificates().ca();
    start(config);
  }

  void start_with_tokens() {
    server::DaemonConfig config = base_config();
    config.tokens_file = tokens_file();
    start(config);
  }

  ClientOptions options(const std::string& token = {}) const {
    ClientOptions o;
    o.target = daemon_->address();
    o.token = token;
    o.unary_deadline = 20s;
    return o;
  }

  ClientOptions tls_options(const std::filesystem::path& ca) {
    ClientOptions o = options();
    o.tls.enabled = true;
    o.tls.root_certs_pem = certificates().pem(ca.filename().string());
    return o;
  }

  // A job that keeps the one render thread busy for a while, so jobs stay unfinished.
  static v1::SubmitJobRequest long_job(const std::string& name) {
    return make_submit_request(cornell(128, 128, 4096, 32), name, 0);
  }

  std::optional<test::TestCertificates> certificates_;
  std::unique_ptr<server::Daemon> daemon_;
};

// ---- TLS ----------------------------------------------------------------------------------

TEST_F(SecurityTest, ATlsClientTrustingTheServersCaRendersAJob) {
  start_with_tls(false);
  Client client(tls_options(certificates().ca()));
  const v1::Job job = client.submit(make_submit_request(cornell(16, 16, 1, 16), "over tls", 0));
  int tiles = 0;
  client.stream_tiles(job.id(), [&](const v1::Tile& tile) {
    EXPECT_FALSE(tile.exr().empty());
    ++tiles;
  });
  EXPECT_EQ(tiles, 1);
  EXPECT_EQ(client.get(job.id()).state(), v1::JOB_STATE_COMPLETED);
}

TEST_F(SecurityTest, APlaintextClientCannotTalkToATlsDaemon) {
  start_with_tls(false);
  Client client(options());
  EXPECT_EQ(code_of([&] { client.list(); }), grpc::StatusCode::UNAVAILABLE);
}

TEST_F(SecurityTest, AClientTrustingAnotherCaRefusesTheServer) {
  start_with_tls(false);
  Client client(tls_options(certificates().other_ca()));
  EXPECT_EQ(code_of([&] { client.list(); }), grpc::StatusCode::UNAVAILABLE);
}

TEST_F(SecurityTest, MutualTlsNeedsAClientCertificateTheClientCaSigned) {
  start_with_tls(true);
  Client without(tls_options(certificates().ca()));
  EXPECT_EQ(code_of([&] { without.list(); }), grpc::StatusCode::UNAVAILABLE);

  ClientOptions rogue = tls_options(certificates().ca());
  rogue.tls.client_cert_pem = certificates().pem("rogue-client.crt");
  rogue.tls.client_key_pem = certificates().pem("rogue-client.key");
  Client rogue_client(rogue);
  EXPECT_EQ(code_of([&] { rogue_client.list(); }), grpc::StatusCode::UNAVAILABLE);

  ClientOptions signed_by_ca = tls_options(certificates().ca());
  signed_by_ca.tls.client_cert_pem = certificates().pem("client.crt");
  signed_by_ca.tls.client_key_pem = certificates().pem("client.key");
  Client with(signed_by_ca);
  EXPECT_EQ(code_of([&] { with.list(); }), grpc::StatusCode::OK);
}

TEST_F(SecurityTest, BadTlsFilesStopTheStartNamingTheKey) {
  const auto expect_refused = [&](const std::function<void(server::DaemonConfig&)>& adjust,
                                  const std::string& key, const std::string& reason) {
    server::DaemonConfig config = base_config();
    config.tls_cert = certificates().server_cert();
    config.tls_key = certificates().server_key();
    adjust(config);
    server::Daemon daemon(config);
    try {
      daemon.start();
      ADD_FAILURE() << "started with a bad " << key;
    } catch (const server::ConfigError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(key + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(reason), std::string::npos) << message;
    }
  };
  const test::TestCertificates& files = certificates();
  expect_refused([&](auto& c) { c.tls_cert = files.path("missing.crt"); }, "tls_cert",
                 "cannot read");
  expect_refused([&](auto& c) { c.tls_cert = files.path("not-pem.txt"); }, "tls_cert",
                 "no PEM certificate");
  expect_refused([&](auto& c) { c.tls_cert = files.path("expired.crt"); }, "tls_cert", "expired");
  expect_refused([&](auto& c) { c.tls_key = files.path("client.key"); }, "tls_key",
                 "is not the private key");
  expect_refused([&](auto& c) { c.tls_key = files.path("encrypted.key"); }, "tls_key", "encrypted");
  expect_refused([&](auto& c) { c.tls_client_ca = files.path("not-pem.txt"); }, "tls_client_ca",
                 "no PEM certificate");
}

// ---- Plaintext off loopback ---------------------------------------------------------------

TEST_F(SecurityTest, TesseradRefusesPlaintextOffLoopbackUnlessAllowed) {
  const auto [code, output] =
      run(std::string(TESSERAD_PATH) + " --listen 0.0.0.0:0 --data '" + data().string() + "'");
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("listen: 0.0.0.0:0"), std::string::npos) << output;
  EXPECT_NE(output.find("allow_insecure_remote"), std::string::npos) << output;
  EXPECT_NE(output.find("tls_cert"), std::string::npos) << output;

  // Opted in, it serves (and the client reaches it over loopback).
  test::TesseradProcess daemon(data(), log(), 1, "0.0.0.0:0", {"--allow-insecure-remote"});
  Client client(ClientOptions{.target = daemon.address()});
  EXPECT_NO_THROW(client.list());
  std::ifstream in(log());
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("serving plaintext on 0.0.0.0"), std::string::npos) << text;
}

// ---- Tokens -------------------------------------------------------------------------------

TEST_F(SecurityTest, EveryRenderServiceCallNeedsAKnownToken) {
  start_with_tokens();
  for (const std::string token : {"", "not-a-token", "alice-7f3c9d1e2b4a6f81"}) {
    SCOPED_TRACE("token '" + token + "'");
    Client client(options(token));
    EXPECT_EQ(code_of([&] { client.list(); }), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code_of([&] { client.get("0123456789abcdef"); }), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code_of([&] { client.submit(long_job("no entry")); }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code_of([&] { client.stream_tiles("0123456789abcdef", [](const v1::Tile&) {}); }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code_of([&] { client.watch_jobs({}, [](const v1::JobEvent&) { return false; }); }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code_of([&] { client.cancel("0123456789abcdef"); }),
              grpc::StatusCode::UNAUTHENTICATED);
  }
  // Nothing got in: the admin sees no job.
  Client admin(options(kAdminToken));
  EXPECT_TRUE(admin.list().empty());
  EXPECT_NE(message_of([&] { Client(options()).list(); }).find("bearer token"), std::string::npos);
}

TEST_F(SecurityTest, TheHealthServiceStaysOpenWithTokens) {
  start_with_tokens();
  const auto channel = make_channel(daemon_->address());
  grpc::GenericStub stub(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + 20s);
  grpc::Slice empty("");
  const grpc::ByteBuffer request(&empty, 1);  // HealthCheckRequest{service: ""}
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                 [&](grpc::Status status) { done.set_value(status); });
  const grpc::Status status = done.get_future().get();
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::vector<grpc::Slice> slices;
  ASSERT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const grpc::Slice& slice : slices)
    bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));  // HealthCheckResponse{status: SERVING}
}

TEST_F(SecurityTest, ASubmitTokenReachesOnlyItsOwnJobsAndAnAdminReachesAll) {
  start_with_tokens();
  Client alice(options(kAliceToken));
  Client bob(options(kBobToken));
  Client admin(options(kAdminToken));

  const v1::Job mine = alice.submit(long_job("alice's"));
  const v1::Job theirs = bob.submit(long_job("bob's"));
  EXPECT_EQ(mine.submitter(), "alice");  // the token's name, not the peer
  EXPECT_EQ(theirs.submitter(), "bob");

  // Alice lists and watches her own job only.
  const std::vector<v1::Job> listed = alice.list();
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].id(), mine.id());
  v1::ListJobsRequest bobs_jobs;
  bobs_jobs.set_submitter("bob");
  EXPECT_EQ(code_of([&] { alice.list(bobs_jobs); }), grpc::StatusCode::PERMISSION_DENIED);
  // Her watch shows her job, and none of Bob's changes: the admin changes Bob's job first,
  // then Alice her own, and events arrive in order, so once hers is seen a leak of his
  // would have been too.
  std::mutex watched_mutex;
  std::vector<v1::JobEvent> watched;
  std::atomic<bool> stop_watching{false};
  std::thread watcher([&] {
    try {
      alice.watch_jobs({}, [&](const v1::JobEvent& event) {
        std::lock_guard lock(watched_mutex);
        watched.push_back(event);
        return !stop_watching.load();
      });
    } catch (const ClientError&) {
    }
  });
  const auto wait_for_event = [&](const std::function<bool(const v1::JobEvent&)>& wanted) {
    const auto give_up = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < give_up) {
      {
        std::lock_guard lock(watched_mutex);
        for (const v1::JobEvent& event : watched)
          if (wanted(event)) return true;
      }
      std::this_thread::sleep_for(5ms);
    }
    return false;
  };
  EXPECT_TRUE(wait_for_event([&](const v1::JobEvent& e) { return e.snapshot(); }));
  v1::UpdateJobRequest bump_bobs;
  bump_bobs.set_job_id(theirs.id());
  bump_bobs.set_priority(3);
  admin.update(bump_bobs);
  v1::UpdateJobRequest bump_mine;
  bump_mine.set_job_id(mine.id());
  bump_mine.set_priority(5);
  EXPECT_EQ(alice.update(bump_mine).priority(), 5);  // her own job she controls
  EXPECT_TRUE(wait_for_event([&](const v1::JobEvent& e) {
    return !e.snapshot() && e.job().id() == mine.id() && e.job().priority() == 5;
  }));
  stop_watching = true;
  alice.pause(mine.id());  // one more event ends the watch
  watcher.join();
  for (const v1::JobEvent& event : watched)
    EXPECT_EQ(event.job().id(), mine.id()) << "Alice's watch showed job " << event.job().id();
  v1::WatchJobsRequest watch_bobs;
  watch_bobs.set_job_id(theirs.id());
  EXPECT_EQ(
      code_of([&] { alice.watch_jobs(watch_bobs, [](const v1::JobEvent&) { return false; }); }),
      grpc::StatusCode::PERMISSION_DENIED);

  // Every direct access to Bob's job is refused, and changes nothing.
  const std::string id = theirs.id();
  const std::vector<std::pair<const char*, std::function<void()>>> calls = {
      {"GetJob", [&] { alice.get(id); }},
      {"CancelJob", [&] { alice.cancel(id); }},
      {"DeleteJob", [&] { alice.remove(id); }},
      {"PauseJob", [&] { alice.pause(id); }},
      {"ResumeJob", [&] { alice.resume(id); }},
      {"RetryJob", [&] { alice.retry(id); }},
      {"UpdateJob",
       [&] {
         v1::UpdateJobRequest update;
         update.set_job_id(id);
         update.set_priority(99);
         alice.update(update);
       }},
      {"StreamTiles", [&] { alice.stream_tiles(id, [](const v1::Tile&) {}); }},
  };
  for (const auto& [method, call] : calls)
    EXPECT_EQ(code_of(call), grpc::StatusCode::PERMISSION_DENIED) << method;
  const v1::Job untouched = admin.get(id);
  EXPECT_EQ(untouched.priority(), 3);  // the admin's change, not hers
  EXPECT_TRUE(untouched.state() == v1::JOB_STATE_QUEUED ||
              untouched.state() == v1::JOB_STATE_RUNNING)
      << untouched.state();

  // She may not submit as Bob, nor hand her job to him.
  v1::SubmitJobRequest as_bob = long_job("as bob");
  as_bob.set_submitter("bob");
  EXPECT_EQ(code_of([&] { alice.submit(as_bob); }), grpc::StatusCode::PERMISSION_DENIED);
  v1::UpdateJobRequest give_away;
  give_away.set_job_id(mine.id());
  give_away.set_submitter("bob");
  EXPECT_EQ(code_of([&] { alice.update(give_away); }), grpc::StatusCode::PERMISSION_DENIED);
  // The admin sees both and acts on Bob's job.
  std::set<std::string> all;
  for (const v1::Job& job : admin.list()) all.insert(job.id());
  EXPECT_EQ(all, (std::set<std::string>{mine.id(), theirs.id()}));
  EXPECT_EQ(admin.cancel(theirs.id()).state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(bob.get(theirs.id()).state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(alice.cancel(mine.id()).state(), v1::JOB_STATE_CANCELLED);
  EXPECT_NO_THROW(admin.remove(theirs.id()));

  // Only the admin moves a job between submitters; then it is the new owner's alone.
  v1::UpdateJobRequest hand_over;
  hand_over.set_job_id(mine.id());
  hand_over.set_submitter("bob");
  EXPECT_EQ(admin.update(hand_over).submitter(), "bob");
  EXPECT_EQ(bob.get(mine.id()).submitter(), "bob");
  EXPECT_EQ(code_of([&] { alice.get(mine.id()); }), grpc::StatusCode::PERMISSION_DENIED);
}

TEST_F(SecurityTest, TesseradRefusesABadTokensFileNamingEntryAndField) {
  const auto path = dir_ / "bad-tokens.yaml";
  std::ofstream(path) << "- {name: alice, sha256: " << sha256_hex("a") << ", role: submit}\n"
                      << "- {name: ci, sha256: " << sha256_hex("b") << ", role: root}\n";
  const auto [code, output] = run(std::string(TESSERAD_PATH) + " --listen 127.0.0.1:0 --data '" +
                                  data().string() + "' --tokens '" + path.string() + "'");
  EXPECT_NE(code, 0) << output;
  EXPECT_NE(output.find("bad-tokens.yaml:2: tokens[1].role: must be submit or admin, got 'root'"),
            std::string::npos)
      << output;
  EXPECT_EQ(output.find("listening"), std::string::npos) << output;
}

// A daemon that could not write a tile's EXR must not accept jobs it would fail.
TEST_F(SecurityTest, TesseradWithoutItsImageCodecsRefusesToStartAndSaysWhereItLooked) {
  const std::string missing = (dir_ / "nowhere" / "libtessera_image_codecs.so").string();
  const auto [code, output] =
      run("env TESSERA_IMAGE_CODECS='" + missing + "' " + std::string(TESSERAD_PATH) +
          " --listen 127.0.0.1:0 --data '" + data().string() + "'");
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("image codecs module"), std::string::npos) << output;
  EXPECT_NE(output.find(missing + ": no such file"), std::string::npos) << output;
  EXPECT_EQ(output.find("listening"), std::string::npos) << output;
}

// ---- The CLI ------------------------------------------------------------------------------

TEST_F(SecurityTest, TheCliRendersThroughMutualTlsWithAToken) {
  server::DaemonConfig config = base_config();
  config.tls_cert = certificates().server_cert();
  config.tls_key = certificates().server_key();
  config.tls_client_ca = certificates().ca();
  config.tokens_file = tokens_file();
  start(config);
  const test::TestCertificates& files = certificates();
  const std::vector<std::string> connection = {"--server",      daemon_->address(),
                                               "--ca",          files.ca().string(),
                                               "--client-cert", files.path("client.crt").string(),
                                               "--client-key",  files.path("client.key").string()};
  const auto with = [&](std::vector<std::string> args, const std::vector<std::string>& extra) {
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  const std::string output = (dir_ / "cornell.exr").string();

  const test::CliRun render =
      test::run_cli(with({"render", test::kCornell, "-o", output, "--width", "16", "--height", "16",
                          "--spp", "1", "--tile-size", "16", "--token", kAliceToken},
                         connection));
  EXPECT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(std::filesystem::exists(output));
  const test::CliRun listed = test::run_cli(with({"list", "--token", kAliceToken}, connection));
  EXPECT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(listed.out.find("completed"), std::string::npos) << listed.out;
  EXPECT_NE(listed.out.find("cornell"), std::string::npos) << listed.out;

  const test::CliRun no_token = test::run_cli(with({"list"}, connection));
  EXPECT_EQ(no_token.exit_code, 1);
  EXPECT_NE(no_token.err.find("UNAUTHENTICATED"), std::string::npos) << no_token.err;

  const test::CliRun plaintext =
      test::run_cli({"list", "--server", daemon_->address(), "--token", kAliceToken});
  EXPECT_EQ(plaintext.exit_code, 1);
  EXPECT_NE(plaintext.err.find("if it serves TLS, give --ca or --tls"), std::string::npos)
      << plaintext.err;

  const test::CliRun wrong_ca =
      test::run_cli({"list", "--server", daemon_->address(), "--token", kAliceToken, "--ca",
                     files.other_ca().string(), "--client-cert", files.path("client.crt").string(),
                     "--client-key", files.path("client.key").string()});
  EXPECT_EQ(wrong_ca.exit_code, 1);
  EXPECT_NE(wrong_ca.err.find("TLS handshake"), std::string::npos) << wrong_ca.err;
}

}  // namespace
}  // namespace tessera
