#pragma once
#include "server/job.hpp"
#include "tessera/v1/render.pb.h"

namespace tessera::server {

// Conversions from the job model to the public API messages.
v1::JobState job_state_to_proto(JobState state);
void job_progress_to_proto(const JobProgress& progress, v1::JobProgress& out);
void job_info_to_proto(const JobInfo& info, v1::Job& out);
void finished_tile_to_proto(const std::string& job_id, const FinishedTile& tile, v1::Tile& out);

}  // namespace tessera::server
