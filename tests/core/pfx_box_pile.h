// A pile of boxes in a bin, for the sleep tests: when it comes to rest, and when it is
// fully asleep.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"

namespace pfx_test {

using namespace pfx;

// A ground, four walls, and `count` 0.5 m boxes above the floor in layers of n x n (n the
// cube root, rounded up), each a little off the grid and turned.
inline void addBoxPileInBin(PfxWorld& world, int count) {
  int n = 1;
  while (n * n * n < count) ++n;
  const auto addFixed = [&](const PfxVector3& position, const PfxVector3& half) {
    PfxBodyInit init;
    init.mass = 0;
    init.position = position;
    EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(half.x(), half.y(), half.z())), init), PFX_OK);
  };
  addFixed(PfxVector3(0, -0.5f, 0), PfxVector3(30, 0.5f, 30));
  const PfxFloat inner = n * 0.33f;
  for (const PfxFloat side : {-1.0f, 1.0f}) {
    addFixed(PfxVector3(side * (inner + 0.1f), 2, 0), PfxVector3(0.1f, 2, inner + 0.2f));
    addFixed(PfxVector3(0, 2, side * (inner + 0.1f)), PfxVector3(inner + 0.2f, 2, 0.1f));
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<PfxFloat> jitter(-1, 1);
  for (int i = 0; i < count; ++i) {
    const int layer = i / (n * n), cell = i % (n * n);
    PfxBodyInit init;
    init.position = PfxVector3{(cell % n - 0.5f * (n - 1)) * 0.62f + 0.05f * jitter(rng),
                               0.3f + layer * 0.62f,
                               (cell / n - 0.5f * (n - 1)) * 0.62f + 0.05f * jitter(rng)};
    const PfxVector3 axis{jitter(rng), jitter(rng), jitter(rng)};
    init.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f * jitter(rng), axis.normalized()));
    EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.25f, 0.25f, 0.25f)), init), PFX_OK);
  }
}

// Steps of a pile's history: the first at which no body had moved more than 5 cm (a tenth
// of its size) over the half second before (at rest, to the eye), and the first after
// which no body was awake (-1: never).
struct PileSteps {
  int rest = -1;
  int asleep = -1;
};

inline PileSteps settlePile(PfxWorld& world, int maxSteps) {
  const int window = static_cast<int>(0.5f / world.getParam().timeStep + 0.5f);
  std::vector<PfxVector3> previous(world.getNumRigidBodies());
  PileSteps steps;
  for (int step = 1; step <= maxSteps && (steps.asleep < 0 || steps.rest < 0); ++step) {
    EXPECT_EQ(world.step(), PFX_OK);
    if (steps.asleep < 0 && world.getStats().numAwakeBodies == 0) steps.asleep = step;
    if (step % window != 0) continue;
    PfxFloat moved = 0;
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      moved = std::max(moved, (world.getRigidState(id).getPosition() - previous[id]).norm());
      previous[id] = world.getRigidState(id).getPosition();
    }
    if (steps.rest < 0 && step > window && moved < 0.05f) steps.rest = step;
  }
  return steps;
}

// Drops `count` boxes into a bin and checks that they come to rest within `maxSteps` and
// are all asleep, as one island each, within 5 s of it.
inline void expectPileSleepsWithinFiveSecondsOfRest(PfxWorld& world, int count, int maxSteps) {
  addBoxPileInBin(world, count);
  const PileSteps steps = settlePile(world, maxSteps);
  std::printf("%d boxes: at rest after %.2f s, asleep after %.2f s\n", count, steps.rest / 60.0,
              steps.asleep / 60.0);
  ASSERT_GT(steps.rest, 0) << "the pile never came to rest";
  ASSERT_GT(steps.asleep, 0) << "the pile never fell asleep";
  EXPECT_LE(steps.asleep, steps.rest + 5 * 60);
  EXPECT_EQ(world.getStats().numSleepingBodies, PfxUInt32(count));
  EXPECT_EQ(world.getStats().numSleepingIslands, world.getStats().numIslands);
}

}  // namespace pfx_test
