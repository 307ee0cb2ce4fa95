#pragma once
// A job's cost counted from its SubmitJobRequest, before the scene is converted or
// prepared: what the memory budget and the primitive limit are checked against, so a
// request that could never fit is refused before the daemon allocates for it.
#include <cstddef>
#include <string>

#include "tessera/render/memory_estimate.hpp"
#include "tessera/v1/render.pb.h"
#include "tessera/v1/scene.pb.h"

namespace tessera::server {

// The scene's counts read from the message itself (array lengths only; nothing is copied).
SceneSize scene_size_of_proto(const v1::Scene& scene);

// The verdict on a request before its scene is converted.
struct JobCostCheck {
  enum class Verdict { kFits, kTooManyPrimitives, kOverMemoryBudget };
  Verdict verdict = Verdict::kFits;
  MemoryEstimate estimate;
  std::string message;  // names the count or the estimate and the limit; empty when it fits
};

// Checks the request's primitive count against limits.max_primitives and its memory
// estimate (tiles in flight on `threads` workers; the daemon never holds a whole image)
// against `memory_budget` (0: no limit). Reads array lengths only.
JobCostCheck check_job_cost(const v1::SubmitJobRequest& request, const SceneLimits& limits,
                            std::size_t memory_budget, unsigned threads);

// Half of the machine's physical memory: the default memory_budget. Half, not all, because
// the estimate is an estimate, requests being checked hold memory of their own, and the
// machine runs other things (a farm node's OS, its file cache, a second daemon).
std::size_t default_memory_budget();

}  // namespace tessera::server
