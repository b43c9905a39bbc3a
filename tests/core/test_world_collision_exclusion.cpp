// PfxWorld::excludeCollision: two bodies that overlap stay where they are once their pair is
// excluded, while each still meets everything else; bad ids change nothing; truncate drops
// the exclusions of the bodies it removes.
#include <gtest/gtest.h>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"

using namespace pfx;

namespace {

// No gravity: only contacts move anything. Two boxes overlapping by 0.1 m at the origin,
// and a sphere resting on neither.
void buildOverlap(PfxWorld& world, PfxUInt32 ids[3]) {
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit init;
  init.position = PfxVector3(0, 0, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &ids[0]), PFX_OK);
  init.position = PfxVector3(0.9f, 0, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &ids[1]), PFX_OK);
  init.position = PfxVector3(0, 5, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5f)), init, &ids[2]), PFX_OK);
}

PfxFloat separation(const PfxWorld& world, const PfxUInt32 ids[3]) {
  return (world.getRigidState(ids[1]).getPosition() - world.getRigidState(ids[0]).getPosition())
      .norm();
}

void stepFor(PfxWorld& world, int steps) {
  for (int i = 0; i < steps; ++i) ASSERT_EQ(world.step(), PFX_OK);
}

}  // namespace

TEST(WorldCollisionExclusion, ExcludedOverlappingBodiesStayPutAndOthersStillCollide) {
  PfxWorld pushed;
  PfxUInt32 ids[3];
  ASSERT_NO_FATAL_FAILURE(buildOverlap(pushed, ids));
  ASSERT_NO_FATAL_FAILURE(stepFor(pushed, 60));
  EXPECT_GT(separation(pushed, ids), 0.95f) << "without the exclusion the overlap is resolved";

  PfxWorld world;
  ASSERT_NO_FATAL_FAILURE(buildOverlap(world, ids));
  ASSERT_EQ(world.excludeCollision(ids[1], ids[0]), PFX_OK);
  ASSERT_EQ(world.excludeCollision(ids[0], ids[1]), PFX_OK);  // again: still one exclusion
  ASSERT_NO_FATAL_FAILURE(stepFor(world, 60));
  EXPECT_FLOAT_EQ(separation(world, ids), 0.9f);
  EXPECT_EQ(world.getStats().numContactPoints, 0u);

  // The sphere thrown at the first box still hits it.
  PfxRigidState sphere = world.getRigidState(ids[2]);
  sphere.setLinearVelocity(PfxVector3(0, -10, 0));
  ASSERT_EQ(world.setRigidState(ids[2], sphere), PFX_OK);
  ASSERT_NO_FATAL_FAILURE(stepFor(world, 60));
  EXPECT_GT(world.getRigidState(ids[2]).getLinearVelocity().y(), -9.0f);
  EXPECT_GT(world.getRigidState(ids[0]).getLinearVelocity().norm(), 0.1f);
}

TEST(WorldCollisionExclusion, BadIdsChangeNothingAndTruncateDropsTheExclusion) {
  PfxWorld world;
  PfxUInt32 ids[3];
  ASSERT_NO_FATAL_FAILURE(buildOverlap(world, ids));
  EXPECT_EQ(world.excludeCollision(ids[0], 3), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.excludeCollision(7, ids[1]), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.excludeCollision(ids[1], ids[1]), PFX_ERR_INVALID_VALUE);
  ASSERT_NO_FATAL_FAILURE(stepFor(world, 60));
  EXPECT_GT(separation(world, ids), 0.95f) << "a refused exclusion excludes nothing";

  // Excluded, then the second box removed and added again at the overlap: the new body
  // with the same id collides.
  ASSERT_NO_FATAL_FAILURE(buildOverlap(world, ids));
  ASSERT_EQ(world.excludeCollision(ids[0], ids[1]), PFX_OK);
  ASSERT_EQ(world.truncate(1, 0, 0), PFX_OK);
  PfxBodyInit init;
  init.position = PfxVector3(0.9f, 0, 0);
  PfxUInt32 again = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &again), PFX_OK);
  ASSERT_EQ(again, ids[1]);
  ASSERT_NO_FATAL_FAILURE(stepFor(world, 60));
  EXPECT_GT(separation(world, ids), 0.95f);
}
