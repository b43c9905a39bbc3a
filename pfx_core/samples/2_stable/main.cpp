// Sample 2_stable: a pyramid of 55 boxes (10 at the base) and a tower of 10 boxes drop a
// little onto a fixed ground and settle, in the stable pipeline (cached pairs, contact
// points and impulses, warm-started solver). Prints how far each structure moved from
// where it was built and whether it still stands.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

constexpr PfxFloat kHalf = 0.5f;  // boxes are 1 m cubes
constexpr PfxFloat kDrop = 0.05f; // each layer starts this far above the one below

struct Built {
  PfxUInt32 id;
  PfxVector3 restPosition;  // where the box sits when the structure stands undisturbed
};

void addGround(PfxWorld& world) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = PfxVector3(0, -1, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(60, 1, 60)), init);
}

Built addBox(PfxWorld& world, PfxFloat x, int layer, PfxFloat z) {
  PfxBodyInit init;
  init.mass = 1;
  init.position = PfxVector3(x, kHalf + layer * (2 * kHalf + kDrop) + kDrop, z);
  Built built;
  pfxAddBody(world, pfxMakeShape(PfxBox(kHalf, kHalf, kHalf)), init, &built.id);
  built.restPosition = PfxVector3(x, kHalf + layer * 2 * kHalf, z);
  return built;
}

// Largest distance of any box from its rest position.
PfxFloat largestDrift(const PfxWorld& world, const std::vector<Built>& boxes) {
  PfxFloat drift = 0;
  for (const Built& b : boxes) {
    drift = std::max(drift, (world.getRigidState(b.id).getPosition() - b.restPosition).norm());
  }
  return drift;
}

}  // namespace

int main() {
  PfxWorld world;
  PfxWorldParam param;
  param.pipeline = kPfxPipelineStable;
  param.timeStep = 1.0f / 60.0f;
  param.iteration = 10;
  world.initialize(param);
  addGround(world);

  std::vector<Built> pyramid, tower;
  const int base = 10;
  for (int layer = 0; layer < base; ++layer) {
    const int count = base - layer;
    for (int i = 0; i < count; ++i) {
      const PfxFloat x = -8.0f + (i - 0.5f * (count - 1)) * (2 * kHalf + 0.02f);
      pyramid.push_back(addBox(world, x, layer, 0));
    }
  }
  for (int layer = 0; layer < 10; ++layer) tower.push_back(addBox(world, 8.0f, layer, 0));

  const int seconds = 20;
  const int steps = static_cast<int>(seconds / param.timeStep);
  double stageTotals[kPfxStageCount] = {};
  double stepTotal = 0;
  PfxFloat maxPenetration = 0;
  for (int s = 0; s < steps; ++s) {
    if (world.step() != PFX_OK) {
      std::printf("step %d failed\n", s);
      return 1;
    }
    const PfxWorldStats& stats = world.getStats();
    for (int k = 0; k < kPfxStageCount; ++k) stageTotals[k] += stats.stageSeconds[k];
    stepTotal += stats.stepSeconds;
    if (s > steps / 2) maxPenetration = std::max(maxPenetration, stats.maxPenetration);
  }

  PfxFloat maxSpeed = 0;
  for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
    maxSpeed = std::max(maxSpeed, world.getRigidState(i).getLinearVelocity().norm());
  }
  const PfxFloat pyramidDrift = largestDrift(world, pyramid);
  const PfxFloat towerDrift = largestDrift(world, tower);
  const PfxWorldStats& stats = world.getStats();

  std::printf("2_stable: %u bodies, %d steps of %.4f s, %u iterations\n",
              world.getNumRigidBodies(), steps, param.timeStep, param.iteration);
  std::printf("pyramid (55 boxes): top at y = %.3f m (built for %.3f), largest drift %.4f m -> %s\n",
              world.getRigidState(pyramid.back().id).getPosition().y(), pyramid.back().restPosition.y(),
              pyramidDrift, pyramidDrift < 0.05f ? "stands" : "FELL");
  std::printf("tower (10 boxes):   top at y = %.3f m (built for %.3f), largest drift %.4f m -> %s\n",
              world.getRigidState(tower.back().id).getPosition().y(), tower.back().restPosition.y(),
              towerDrift, towerDrift < 0.05f ? "stands" : "FELL");
  std::printf("at rest: fastest body %.5f m/s; deepest penetration in the last 10 s %.4f m\n",
              maxSpeed, maxPenetration);
  std::printf("last step: %u pairs, %u touching, %u contact points\n", stats.numPairs,
              stats.numContactPairs, stats.numContactPoints);
  std::printf("mean step time %.3f ms:\n", 1e3 * stepTotal / steps);
  for (int k = 0; k < kPfxStageCount; ++k) {
    std::printf("  %-26s %8.4f ms\n", pfxStageName(static_cast<PfxStage>(k)),
                1e3 * stageTotals[k] / steps);
  }
  return (pyramidDrift < 0.05f && towerDrift < 0.05f) ? 0 : 1;
}
