#include "tessera/image/image_codecs.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tessera/image/exr.hpp"

namespace tessera {
namespace {

constexpr char kProbeVariable[] = "TESSERA_IMAGE_CODECS_TEST_PROBE";

bool open_image_io_is_mapped() {
  std::ifstream maps("/proc/self/maps");
  const std::string text((std::istreambuf_iterator<char>(maps)), std::istreambuf_iterator<char>());
  return text.find("libOpenImageIO") != std::string::npos;
}

// Run in a fresh copy of this program (see the test below), before main and before any
// test could have touched an image: exits 0 when OpenImageIO is absent from the process
// until the first EXR is encoded, present afterwards, and the EXR decodes to its pixels.
int probe() {
  if (open_image_io_is_mapped()) return 2;
  const std::vector<float> rgba = {0.25f, 0.5f, 0.75f, 1.0f, 2.0f, 3.0f, 4.0f, 1.0f};
  const RgbaImage back = decode_exr(encode_exr(rgba, 2, 1));
  if (back.pixels != rgba) return 3;
  if (!open_image_io_is_mapped()) return 4;
  return 0;
}

[[maybe_unused]] const int kProbed = [] {
  if (std::getenv(kProbeVariable) != nullptr) _exit(probe());
  return 0;
}();

TEST(ImageCodecs, OpenImageIoIsLoadedAtTheFirstImageNotAtStart) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    setenv(kProbeVariable, "1", 1);
    execl("/proc/self/exe", "image_codecs_probe", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  switch (WEXITSTATUS(status)) {
    case 0:
      break;
    case 2:
      FAIL() << "OpenImageIO was mapped at start: a program links it again";
    case 3:
      FAIL() << "the EXR written through the module read back different pixels";
    case 4:
      FAIL() << "OpenImageIO was not mapped after an EXR was written";
    default:
      FAIL() << "the probe exited with " << WEXITSTATUS(status);
  }
}

TEST(ImageCodecs, TheLoadedModuleIsThisBuildsAndLoadsOnce) {
  const std::filesystem::path path = load_image_codecs();
  EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
  EXPECT_EQ(path.filename(), "libtessera_image_codecs.so");
  EXPECT_STREQ(image_codecs::table().abi, image_codecs::kAbi);
  EXPECT_EQ(load_image_codecs(), path);
  EXPECT_EQ(&image_codecs::table(), &image_codecs::table());
}

TEST(ImageCodecs, EveryUnusableCandidateIsNamedWithItsReason) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tessera_codecs_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path text_file = dir / "libtessera_image_codecs.so";
  std::ofstream(text_file) << "not a shared object\n";
  // A real shared object without the entry point: the C library, found through dlopen's
  // own address.
  Dl_info info{};
  ASSERT_NE(dladdr(reinterpret_cast<void*>(&dlopen), &info), 0);
  const std::filesystem::path libc = info.dli_fname;
  const std::filesystem::path missing = dir / "missing" / "libtessera_image_codecs.so";

  std::filesystem::path opened = "unchanged";
  std::string error;
  EXPECT_EQ(image_codecs::open_first({missing, text_file, libc}, opened, error), nullptr);
  EXPECT_EQ(opened, "unchanged");
  EXPECT_NE(error.find(missing.string() + ": no such file"), std::string::npos) << error;
  EXPECT_NE(error.find(text_file.string() + ": "), std::string::npos) << error;
  EXPECT_NE(error.find(libc.string() + ": not the image codecs module"), std::string::npos)
      << error;

  // The working module after them is taken.
  const std::filesystem::path module = load_image_codecs();
  EXPECT_NE(image_codecs::open_first({missing, text_file, libc, module}, opened, error), nullptr);
  EXPECT_EQ(opened, module);
  std::filesystem::remove_all(dir);
}

TEST(ImageCodecs, AnExplicitPathIsTheOnlyPlaceLookedIn) {
  const char* before = std::getenv("TESSERA_IMAGE_CODECS");
  const std::string saved = before != nullptr ? before : "";
  setenv("TESSERA_IMAGE_CODECS", "/nonexistent/libtessera_image_codecs.so", 1);
  const std::vector<std::filesystem::path> candidates = image_codecs::candidate_paths();
  if (before != nullptr)
    setenv("TESSERA_IMAGE_CODECS", saved.c_str(), 1);
  else
    unsetenv("TESSERA_IMAGE_CODECS");
  ASSERT_EQ(candidates.size(), 1u);
  EXPECT_EQ(candidates[0], "/nonexistent/libtessera_image_codecs.so");

  const std::vector<std::filesystem::path> defaults = image_codecs::candidate_paths();
  ASSERT_GE(defaults.size(), 2u);
  EXPECT_EQ(defaults.back().filename(), "libtessera_image_codecs.so");
}

}  // namespace
}  // namespace tessera
