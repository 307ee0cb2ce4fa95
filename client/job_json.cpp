#include "client/job_json.hpp"

#include <algorithm>
#include <cctype>

namespace tessera {

std::string job_state_name(v1::JobState state) {
  std::string name = v1::JobState_Name(state);
  const std::string prefix = "JOB_STATE_";
  if (name.rfind(prefix, 0) == 0) name.erase(0, prefix.size());
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return name.empty() || name == "unspecified" ? "unknown" : name;
}

nlohmann::json progress_to_json(const v1::JobProgress& p) {
  const double percent =
      p.tiles_total() == 0 ? 0.0 : 100.0 * p.tiles_done() / static_cast<double>(p.tiles_total());
  return {{"tiles_done", p.tiles_done()},
          {"tiles_total", p.tiles_total()},
          {"percent", percent},
          {"rays_traced", p.rays_traced()},
          {"elapsed_seconds", p.elapsed_seconds()},
          {"rays_per_second", p.rays_per_second()},
          {"eta_seconds", p.eta_seconds()}};
}

nlohmann::json job_to_json(const v1::Job& job) {
  const v1::RenderSettings& s = job.settings();
  nlohmann::json labels = nlohmann::json::object();
  for (const auto& [key, value] : job.labels()) labels[key] = value;
  return {{"id", job.id()},
          {"name", job.name()},
          {"state", job_state_name(job.state())},
          {"priority", job.priority()},
          {"submitter", job.submitter()},
          {"labels", labels},
          {"request_id", job.request_id()},
          {"settings",
           {{"width", s.width()},
            {"height", s.height()},
            {"samples_per_pixel", s.samples_per_pixel()},
            {"max_depth", s.max_depth()},
            {"tile_size", s.tile_size()},
            {"seed", s.seed()},
            {"passes", std::max(s.passes(), 1u)}}},
          {"progress", progress_to_json(job.progress())},
          {"error", job.error()},
          {"submitted_unix_ms", job.submitted_unix_ms()},
          {"finished_unix_ms", job.finished_unix_ms()}};
}

nlohmann::json tile_event_json(const v1::Tile& tile) {
  const v1::TileRect& r = tile.rect();
  return {{"event", "tile"},
          {"job_id", tile.job_id()},
          {"sequence", tile.sequence()},
          {"tile",
           {{"index", r.index()},
            {"x", r.x()},
            {"y", r.y()},
            {"width", r.width()},
            {"height", r.height()},
            {"pass", std::max(tile.pass_index(), 1u)}}},
          {"progress", progress_to_json(tile.progress())}};
}

}  // namespace tessera
