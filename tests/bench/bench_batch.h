// The `batch` scene: throughput of PfxWorldBatch, in world-steps per wall second, for 1 to
// 1,024 copies of one world stepped together, on each --threads count. Two worlds: the
// arm of the urdf scene (urdf/arm.urdf on a fixed base over a ground box, its joints held
// by position drives; with the loaders) and a ragdoll (pfxAddRagdoll) lying on a ground
// box. Each is dropped and stepped 0.5 s at 1/240 s first, so that the copies start with
// their contacts, and the batch steps once before the timing (each copy's buffers grow on
// its first step).
//
// Each run steps max(4, 1024 / copies) times, so that a run takes about as long whatever
// the copies; wall time, since the point is how the threads share the worlds out.
//
// TSV rows: scene `batch`, variant `<robot>/<copies>`, engine pfx, dt 1/240, the run's
// thread count; metric world_steps_per_s (wall_s_per_sim_s: wall seconds per simulated
// second, summed over the copies).
#pragma once

#include <vector>

#include "bench_cli.h"
#include "bench_report.h"

namespace pfxbench {

constexpr const char* kBatchSceneName = "batch";

// Appends the scene's rows; returns the number of worlds that could not be built or stepped.
int runBatchScene(const Options& options, std::vector<ResultRow>& rows);

}  // namespace pfxbench
