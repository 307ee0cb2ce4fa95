// `tessera convert`: the SubmitJobRequest that `submit` would send, written for another
// program (the Python client) to send, so every language goes through the C++ YAML loader
// and conversion.
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "client/cli_options.hpp"
#include "client/commands.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/scene/yaml_loader.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera {
namespace {

class ConvertCommandTest : public test::TestDirFixture {};

std::string cornell_path() {
  return std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml";
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

CliCommand cornell_convert(std::string output) {
  CliCommand command;
  command.kind = CommandKind::kConvert;
  command.scene_path = cornell_path();
  command.request_output = std::move(output);
  command.overrides.width = 48;
  command.overrides.samples_per_pixel = 2;
  command.priority = 3;
  command.labels = {"shot=010"};
  command.submitter = "ana";
  return command;
}

TEST_F(ConvertCommandTest, WritesTheRequestSubmitWouldSend) {
  const std::filesystem::path output = dir_ / "sub" / "cornell.pb";
  std::ostringstream out, err;
  ASSERT_EQ(run_command(cornell_convert(output.string()), {out, err, false}), kExitOk) << err.str();
  EXPECT_TRUE(out.str().empty());
  EXPECT_TRUE(err.str().empty());

  v1::SubmitJobRequest written;
  ASSERT_TRUE(written.ParseFromString(read_file(output)));
  LoadedScene loaded = load_scene_file(cornell_path());
  loaded.scene.render.width = 48;
  loaded.scene.render.samples_per_pixel = 2;
  v1::SubmitJobRequest expected = make_submit_request(loaded.scene, "cornell", 3);
  (*expected.mutable_labels())["shot"] = "010";
  expected.set_submitter("ana");
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(written, expected))
      << written.ShortDebugString().substr(0, 2000);
  EXPECT_EQ(written.settings().width(), 48u);
  EXPECT_EQ(written.settings().samples_per_pixel(), 2u);
}

TEST_F(ConvertCommandTest, DashWritesTheSameBytesToStandardOutput) {
  const std::filesystem::path output = dir_ / "cornell.pb";
  std::ostringstream file_out, file_err, out, err;
  ASSERT_EQ(run_command(cornell_convert(output.string()), {file_out, file_err, false}), kExitOk);
  ASSERT_EQ(run_command(cornell_convert("-"), {out, err, false}), kExitOk) << err.str();
  EXPECT_FALSE(out.str().empty());
  EXPECT_EQ(out.str(), read_file(output));
}

TEST_F(ConvertCommandTest, SceneErrorExitsTwoAndWritesNothing) {
  const std::filesystem::path scene = dir_ / "bad.yaml";
  std::ofstream(scene) << "materials:\n  - { name: m, type: lambertian }\ngeometry:\n"
                          "  - { type: sphere, material: m, center: [0, 0, 0], radius: -2 }\n";
  CliCommand command;
  command.kind = CommandKind::kConvert;
  command.scene_path = scene.string();
  command.request_output = (dir_ / "bad.pb").string();
  std::ostringstream out, err;
  EXPECT_EQ(run_command(command, {out, err, false}), kExitUsage);
  EXPECT_EQ(err.str(),
            "tessera: " + scene.string() + ":4: geometry[0].radius: must be > 0, got -2\n");
  EXPECT_FALSE(std::filesystem::exists(command.request_output));
}

TEST_F(ConvertCommandTest, UnwritableOutputExitsOneNamingTheFile) {
  const std::filesystem::path blocker = dir_ / "file";
  std::ofstream(blocker) << "x";
  const std::string output = (blocker / "cornell.pb").string();
  std::ostringstream out, err;
  EXPECT_EQ(run_command(cornell_convert(output), {out, err, false}), kExitFailed);
  EXPECT_NE(err.str().find(blocker.string()), std::string::npos) << err.str();
}

ParsedCommandLine parse(std::vector<const char*> args, std::ostream& out, std::ostream& err) {
  args.insert(args.begin(), "tessera");
  return parse_command_line(static_cast<int>(args.size()), args.data(), out, err);
}

TEST(ConvertCommandLine, TakesSubmitsOptionsAndNeedsAnOutput) {
  std::ostringstream out, err;
  const ParsedCommandLine parsed =
      parse({"convert", "-", "-o", "-", "--width", "64", "--spp", "4", "--name", "n", "--priority",
             "2", "--label", "a=b", "--submitter", "s", "--lenient"},
            out, err);
  ASSERT_TRUE(parsed.command) << err.str();
  const CliCommand& command = *parsed.command;
  EXPECT_EQ(command.kind, CommandKind::kConvert);
  EXPECT_EQ(command.scene_path, "-");
  EXPECT_EQ(command.request_output, "-");
  EXPECT_EQ(command.overrides.width, 64u);
  EXPECT_EQ(command.overrides.samples_per_pixel, 4u);
  EXPECT_EQ(command.name, "n");
  EXPECT_EQ(command.priority, 2);
  EXPECT_EQ(command.labels, std::vector<std::string>{"a=b"});
  EXPECT_EQ(command.submitter, "s");
  EXPECT_TRUE(command.lenient);

  std::ostringstream out2, err2;
  const ParsedCommandLine missing = parse({"convert", "scene.yaml"}, out2, err2);
  EXPECT_FALSE(missing.command);
  EXPECT_EQ(missing.exit_code, kExitUsage);
  EXPECT_NE(err2.str().find("--output"), std::string::npos) << err2.str();
}

}  // namespace
}  // namespace tessera
