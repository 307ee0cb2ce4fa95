// libFuzzer target: a SubmitJobRequest's bytes as tesserad takes them: parsed, its cost
// checked (job_cost), then converted and validated (scene_from_proto), and a scene that
// passes converted back (scene_to_proto) and again, which must give the same scene. Any
// crash, sanitizer report, escaping exception or mismatch is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include <google/protobuf/stubs/logging.h>

#include "convert/scene_proto.hpp"
#include "server/job_cost.hpp"

namespace {

// Invalid UTF-8 in a string field is a parse failure the target expects; protobuf's log
// line for each would drown the fuzzer's output.
const bool kProtobufQuiet = [] {
  google::protobuf::SetLogHandler(
      [](google::protobuf::LogLevel, const char*, int, const std::string&) {});
  return true;
}();

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tessera::v1::SubmitJobRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return 0;
  // Small limits, as a daemon on a small node would set them (see fuzz_yaml_scene.cpp).
  tessera::SceneLimits limits;
  limits.max_triangles = 100'000;
  limits.max_primitives = 100'000;
  limits.max_patch_control_points = 10'000;
  limits.max_trim_points = 100'000;
  limits.max_environment_pixels = 1 << 16;
  const tessera::server::JobCostCheck cost =
      tessera::server::check_job_cost(request, limits, std::size_t{1} << 30, 2);
  if (cost.verdict != tessera::server::JobCostCheck::Verdict::kFits) return 0;
  const tessera::SceneConversion conversion =
      tessera::scene_from_proto(request.scene(), request.settings(), limits);
  if (!conversion.ok()) {
    if (conversion.issues.empty()) std::abort();  // refused without saying why
    (void)tessera::describe_issues(conversion.issues);
    return 0;
  }
  const tessera::SceneDescription& scene = *conversion.scene;
  const tessera::SceneConversion again = tessera::scene_from_proto(
      tessera::scene_to_proto(scene), tessera::settings_to_proto(scene.render), limits);
  if (!again.ok() || !(*again.scene == scene)) std::abort();  // the round trip lost something
  return 0;
}
