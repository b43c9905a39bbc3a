// 1,000 boxes dropped into a bin come to rest and are fully asleep within 5 s of it, as
// one island; asleep, nothing moves and no pair is solved.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "pfx_box_pile.h"

using namespace pfx;

TEST(SleepPile, ThousandBoxesSleepWithinFiveSecondsOfComingToRest) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  pfx_test::addBoxPileInBin(world, 1000);
  const pfx_test::PileSteps steps = pfx_test::settlePile(world, 60 * 40);
  std::printf("1,000 boxes: at rest after %.2f s, asleep after %.2f s\n", steps.rest / 60.0,
              steps.asleep / 60.0);
  ASSERT_GT(steps.rest, 0) << "the pile never came to rest";
  ASSERT_GT(steps.asleep, 0) << "the pile never fell asleep";
  EXPECT_LE(steps.asleep, steps.rest + 5 * 60);
  const PfxWorldStats& stats = world.getStats();
  EXPECT_EQ(stats.numSleepingBodies, 1000u);
  EXPECT_EQ(stats.numSleepingIslands, stats.numIslands);

  const std::vector<PfxRigidState> before(world.getRigidStates(),
                                          world.getRigidStates() + world.getNumRigidBodies());
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_EQ(stats.numPairs, 0u);
  EXPECT_GT(stats.numSleepingPairs, 1000u);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    EXPECT_EQ(world.getRigidState(id).getPosition(), before[id].getPosition());
  }
}
