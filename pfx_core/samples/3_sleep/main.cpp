// Sample 3_sleep: 1,000 boxes (or as many as the first argument says) are dropped into a
// bin, settle and fall asleep as one island; a box thrown into the pile wakes it, and it
// settles and sleeps again. Prints the awake and sleeping bodies and islands every half
// second, then the step time of the settled pile awake (its last half second before it
// fell asleep) against asleep.
#include <cstdio>
#include <cstdlib>
#include <random>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

constexpr PfxFloat kHalf = 0.25f;  // boxes are 0.5 m cubes

void addFixedBox(PfxWorld& world, const PfxVector3& position, const PfxVector3& half) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = position;
  pfxAddBody(world, pfxMakeShape(PfxBox(half.x(), half.y(), half.z())), init);
}

// A ground and four walls, 6 m high, around a floor for layers of perSide x perSide boxes.
void addBin(PfxWorld& world, int perSide) {
  addFixedBox(world, PfxVector3(0, -1, 0), PfxVector3(30, 1, 30));
  const PfxFloat inner = perSide * 0.66f / 2;
  for (int side = -1; side <= 1; side += 2) {
    addFixedBox(world, PfxVector3(side * (inner + 0.25f), 3, 0), PfxVector3(0.25f, 3, inner + 0.5f));
    addFixedBox(world, PfxVector3(0, 3, side * (inner + 0.25f)), PfxVector3(inner + 0.5f, 3, 0.25f));
  }
}

// Boxes in layers of perSide x perSide, each a little off the grid and turned.
void addPile(PfxWorld& world, int count, int perSide) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<PfxFloat> jitter(-1, 1);
  for (int i = 0; i < count; ++i) {
    const int layer = i / (perSide * perSide);
    const int cell = i % (perSide * perSide);
    PfxBodyInit init;
    init.position = PfxVector3((cell % perSide - 0.5f * (perSide - 1)) * 0.62f + 0.05f * jitter(rng),
                               0.3f + layer * 0.62f,
                               (cell / perSide - 0.5f * (perSide - 1)) * 0.62f + 0.05f * jitter(rng));
    const PfxVector3 axis(jitter(rng), jitter(rng), jitter(rng));
    init.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f * jitter(rng), axis.normalized()));
    pfxAddBody(world, pfxMakeShape(PfxBox(kHalf, kHalf, kHalf)), init);
  }
}

// Bodies and islands awake and asleep, and the pairs the step worked on against those set
// aside asleep.
void printStats(double clock, const PfxWorldStats& stats) {
  std::printf("%6.2f s  bodies awake %5u asleep %5u  islands %4u asleep %4u  pairs %5u asleep %5u"
              "  step %7.3f ms\n",
              clock, stats.numAwakeBodies, stats.numSleepingBodies, stats.numIslands,
              stats.numSleepingIslands, stats.numPairs, stats.numSleepingPairs,
              1e3 * stats.stepSeconds);
}

struct Timing {
  double awakeSeconds = 0;  // the last half second before the pile fell asleep
  int awakeSteps = 0;
  double asleepSeconds = 0;
  int asleepSteps = 0;
};

// Steps until every body sleeps (or `maxSeconds` pass), printing every half second and
// recording step times. Returns the time it took, or a negative time if it never slept.
double runUntilAsleep(PfxWorld& world, double& clock, double maxSeconds, Timing& timing) {
  const PfxFloat dt = world.getParam().timeStep;
  const int halfSecond = static_cast<int>(0.5 / dt + 0.5);
  double recent[64] = {};
  const int window = halfSecond < 64 ? halfSecond : 64;
  const double start = clock;
  for (int s = 1; clock - start < maxSeconds; ++s) {
    if (world.step() != PFX_OK) return -1;
    clock += dt;
    const PfxWorldStats& stats = world.getStats();
    recent[s % window] = stats.stepSeconds;
    if (s % halfSecond == 0 || stats.numAwakeBodies == 0) {
      printStats(clock, stats);
    }
    if (stats.numAwakeBodies == 0) {
      if (s > window) {
        for (int k = 0; k < window; ++k) timing.awakeSeconds += recent[k];
        timing.awakeSteps += window;
      }
      return clock - start;
    }
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 1000;
  if (count < 1 || count > 100000) {
    std::fprintf(stderr, "usage: %s [number of boxes, 1..100000]\n", argv[0]);
    return 2;
  }
  int perSide = 1;
  while (perSide * perSide * perSide < count) ++perSide;

  PfxWorld world;
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(200);  // sleep is on by default
  world.initialize(param);
  addBin(world, perSide);
  addPile(world, count, perSide);
  std::printf("3_sleep: %d boxes dropped into a bin; sleep after %.1f s below %.2f m/s and %.2f rad/s\n",
              count, param.sleepTime, param.sleepLinearVelocity, param.sleepAngularVelocity);

  Timing timing;
  double clock = 0;
  const double settled = runUntilAsleep(world, clock, 60, timing);
  if (settled < 0) {
    std::printf("the pile did not fall asleep within 60 s\n");
    return 1;
  }
  std::printf("-- asleep after %.2f s; 2 s asleep:\n", settled);
  for (int s = 0; s < 120; ++s) {
    world.step();
    clock += param.timeStep;
    timing.asleepSeconds += world.getStats().stepSeconds;
    ++timing.asleepSteps;
  }
  printStats(clock, world.getStats());

  // A box thrown down into the pile at 15 m/s wakes the island it hits.
  PfxBodyInit thrown;
  thrown.position = PfxVector3(0.3f, 2 + perSide * 0.7f, 0.2f);
  thrown.linearVelocity = PfxVector3(0, -15, 0);
  thrown.angularVelocity = PfxVector3(2, 0, 1);
  thrown.mass = 5;
  pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), thrown);
  std::printf("-- a 5 kg box thrown in at 15 m/s:\n");
  Timing again;
  const double resettled = runUntilAsleep(world, clock, 60, again);
  if (resettled < 0) {
    std::printf("the pile did not fall asleep again within 60 s\n");
    return 1;
  }
  std::printf("-- asleep again %.2f s after the throw\n", resettled);

  const double awakeMs = 1e3 * timing.awakeSeconds / timing.awakeSteps;
  const double asleepMs = 1e3 * timing.asleepSeconds / timing.asleepSteps;
  std::printf("settled pile, mean step: awake %.3f ms, asleep %.3f ms (%.3f of awake)\n", awakeMs,
              asleepMs, asleepMs / awakeMs);
  return 0;
}
