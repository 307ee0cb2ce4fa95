#pragma once
#include "server/job.hpp"
#include "tessera/v1/render.pb.h"

namespace tessera::server {

// Conversions between the job model and the public API messages.
v1::JobState job_state_to_proto(JobState state);
// The job state a request names; nothing for JOB_STATE_UNSPECIFIED or an unknown value.
std::optional<JobState> job_state_from_proto(int state);
void job_progress_to_proto(const JobProgress& progress, v1::JobProgress& out);
void job_info_to_proto(const JobInfo& info, v1::Job& out);
void stored_tile_to_proto(const JobRecord& job, const StoredTile& tile, v1::Tile& out);

}  // namespace tessera::server
