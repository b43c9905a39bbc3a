#include "bench_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <malloc.h>
#include <time.h>
#include <memory>

#include "bench_metrics.h"
#include "bench_motors.h"

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

// False, saying which body, when the scene sets a speed limit and a dynamic body moves
// faster or its state is not finite. Scenes without a limit keep their figures to the end
// (a body gone NaN counts as escaped there).
bool withinSpeedLimit(const Scene& scene, const std::vector<BodyState>& states,
                      std::string& error) {
  if (!std::isfinite(scene.speedLimit)) return true;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (scene.bodies[i].fixed) continue;
    const BodyState& s = states[i];
    const double speed = s.linearVelocity.norm();
    const bool finite = s.position.allFinite() && s.orientation.coeffs().allFinite() &&
                        s.angularVelocity.allFinite() && std::isfinite(speed);
    if (finite && speed <= scene.speedLimit) continue;
    char text[160];
    if (finite) {
      std::snprintf(text, sizeof(text), "blew up: body %zu at %.3g m/s, beyond the scene's %.3g m/s",
                    i, speed, scene.speedLimit);
    } else {
      std::snprintf(text, sizeof(text), "blew up: body %zu has a state that is not finite", i);
    }
    error = text;
    return false;
  }
  return true;
}

struct Simulation {
  bool built = false;
  bool ok = false;  // built and stepped to the end
  std::string error;
  double wallSeconds = 0;
  double cpuSeconds = 0;
  double simulatedSeconds = 0;
  std::uint64_t finalDigest = 0;
};

std::uint64_t digestOf(const std::vector<BodyState>& states) {
  std::uint64_t hash = 1469598103934665603ull;
  auto add = [&](double value) {
    unsigned char bytes[sizeof(double)];
    std::memcpy(bytes, &value, sizeof(double));
    for (unsigned char byte : bytes) hash = (hash ^ byte) * 1099511628211ull;
  };
  for (const BodyState& s : states) {
    for (int k = 0; k < 3; ++k) add(s.position[k]);
    for (int k = 0; k < 4; ++k) add(s.orientation.coeffs()[k]);
    for (int k = 0; k < 3; ++k) add(s.linearVelocity[k]);
    for (int k = 0; k < 3; ++k) add(s.angularVelocity[k]);
  }
  return hash;
}

// Bytes on the heap, glibc's count over all arenas, large mapped blocks included.
double heapBytesInUse() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks) + static_cast<double>(info.hblkhd);
}

// What an engine keeps on the heap per body of the scene: a fresh engine built and stepped
// a few times, so that its pair and contact buffers have grown, against the heap before.
double heapBytesPerBody(const EngineInfo& info, const Scene& scene, const EngineSettings& settings,
                        long long steps) {
  constexpr long long kWarmUpSteps = 10;
  const double before = heapBytesInUse();
  std::unique_ptr<Engine> engine = info.create();
  std::string error;
  if (!engine->build(scene, settings, error)) return kNaN;
  for (long long i = 0; i < std::min(steps, kWarmUpSteps); ++i) {
    if (!engine->step(error)) return kNaN;
  }
  return (heapBytesInUse() - before) / static_cast<double>(scene.bodies.size());
}

struct Observers {
  std::function<void(const std::vector<BodyState>&)> bodies;
  // Null when the joints are not watched; otherwise called at the start and after every
  // step, so that joint_gap_max sees every step, not only the samples.
  std::function<void(const std::vector<JointAnchors>&)> joints;
};

