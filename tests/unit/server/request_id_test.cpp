// SubmitJobRequest.request_id: the validation rule and the fingerprint that tells a retry of
// a request from another request reusing its id.
#include "server/request_id.hpp"

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace tessera::server {
namespace {

using testing::tiny_scene;
using testing::tiny_settings;

v1::SubmitJobRequest tiny_request() {
  v1::SubmitJobRequest request;
  *request.mutable_scene() = tiny_scene();
  *request.mutable_settings() = tiny_settings();
  request.set_name("tiny");
  request.set_request_id("retry-1");
  return request;
}

TEST(RequestId, PrintableAsciiUpTo128CharactersIsAccepted) {
  EXPECT_FALSE(request_id_problem(""));  // no request id
  EXPECT_FALSE(request_id_problem("3f2a9c0e-4b1d-4c8e-9a7f-0123456789ab"));
  EXPECT_FALSE(request_id_problem("nightly build #42 (shot 010)"));
  EXPECT_FALSE(request_id_problem(std::string(128, 'x')));
}

TEST(RequestId, TooLongOrNonPrintableIsRefusedNamingTheField) {
  const auto too_long = request_id_problem(std::string(129, 'x'));
  ASSERT_TRUE(too_long);
  EXPECT_EQ(*too_long, "request_id: must be at most 128 characters, got 129");
  const auto newline = request_id_problem("abc\ndef");
  ASSERT_TRUE(newline);
  EXPECT_EQ(*newline, "request_id: must be printable ASCII; byte 3 is 0x0a");
  const auto utf8 = request_id_problem("caf\xc3\xa9");
  ASSERT_TRUE(utf8);
  EXPECT_EQ(*utf8, "request_id: must be printable ASCII; byte 3 is 0xc3");
  EXPECT_TRUE(request_id_problem(std::string("a\0b", 3)));
  EXPECT_TRUE(request_id_problem("del\x7f"));
}

TEST(RequestId, TheFingerprintIsTheSceneAndSettingsOnly) {
  const v1::SubmitJobRequest request = tiny_request();
  const std::string fingerprint = request_fingerprint(request);
  EXPECT_EQ(request_fingerprint(request), fingerprint);  // deterministic

  // What a retry may change without becoming another request.
  v1::SubmitJobRequest renamed = request;
  renamed.set_name("renamed");
  renamed.set_priority(7);
  (*renamed.mutable_labels())["shot"] = "010";
  renamed.set_request_id("another");
  EXPECT_EQ(request_fingerprint(renamed), fingerprint);

  v1::SubmitJobRequest other_scene = request;
  other_scene.mutable_scene()->mutable_geometry(0)->mutable_sphere()->set_radius(2);
  EXPECT_NE(request_fingerprint(other_scene), fingerprint);
  v1::SubmitJobRequest other_settings = request;
  other_settings.mutable_settings()->set_samples_per_pixel(2);
  EXPECT_NE(request_fingerprint(other_settings), fingerprint);
  // The same bytes moved from the scene into the settings are not the same request.
  EXPECT_NE(request_fingerprint(v1::SubmitJobRequest()), fingerprint);
}

}  // namespace
}  // namespace tessera::server
