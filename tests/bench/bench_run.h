// One run: a scene stepped by one engine with one set of step settings, timed around the
// steps only, judged by the scene's metrics. Runs that need position_error also run the
// reference: the same scene and engine at dt / 16 with four times the iterations.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bench_engine.h"
#include "bench_progress.h"
#include "bench_scene.h"

namespace pfxbench {

struct RunResult {
  bool ok = false;
  bool skipped = false;  // the engine cannot run this scene here; `error` says why
  // The engine gave up during the run (it diverged or reported an error): a result, not a
  // failure of the benchmark. Its figures are NaN, its time is per second it did simulate,
  // and `error` says what happened when.
  bool stopped = false;
  std::string error;
  double wallSecondsPerSimSecond = 0;
  // The process's CPU time over the same steps: on a machine shared with other work, where
  // the wall time also counts the time the process waited for a core.
  double cpuSecondsPerSimSecond = 0;
  std::vector<std::pair<Metric, double>> metrics;
  // FNV-1a over every body's final position, orientation and velocities as the engine
  // reported them: equal digests mean bit-identical states (runs finished only).
  std::uint64_t stateDigest = 0;
};

// CPU seconds the process has used so far, all its threads together.
double processCpuSeconds();

// Relative cost of a run for the progress bar (body steps, reference included).
double runWork(const Scene& scene, const EngineSettings& settings, double seconds);

RunResult runScene(const EngineInfo& engine, const Scene& scene, const EngineSettings& settings,
                   double seconds, Progress& progress);

}  // namespace pfxbench
