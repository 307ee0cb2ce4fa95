#include "server/job_proto.hpp"

#include "convert/scene_proto.hpp"

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
  }
  return v1::JOB_STATE_UNSPECIFIED;
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
  out.set_priority(info.priority);
  out.set_state(job_state_to_proto(info.state));
  *out.mutable_settings() = settings_to_proto(info.settings);
  job_progress_to_proto(info.progress, *out.mutable_progress());
  out.set_error(info.error);
  out.set_submitted_unix_ms(info.submitted_unix_ms);
  out.set_finished_unix_ms(info.finished_unix_ms);
}

void finished_tile_to_proto(const std::string& job_id, const FinishedTile& tile, v1::Tile& out) {
  out.set_job_id(job_id);
  v1::TileRect& rect = *out.mutable_rect();
  rect.set_index(tile.rect.index);
  rect.set_x(tile.rect.x);
  rect.set_y(tile.rect.y);
  rect.set_width(tile.rect.width);
  rect.set_height(tile.rect.height);
  out.set_pass("beauty");
  out.set_exr(tile.exr->data(), tile.exr->size());
  job_progress_to_proto(tile.progress, *out.mutable_progress());
}

}  // namespace tessera::server