// Builds the scene in a fresh engine and takes `steps` steps, showing the states to the
// observer at the start, every `every` steps and at the end. Only the steps are timed.
Simulation simulate(const EngineInfo& info, const Scene& scene, const EngineSettings& settings,
                    long long steps, long long every, const Observers& observers,
                    Progress& progress) {
  Simulation sim;
  std::unique_ptr<Engine> engine = info.create();
  if (!engine->build(scene, settings, sim.error)) return sim;
  sim.built = true;
  std::vector<BodyState> states;
  std::vector<JointAnchors> anchors;
  engine->readBodies(states);
  observers.bodies(states);
  if (observers.joints) {
    engine->readJointAnchors(anchors);
    observers.joints(anchors);
  }
  const double weight = bodyWeight(scene);
  // Motors are commanded before every step from the states then; reading those states is
  // the benchmark's work and not timed, handing the commands to the engine is.
  const bool driven = !scene.motors.empty();
  const MotorController controller(scene);
  std::vector<double> rates;
  const long long chunkLength = observers.joints || driven ? 1 : every;
  for (long long done = 0; done < steps;) {
    const long long chunk = std::min(chunkLength, steps - done);
    if (driven) {
      engine->readBodies(states);
      controller.commands(static_cast<double>(done) * settings.dt, states, rates);
    }
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = processCpuSeconds();
    if (driven) engine->setMotorRates(rates);
    for (long long i = 0; i < chunk; ++i) {
      if (!engine->step(sim.error)) {
        sim.wallSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        sim.cpuSeconds += processCpuSeconds() - cpuStart;
        sim.simulatedSeconds = static_cast<double>(done + i) * settings.dt;
        return sim;
      }
    }
    sim.wallSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sim.cpuSeconds += processCpuSeconds() - cpuStart;
    done += chunk;
    sim.simulatedSeconds = static_cast<double>(done) * settings.dt;
    if (observers.joints) {
      engine->readJointAnchors(anchors);
      observers.joints(anchors);
    }
    if (done % every == 0 || done == steps) {
      engine->readBodies(states);
      observers.bodies(states);
      if (!withinSpeedLimit(scene, states, sim.error)) return sim;
    }
    progress.advance(static_cast<double>(chunk) * weight);
  }
  sim.ok = true;
  sim.finalDigest = digestOf(states);
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
  Observers observers;
  observers.bodies = [&](const std::vector<BodyState>& states) {
    recorder.observe(states);
    if (tracked) appendTrackedPoints(scene, states, points);
  };
  if (scene.hasMetric(Metric::JointGapMax)) {
    observers.joints = [&](const std::vector<JointAnchors>& anchors) {
      recorder.observeJoints(anchors);
    };
  }
  const Simulation run = simulate(engine, scene, settings, steps, every, observers, progress);
  if (!run.built) {
    result.error = run.error;
    return result;
  }
  if (!run.ok) {
    char when[64];
    std::snprintf(when, sizeof(when), "stopped after %.4g s: ", run.simulatedSeconds);
    result.ok = true;
    result.stopped = true;
    result.error = when + run.error;
    result.wallSecondsPerSimSecond =
        run.simulatedSeconds > 0 ? run.wallSeconds / run.simulatedSeconds : kNaN;
    result.cpuSecondsPerSimSecond =
        run.simulatedSeconds > 0 ? run.cpuSeconds / run.simulatedSeconds : kNaN;
    for (Metric metric : scene.metrics) result.metrics.emplace_back(metric, kNaN);
    return result;
  }
  result.wallSecondsPerSimSecond = run.wallSeconds / run.simulatedSeconds;
  result.cpuSecondsPerSimSecond = run.cpuSeconds / run.simulatedSeconds;
  result.stateDigest = run.finalDigest;

  double positionError = kNaN;
  if (tracked) {
    EngineSettings fine = settings;
    fine.dt = settings.dt / kReferenceStepDivisor;
    fine.iterations = settings.iterations * kReferenceIterationFactor;
    std::vector<Vec3> referencePoints;
    Observers referenceObservers;
    referenceObservers.bodies = [&](const std::vector<BodyState>& states) {
      appendTrackedPoints(scene, states, referencePoints);
    };
    const Simulation reference = simulate(engine, scene, fine, steps * kReferenceStepDivisor,
                                          every * kReferenceStepDivisor, referenceObservers,
                                          progress);
    if (reference.ok) {
      positionError = largestDeviation(points, referencePoints);
    } else {
      char when[64];
      std::snprintf(when, sizeof(when), " after %.4g s", reference.simulatedSeconds);
      progress.log("reference run stopped" + std::string(reference.built ? when : "") + ": " +
                   reference.error + "; position_error is NaN");
    }
  }

  for (Metric metric : scene.metrics) {
    double value = recorder.value(metric);
    if (metric == Metric::PositionError) value = positionError;
    if (metric == Metric::BytesPerBody) value = heapBytesPerBody(engine, scene, settings, steps);
    if (metric == Metric::MsPerStep) value = 1e3 * result.wallSecondsPerSimSecond * settings.dt;
    if (metric == Metric::MsPerStepPerRobot) {
      value = 1e3 * result.wallSecondsPerSimSecond * settings.dt / scene.robots;
    }
    if (metric == Metric::CpuMsPerStepPerRobot) {
      value = 1e3 * result.cpuSecondsPerSimSecond * settings.dt / scene.robots;
    }
    result.metrics.emplace_back(metric, value);
  }
  result.ok = true;
  return result;
}

double processCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace pfxbench
