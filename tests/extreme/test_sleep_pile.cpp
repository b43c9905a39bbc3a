// 1,000 boxes dropped into a bin come to rest and are fully asleep within 5 s of it, as
// one island; asleep, nothing moves and no pair is solved.
#include <gtest/gtest.h>

#include <vector>

#include "pfx_box_pile.h"

using namespace pfx;

TEST(SleepPile, ThousandBoxesSleepWithinFiveSecondsOfComingToRest) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  pfx_test::expectPileSleepsWithinFiveSecondsOfRest(world, 1000, 60 * 40);
  if (::testing::Test::HasFatalFailure()) return;
  const PfxWorldStats& stats = world.getStats();

  const std::vector<PfxRigidState> before(world.getRigidStates(),
                                          world.getRigidStates() + world.getNumRigidBodies());
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_EQ(stats.numPairs, 0u);
  EXPECT_GT(stats.numSleepingPairs, 1000u);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    EXPECT_EQ(world.getRigidState(id).getPosition(), before[id].getPosition());
  }
}
