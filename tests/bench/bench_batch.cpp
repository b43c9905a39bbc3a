// The batch scene (bench_batch.h).
#include "bench_batch.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "pfx/pfx.h"
#ifdef PFX_BENCH_HAVE_LOADERS
#include "pfx/loaders/pfx_urdf_loader.h"
#endif

namespace pfxbench {

namespace {

using namespace pfx;

constexpr double kTimeStep = 1.0 / 240;
constexpr int kSettleSteps = 120;
constexpr PfxUInt32 kCopies[] = {1, 4, 16, 64, 256, 1024};
constexpr PfxUInt32 kWorldStepsPerRun = 1024;

bool startWorld(PfxWorld& world) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  param.timeStep = PfxFloat(kTimeStep);
  param.enableSleep = false;  // every step of every copy is solved
  if (world.initialize(param) != PFX_OK) return false;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, 0, PfxFloat(-0.5));
  return pfxAddBody(world, pfxMakeShape(PfxBox(5, 5, PfxFloat(0.5))), ground) == PFX_OK;
}

// What a source world's shapes point into (a URDF's meshes), kept while it is copied.
using KeepAlive = std::shared_ptr<void>;

bool buildRagdoll(PfxWorld& world, KeepAlive&, std::string& error) {
  PfxRagdoll ragdoll;
  if (!startWorld(world) ||
      pfxAddRagdoll(world, PfxVector3(0, 0, 1.1f), PfxQuat::Identity(), &ragdoll) != PFX_OK) {
    error = "the ragdoll could not be built";
    return false;
  }
  return true;
}

#ifdef PFX_BENCH_HAVE_LOADERS
bool buildArm(PfxWorld& world, KeepAlive& keepAlive, std::string& error) {
  if (!startWorld(world)) return false;
  PfxUrdfLoadParam load;
  load.fixedBase = true;
  auto owned = std::make_shared<PfxUrdfModel>();
  PfxUrdfModel& model = *owned;
  keepAlive = owned;
  if (pfxLoadUrdfFile(world, std::string(PFX_SOURCE_DIR) + "/urdf/arm.urdf", load, model,
                      &error) != PFX_OK) {
    return false;
  }
  // Every movable joint held at 0.3 rad (fixed ones refuse a command, which is left so): the
  // arm works against its drives on every step.
  for (PfxUInt32 j = 0; j < model.joints.size(); ++j) {
    pfxSetUrdfJointCommand(world, model, j, kPfxJointDrivePosition, PfxFloat(0.3));
  }
  return true;
}
#endif

struct Robot {
  const char* name;
  std::function<bool(PfxWorld&, KeepAlive&, std::string&)> build;
};

}  // namespace

int runBatchScene(const Options& options, std::vector<ResultRow>& rows) {
  std::vector<Robot> robots;
#ifdef PFX_BENCH_HAVE_LOADERS
  robots.push_back({"arm", buildArm});
#endif
  robots.push_back({"ragdoll", buildRagdoll});
  int failures = 0;
  for (const Robot& robot : robots) {
    KeepAlive sourceMeshes;  // declared first: the world points into it
    PfxWorld source;
    std::string error;
    bool built = robot.build(source, sourceMeshes, error);
    for (int s = 0; built && s < kSettleSteps; ++s) built = source.step() == PFX_OK;
    if (!built) {
      std::fprintf(stderr, "batch %s: FAILED: %s\n", robot.name, error.c_str());
      ++failures;
      continue;
    }
    for (const int threads : options.threads) {
      for (const PfxUInt32 copies : kCopies) {
        PfxWorldBatch batch;
        if (batch.setNumThreads(PfxUInt32(threads)) != PFX_OK ||
            batch.addCopies(source, copies, &error) != PFX_OK || batch.step() != PFX_OK) {
          std::fprintf(stderr, "batch %s x%u: FAILED: %s\n", robot.name, copies, error.c_str());
          ++failures;
          continue;
        }
        const PfxUInt32 steps = std::max<PfxUInt32>(4, kWorldStepsPerRun / copies);
        const auto start = std::chrono::steady_clock::now();
        const PfxInt32 err = batch.step(steps);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (err != PFX_OK) {
          std::fprintf(stderr, "batch %s x%u: FAILED: %s\n", robot.name, copies,
                       pfxGetLastErrorDetail());
          ++failures;
          continue;
        }
        const double worldSteps = double(copies) * steps;
        std::fprintf(stderr, "batch %s x%u on %d threads: %.0f world-steps/s\n", robot.name,
                     copies, threads, worldSteps / seconds);
        rows.push_back({kBatchSceneName, "pfx", std::string(robot.name) + "/" + std::to_string(copies),
                        kTimeStep, 1, 10, threads, seconds / (worldSteps * kTimeStep),
                        "world_steps_per_s", worldSteps / seconds});
      }
    }
  }
  return failures;
}

}  // namespace pfxbench
