// The CLI's commands as a user sees them: exit codes, the one-line error messages, and the
// files `render --local` writes. Server-side behaviour is in tests/integration.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "client/commands.hpp"
#include "tessera/image/denoise.hpp"
#include "tessera/image/exr.hpp"
#include "tessera/render/camera.hpp"
#include "tessera/render/output_channels.hpp"
#include "tessera/render/prepared_scene.hpp"
#include "tessera/render/render_image.hpp"
#include "tessera/scene/yaml_loader.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera {
namespace {

struct CommandRun {
  int exit_code;
  std::string out, err;
};

CommandRun run(const CliCommand& command) {
  std::ostringstream out, err;
  const int code = run_command(command, {out, err, false});
  return {code, out.str(), err.str()};
}

class CommandsTest : public test::TestDirFixture {};

std::string cornell_path() {
  return std::string(TESSERA_SOURCE_DIR) + "/examples/scenes/cornell.yaml";
}

// A loopback port nothing listens on: bound once by us, then released.
int unused_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

TEST_F(CommandsTest, SceneErrorPrintsTheLoaderMessageAndExitsTwo) {
  const std::filesystem::path scene = dir_ / "bad.yaml";
  std::ofstream(scene) << "materials:\n  - { name: m, type: lambertian }\ngeometry:\n"
                          "  - { type: sphere, material: m, center: [0, 0, 0], radius: 1 }\n"
                          "  - { type: sphere, material: m, center: [0, 0, 0], radius: -2 }\n";
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.scene_path = scene.string();
  command.output_exr = (dir_ / "out.exr").string();
  for (bool local : {false, true}) {
    command.local = local;
    const CommandRun r = run(command);
    EXPECT_EQ(r.exit_code, kExitUsage);
    EXPECT_EQ(r.err,
              "tessera: " + scene.string() + ":5: geometry[1].radius: must be > 0, got -2\n");
    EXPECT_FALSE(std::filesystem::exists(command.output_exr));
  }
  command.kind = CommandKind::kSubmit;
  EXPECT_EQ(run(command).exit_code, kExitUsage);
}

TEST_F(CommandsTest, MissingSceneFileIsASceneError) {
  CliCommand command;
  command.kind = CommandKind::kSubmit;
  command.scene_path = (dir_ / "nope.yaml").string();
  const CommandRun r = run(command);
  EXPECT_EQ(r.exit_code, kExitUsage);
  EXPECT_EQ(r.err, "tessera: " + command.scene_path + ": scene file not found\n");
}

TEST_F(CommandsTest, UnreachableServerNamesTheAddressAndExitsOne) {
  const std::string server = "127.0.0.1:" + std::to_string(unused_port());
  CliCommand command;
  command.server = server;
  command.scene_path = cornell_path();
  command.output_exr = (dir_ / "out.exr").string();
  command.job_id = "some-job";
  for (CommandKind kind : {CommandKind::kRender, CommandKind::kSubmit, CommandKind::kList,
                           CommandKind::kStatus, CommandKind::kCancel, CommandKind::kWatch}) {
    command.kind = kind;
    const CommandRun r = run(command);
    SCOPED_TRACE(r.err);
    EXPECT_EQ(r.exit_code, kExitFailed);
    EXPECT_EQ(r.err.rfind("tessera: cannot reach the server at " + server, 0), 0u);
    EXPECT_NE(r.err.find("UNAVAILABLE"), std::string::npos);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
    EXPECT_TRUE(r.out.empty());
  }
  EXPECT_FALSE(std::filesystem::exists(command.output_exr));
}

TEST_F(CommandsTest, LocalRenderWritesTheSameImageAsTheCore) {
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.local = true;
  command.threads = 3;
  command.scene_path = cornell_path();
  command.output_exr = (dir_ / "nested/dir/cornell.exr").string();
  command.preview_png = (dir_ / "cornell.png").string();
  command.overrides.width = 40;
  command.overrides.height = 30;
  command.overrides.samples_per_pixel = 2;
  command.overrides.tile_size = 16;
  const CommandRun r = run(command);
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_EQ(r.out.rfind("tessera: rendered 40x30 at 2 spp in ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("rays/s: " + command.output_exr + ", " + command.preview_png + "\n"),
            std::string::npos)
      << r.out;

  SceneDescription scene = load_scene_file(cornell_path()).scene;
  scene.render.width = 40;
  scene.render.height = 30;
  scene.render.samples_per_pixel = 2;
  scene.render.tile_size = 16;
  const std::vector<float> reference = render_image(*PreparedScene::build(scene));
  const RgbaImage written = read_image(command.output_exr);
  ASSERT_EQ(written.width, 40u);
  ASSERT_EQ(written.height, 30u);
  EXPECT_EQ(std::memcmp(written.pixels.data(), reference.data(), reference.size() * sizeof(float)),
            0);

  const RgbaImage preview = read_image(command.preview_png);
  EXPECT_EQ(preview.width, 40u);
  EXPECT_EQ(preview.height, 30u);
}

// A preview integrator with AOVs asked for renders locally into one EXR holding the beauty
// channels and every AOV's channels, equal to the core's own passes.
TEST_F(CommandsTest, LocalRenderWritesAovChannels) {
  const std::filesystem::path scene = dir_ / "aovs.yaml";
  std::ofstream(scene)
      << "materials:\n  - { name: m, type: lambertian, albedo: [0.2, 0.4, 0.6] }\ngeometry:\n"
         "  - { type: sphere, material: m, center: [0, 0, 0], radius: 1 }\n"
         "render: { width: 16, height: 12, spp: 1, tile_size: 8, aovs: [albedo, depth] }\n";
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.local = true;
  command.scene_path = scene.string();
  command.output_exr = (dir_ / "aovs.exr").string();
  const CommandRun r = run(command);
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;

  std::ifstream in(command.output_exr, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  const ChannelImage file = decode_exr_channels(bytes);
  EXPECT_EQ(std::set<std::string>(file.channels.begin(), file.channels.end()),
            (std::set<std::string>{"R", "G", "B", "A", "Albedo.R", "Albedo.G", "Albedo.B", "Z"}));
  const ChannelImage written = select_channels(file, output_channels(kAovAlbedo | kAovDepth));
  const auto prepared = PreparedScene::build(load_scene_file(scene).scene);
  for (const TileRect& tile : make_tiles(16, 12, 8)) {
    TilePasses passes;
    prepared->render_tile(tile, passes);
    const std::vector<float> expected = interleave_passes(passes, kAovAlbedo | kAovDepth);
    const std::size_t stride = written.channels.size();
    for (std::uint32_t row = 0; row < tile.height; ++row)
      for (std::uint32_t col = 0; col < tile.width * stride; ++col)
        ASSERT_EQ(written.pixels[((tile.y + row) * 16 + tile.x) * stride + col],
                  expected[row * tile.width * stride + col]);
  }
}

// `render --denoise` adds the guides and a denoised pass equal to the core's denoiser on
// the written beauty and guides; `denoise` on a file without the guides names them.
TEST_F(CommandsTest, DenoiseAddsADenoisedPassAndNamesMissingGuides) {
  const std::filesystem::path scene = dir_ / "denoise.yaml";
  std::ofstream(scene) << "materials:\n  - { name: m, type: lambertian, albedo: [0.2, 0.4, 0.6] }\n"
                          "  - { name: l, type: light, emission: 4 }\ngeometry:\n"
                          "  - { type: sphere, material: m, center: [0, 0, 0], radius: 1 }\n"
                          "  - { type: sphere, material: l, center: [2, 2, 2], radius: 0.5 }\n"
                          "render: { width: 16, height: 12, spp: 4, tile_size: 8 }\n";
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.local = true;
  command.denoise = true;
  command.scene_path = scene.string();
  command.output_exr = (dir_ / "denoised.exr").string();
  command.preview_png = (dir_ / "denoised.png").string();
  const CommandRun r = run(command);
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(std::filesystem::exists(command.preview_png));

  std::ifstream in(command.output_exr, std::ios::binary);
  const ChannelImage file = decode_exr_channels(std::vector<std::uint8_t>(
      (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
  const auto plane = [&](const std::vector<std::string>& names) {
    return select_channels(file, names).pixels;
  };
  const auto aov = [&](std::uint32_t bit) {
    std::vector<std::string> names = output_channels(bit);
    return plane({names.begin() + 4, names.end()});
  };
  const std::vector<float> beauty = plane({"R", "G", "B"}), albedo = aov(kAovAlbedo),
                           normal = aov(kAovNormal), variance = aov(kAovVariance);
  const std::vector<float> expected = denoise({16, 12, beauty, albedo, normal, variance});
  EXPECT_EQ(plane({"denoised.R", "denoised.G", "denoised.B"}), expected);
  EXPECT_NE(expected, beauty);
  // The rewritten file keeps the header a pipeline needs.
  const ImageHeader header = read_image_header(command.output_exr);
  EXPECT_NE(header.find("worldToNDC"), nullptr);
  EXPECT_NE(header.find("tessera/samplesPerPixel"), nullptr);

  const std::filesystem::path plain = dir_ / "plain.exr";
  command.denoise = false;
  command.output_exr = plain.string();
  command.preview_png.clear();
  ASSERT_EQ(run(command).exit_code, kExitOk);
  CliCommand denoise_command;
  denoise_command.kind = CommandKind::kDenoise;
  denoise_command.input_exr = plain.string();
  denoise_command.output_exr = (dir_ / "out.exr").string();
  const CommandRun missing = run(denoise_command);
  EXPECT_EQ(missing.exit_code, kExitFailed);
  EXPECT_NE(missing.err.find("albedo"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("--denoise"), std::string::npos) << missing.err;
}

TEST_F(CommandsTest, UnwritableOutputFailsBeforeRendering) {
  std::ofstream(dir_ / "file") << "x";
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.local = true;
  command.scene_path = cornell_path();
  command.output_exr = (dir_ / "file/out.exr").string();  // parent is a file
  const CommandRun r = run(command);
  EXPECT_EQ(r.exit_code, kExitFailed);
  EXPECT_EQ(r.err.rfind("tessera: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("file"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

// The EXR a render writes carries its provenance and camera in OpenEXR's standard
// attributes, read back through OpenImageIO, and its primitive IDs as a UINT channel.
// worldToNDC maps look_at to the image centre and the point a corner pixel's ray reaches
// to that corner.
TEST_F(CommandsTest, LocalRenderWritesTheHeaderAPipelineNeeds) {
  const std::filesystem::path scene = dir_ / "header.yaml";
  std::ofstream(scene)
      << "camera: { position: [1, 2, 6], look_at: [0.5, 0.5, 0], fov: 35 }\n"
         "materials:\n  - { name: m, type: lambertian, albedo: 0.5 }\ngeometry:\n"
         "  - { type: sphere, material: m, center: [0.5, 0.5, 0], radius: 1 }\n"
         "render: { width: 24, height: 16, spp: 2, tile_size: 8, aovs: [depth, primitive_id] }\n";
  CliCommand command;
  command.kind = CommandKind::kRender;
  command.local = true;
  command.scene_path = scene.string();
  command.output_exr = (dir_ / "header.exr").string();
  command.preview_png = (dir_ / "header.png").string();
  command.preview_tone = "aces";
  command.preview_exposure = 1.0;
  const CommandRun r = run(command);
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(std::filesystem::exists(command.preview_png));
  EXPECT_FALSE(std::filesystem::exists(command.output_exr + ".tmp.exr"));

  // The attribute names and types as OpenEXR stores them, in the file's bytes.
  std::ifstream in(command.output_exr, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const std::string& attribute :
       {std::string("worldToCamera\0m44f\0", 19), std::string("worldToNDC\0m44f\0", 16),
        std::string("chromaticities\0chromaticities\0", 30)})
    EXPECT_NE(bytes.find(attribute), std::string::npos) << attribute.c_str();

  const ImageHeader header = read_image_header(command.output_exr);
  const auto text = [&](const char* name) {
    const ImageHeader::Attribute* a = header.find(name);
    return a ? a->value : std::string("(missing)");
  };
  EXPECT_EQ(text("Software"), std::string("Tessera ") + TESSERA_VERSION);
  EXPECT_EQ(text("tessera/scene"), "header");
  EXPECT_EQ(text("tessera/samplesPerPixel"), "2");
  ASSERT_NE(header.find("tessera/renderSeconds"), nullptr);
  EXPECT_GT(header.find("tessera/renderSeconds")->numbers.at(0), 0.0);
  const ImageHeader::Attribute* chromaticities = header.find("chromaticities");
  ASSERT_NE(chromaticities, nullptr);
  ASSERT_EQ(chromaticities->numbers.size(), 8u);
  EXPECT_NEAR(chromaticities->numbers[0], 0.64, 1e-6);    // red x
  EXPECT_NEAR(chromaticities->numbers[6], 0.3127, 1e-6);  // white x

  // Imath's convention: row vectors, p' = p * M.
  const auto transform = [](const ImageHeader::Attribute* m, const glm::dvec3& p) {
    glm::dvec4 out(0.0);
    const double in4[4] = {p.x, p.y, p.z, 1.0};
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) out[j] += in4[i] * m->numbers.at(4 * i + j);
    return out;
  };
  const auto project = [&](const char* name, const glm::dvec3& p) {
    const ImageHeader::Attribute* m = header.find(name);
    EXPECT_NE(m, nullptr) << name;
    if (!m) return glm::dvec2(-99.0);
    const glm::dvec4 clip = transform(m, p);
    return glm::dvec2(clip.x / clip.w, clip.y / clip.w);
  };
  const SceneDescription desc = load_scene_file(scene).scene;
  const Ray corner_ray = Camera::from_description(desc.camera, 24, 16).generate(0.0f, 0.0f);
  const glm::dvec3 corner_point =
      glm::dvec3(corner_ray.origin) + 5.0 * glm::dvec3(corner_ray.direction);
  // NDC: [0, 1] from the top-left corner; screen: [-1, 1], +Y up.
  EXPECT_NEAR(glm::length(project("worldToNDC", {0.5, 0.5, 0.0}) - glm::dvec2(0.5, 0.5)), 0.0,
              1e-5);
  EXPECT_NEAR(glm::length(project("worldToNDC", corner_point) - glm::dvec2(0.0, 0.0)), 0.0, 1e-4);
  EXPECT_NEAR(glm::length(project("worldToScreen", {0.5, 0.5, 0.0})), 0.0, 1e-5);
  EXPECT_NEAR(glm::length(project("worldToScreen", corner_point) - glm::dvec2(-1.0, 1.0)), 0.0,
              1e-4);
  // worldToCamera takes the eye to the origin and look_at onto -Z.
  const ImageHeader::Attribute* to_camera = header.find("worldToCamera");
  ASSERT_NE(to_camera, nullptr);
  EXPECT_NEAR(glm::length(glm::dvec3(transform(to_camera, {1.0, 2.0, 6.0}))), 0.0, 1e-5);
  const glm::dvec4 target = transform(to_camera, {0.5, 0.5, 0.0});
  EXPECT_NEAR(target.x, 0.0, 1e-5);
  EXPECT_NEAR(target.y, 0.0, 1e-5);
  EXPECT_NEAR(target.z, -std::sqrt(0.25 + 2.25 + 36.0), 1e-4);

  // Channels: float colour and depth, UINT IDs.
  for (std::size_t c = 0; c < header.channel_names.size(); ++c)
    EXPECT_EQ(header.channel_types[c],
              header.channel_names[c] == "PrimitiveID.X" ? "uint" : "float")
        << header.channel_names[c];
}

}  // namespace
}  // namespace tessera
