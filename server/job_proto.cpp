#include "server/job_proto.hpp"

#include <algorithm>

#include "convert/scene_proto.hpp"
#include "server/job_passes.hpp"

namespace tessera::server {

v1::JobState job_state_to_proto(JobState state) {
  switch (state) {
    case JobState::kQueued:
      return v1::JOB_STATE_QUEUED;
    case JobState::kRunning:
      return v1::JOB_STATE_RUNNING;
    case JobState::kCompleted:
      return v1::JOB_STATE_COMPLETED;
    case JobState::kFailed:
      return v1::JOB_STATE_FAILED;
    case JobState::kCancelled:
      return v1::JOB_STATE_CANCELLED;
    case JobState::kPaused:
      return v1::JOB_STATE_PAUSED;
  }
  return v1::JOB_STATE_UNSPECIFIED;
}

std::optional<JobState> job_state_from_proto(int state) {
  switch (state) {
    case v1::JOB_STATE_QUEUED:
      return JobState::kQueued;
    case v1::JOB_STATE_RUNNING:
      return JobState::kRunning;
    case v1::JOB_STATE_COMPLETED:
      return JobState::kCompleted;
    case v1::JOB_STATE_FAILED:
      return JobState::kFailed;
    case v1::JOB_STATE_CANCELLED:
      return JobState::kCancelled;
    case v1::JOB_STATE_PAUSED:
      return JobState::kPaused;
    default:
      return std::nullopt;
  }
}

void job_progress_to_proto(const JobProgress& progress, v1::JobProgress& out) {
  out.set_tiles_done(progress.tiles_done);
  out.set_tiles_total(progress.tiles_total);
  out.set_rays_traced(progress.rays_traced);
  out.set_elapsed_seconds(progress.elapsed_seconds);
  out.set_rays_per_second(progress.rays_per_second);
  out.set_eta_seconds(progress.eta_seconds);
}

void job_info_to_proto(const JobInfo& info, v1::Job& out) {
  out.set_id(info.id);
  out.set_name(info.name);
  out.set_submitter(info.submitter);
  out.set_priority(info.priority);
  out.set_state(job_state_to_proto(info.state));
  *out.mutable_settings() = settings_to_proto(info.settings);
  job_progress_to_proto(info.progress, *out.mutable_progress());
  out.set_error(info.error);
  out.set_submitted_unix_ms(info.submitted_unix_ms);
  out.set_finished_unix_ms(info.finished_unix_ms);
  out.mutable_labels()->clear();
  for (const auto& [key, value] : info.labels) (*out.mutable_labels())[key] = value;
  out.set_request_id(info.request_id);
}

void stored_tile_to_proto(const JobRecord& job, const StoredTile& tile, v1::Tile& out) {
  const RenderSettings& s = job.settings;
  // The store index names a pass of a tile (job_passes.hpp); the rectangle follows from
  // the tile's index and the job's tile grid, so the store keeps only the index.
  const TilePass tile_pass = PassLayout(s).of(tile.index);
  const std::uint32_t columns = (s.width + s.tile_size - 1) / s.tile_size;
  const std::uint32_t x = (tile_pass.tile % columns) * s.tile_size;
  const std::uint32_t y = (tile_pass.tile / columns) * s.tile_size;
  out.set_job_id(job.id);
  v1::TileRect& rect = *out.mutable_rect();
  rect.set_index(tile_pass.tile);
  rect.set_x(x);
  rect.set_y(y);
  rect.set_width(std::min(s.tile_size, s.width - x));
  rect.set_height(std::min(s.tile_size, s.height - y));
  out.set_pass("beauty");
  out.set_pass_index(tile_pass.pass);
  out.set_sequence(tile.ordinal);
  out.set_exr(tile.exr.data(), tile.exr.size());
  job_progress_to_proto(tile_progress(job, tile), *out.mutable_progress());
}

}  // namespace tessera::server
