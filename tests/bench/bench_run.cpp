#include "bench_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include "bench_metrics.h"

namespace pfxbench {

namespace {

constexpr int kReferenceStepDivisor = 16;
constexpr int kReferenceIterationFactor = 4;
// States are sampled for the metrics at 60 Hz, or every step when steps are longer.
constexpr double kSamplePeriod = 1.0 / 60;

long long stepCount(double seconds, double dt) {
  return std::max(1LL, std::llround(seconds / dt));
}

long long sampleInterval(double dt) { return std::max(1LL, std::llround(kSamplePeriod / dt)); }

double bodyWeight(const Scene& scene) {
  return 1.0 + static_cast<double>(std::count_if(scene.bodies.begin(), scene.bodies.end(),
                                                 [](const BodyDesc& b) { return !b.fixed; }));
}

struct Simulation {
  bool ok = false;
  std::string error;
  double wallSeconds = 0;
};

using Observer = std::function<void(const std::vector<BodyState>&)>;

// Builds the scene in a fresh engine and takes `steps` steps, showing the states to the
// observer at the start, every `every` steps and at the end.
Simulation simulate(const EngineInfo& info, const Scene& scene, const EngineSettings& settings,
                    long long steps, long long every, const Observer& observe,
                    Progress& progress) {
  Simulation sim;
  std::unique_ptr<Engine> engine = info.create();
  if (!engine->build(scene, settings, sim.error)) return sim;
  std::vector<BodyState> states;
  engine->readBodies(states);
  observe(states);
  const double weight = bodyWeight(scene);
  for (long long done = 0; done < steps;) {
    const long long chunk = std::min(every, steps - done);
    const auto start = std::chrono::steady_clock::now();
    for (long long i = 0; i < chunk; ++i) {
      if (!engine->step(sim.error)) return sim;
    }
    sim.wallSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    done += chunk;
    engine->readBodies(states);
    observe(states);
    progress.advance(static_cast<double>(chunk) * weight);
  }
  sim.ok = true;
  return sim;
}

}  // namespace

double runWork(const Scene& scene, const EngineSettings& settings, double seconds) {
  const double steps = static_cast<double>(stepCount(seconds, settings.dt));
  const double reference = scene.hasMetric(Metric::PositionError) ? kReferenceStepDivisor : 0;
  return steps * (1 + reference) * bodyWeight(scene);
}

RunResult runScene(const EngineInfo& engine, const Scene& scene, const EngineSettings& settings,
                   double seconds, Progress& progress) {
  RunResult result;
  if (!engine.create()->supports(scene, settings, result.error)) {
    result.skipped = true;
    return result;
  }
  const bool tracked = scene.hasMetric(Metric::PositionError);
  const long long steps = stepCount(seconds, settings.dt);
  const long long every = sampleInterval(settings.dt);

  MetricRecorder recorder(scene);
  std::vector<Vec3> points;
  const Simulation run = simulate(
      engine, scene, settings, steps, every,
      [&](const std::vector<BodyState>& states) {
        recorder.observe(states);
        if (tracked) appendTrackedPoints(scene, states, points);
      },
      progress);
  if (!run.ok) {
    result.error = run.error;
    return result;
  }
  result.wallSecondsPerSimSecond = run.wallSeconds / (static_cast<double>(steps) * settings.dt);

  double positionError = std::numeric_limits<double>::quiet_NaN();
  if (tracked) {
    EngineSettings fine = settings;
    fine.dt = settings.dt / kReferenceStepDivisor;
    fine.iterations = settings.iterations * kReferenceIterationFactor;
    std::vector<Vec3> referencePoints;
    const Simulation reference = simulate(
        engine, scene, fine, steps * kReferenceStepDivisor, every * kReferenceStepDivisor,
        [&](const std::vector<BodyState>& states) {
          appendTrackedPoints(scene, states, referencePoints);
        },
        progress);
    if (reference.ok) {
      positionError = largestDeviation(points, referencePoints);
    } else {
      progress.log("reference run failed: " + reference.error);
    }
  }

  for (Metric metric : scene.metrics) {
    result.metrics.emplace_back(metric,
                                metric == Metric::PositionError ? positionError : recorder.value(metric));
  }
  result.ok = true;
  return result;
}

}  // namespace pfxbench
