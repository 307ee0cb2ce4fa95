#include "server/server_info.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>
#include <utility>

#include "tessera/scene/schema/kinds.hpp"

// Set for this file alone by server/CMakeLists.txt (so a new commit recompiles only it).
#ifndef TESSERA_GIT_COMMIT
#define TESSERA_GIT_COMMIT ""
#endif
#ifndef TESSERA_COMPILER
#define TESSERA_COMPILER ""
#endif
#ifndef TESSERA_BUILD_TYPE
#define TESSERA_BUILD_TYPE ""
#endif

namespace tessera::server {
namespace {

void add_names(std::span<const std::string_view> names,
               google::protobuf::RepeatedPtrField<std::string>& out) {
  for (const std::string_view name : names) out.Add(std::string(name));
}

// A kOneOf field's choices ("a|b|c") into its names.
void add_choices(std::string_view choices, google::protobuf::RepeatedPtrField<std::string>& out) {
  for (std::string& name : schema::choice_names(choices)) out.Add(std::move(name));
}

// The CPU's model name from /proc/cpuinfo; empty where there is none.
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    std::string name = line.substr(colon + 1);
    name.erase(0, std::min(name.find_first_not_of(' '), name.size()));
    return name;
  }
  return {};
}

}  // namespace

v1::ServerInfo make_server_info(const DaemonConfig& config, const std::vector<std::string>& gpus) {
  v1::ServerInfo info;
  info.set_version(TESSERA_VERSION);
  v1::BuildInfo& build = *info.mutable_build();
  build.set_git_commit(TESSERA_GIT_COMMIT);
  build.set_compiler(TESSERA_COMPILER);
  build.set_build_type(TESSERA_BUILD_TYPE);

  v1::Device& cpu = *info.add_devices();
  cpu.set_kind("cpu");
  cpu.set_name(cpu_model());
  cpu.set_threads(config.threads);
  for (const std::string& name : gpus) {
    v1::Device& gpu = *info.add_devices();
    gpu.set_kind("gpu");
    gpu.set_name(name);
    gpu.set_threads(1);  // one scheduler worker feeds it
  }

  const SceneLimits& scene = config.limits;
  v1::ServerLimits& limits = *info.mutable_limits();
  limits.set_max_width(scene.max_width);
  limits.set_max_height(scene.max_height);
  limits.set_max_pixels(scene.max_pixels);
  limits.set_max_samples_per_pixel(scene.max_samples_per_pixel);
  limits.set_max_primitives(scene.max_primitives);
  limits.set_max_triangles(scene.max_triangles);
  limits.set_max_depth(scene.max_depth);
  limits.set_min_tile_size(scene.min_tile_size);
  limits.set_max_tile_size(scene.max_tile_size);
  // What gRPC is really given (daemon.cpp clamps to int).
  limits.set_max_receive_message_bytes(
      std::min<std::size_t>(config.max_receive_message_bytes, std::numeric_limits<int>::max()));
  limits.set_memory_budget_bytes(effective_memory_budget(config));
  limits.set_max_jobs_per_submitter(config.max_jobs_per_submitter);
  limits.set_prepare_timeout_seconds(static_cast<double>(config.prepare_timeout.count()) / 1000.0);

  v1::Capabilities& capabilities = *info.mutable_capabilities();
  add_names(integrator_names(), *capabilities.mutable_integrators());
  add_names(sampler_names(), *capabilities.mutable_samplers());
  add_names(light_strategy_names(), *capabilities.mutable_light_strategies());
  add_names(aov_names(), *capabilities.mutable_aovs());
  add_names(material_type_names(), *capabilities.mutable_material_types());
  schema::for_each_kind<schema::ShapeKinds>(
      [&](auto kind) { capabilities.add_geometry_kinds(std::string(decltype(kind)::proto_name)); });
  add_choices(schema::field_choices<schema::RenderKind>("pixel_filter"),
              *capabilities.mutable_pixel_filters());
  add_choices(schema::field_choices<schema::TextureKind>("type"),
              *capabilities.mutable_texture_types());
  add_choices(schema::field_choices<schema::RenderKind>("accel_builder"),
              *capabilities.mutable_accel_builders());
  capabilities.set_progressive_passes(true);
  capabilities.set_adaptive_sampling(true);
  capabilities.set_idempotent_submit(true);
  return info;
}

}  // namespace tessera::server
