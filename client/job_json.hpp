#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "tessera/v1/render.pb.h"

namespace tessera {

// The lower-case name of a job state ("queued", "running", ...; "unknown" for none).
std::string job_state_name(v1::JobState state);

// The JSON the CLI's --json prints for a job (README: "tessera --json"): id, name, state,
// priority, submitter, labels, request_id, settings {width, height, samples_per_pixel,
// max_depth, tile_size, seed, passes}, progress {tiles_done, tiles_total, percent,
// rays_traced, elapsed_seconds, rays_per_second, eta_seconds}, error, submitted_unix_ms,
// finished_unix_ms. Field names are stable: scripts read them.
nlohmann::json job_to_json(const v1::Job& job);
nlohmann::json progress_to_json(const v1::JobProgress& progress);

// One `tessera watch --json` line for a delivered tile: event "tile", job_id, sequence,
// tile {index, x, y, width, height, pass}, progress.
nlohmann::json tile_event_json(const v1::Tile& tile);

}  // namespace tessera
