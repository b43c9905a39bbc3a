// PfxWorld::truncate: bodies, joints and couplings added after a point can be taken out
// again as if they had never been added (what a loader does when a load fails half way):
// the bodies kept move bit for bit as in a world that never had the others, pairs and rays
// forget the removed bodies, and bad counts are rejected with nothing changed.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

// A ground and a little stack with a hinged pair on it: contacts, joints and sleep-free
// motion for a few seconds.
void buildBase(PfxWorld& world) {
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  PfxUInt32 ids[3];
  for (int i = 0; i < 3; ++i) {
    PfxBodyInit box;
    box.position = PfxVector3(0.1f * i, 0.5f + 1.01f * i, 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), box, &ids[i]), PFX_OK);
  }
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = PfxVector3(0.05f, 1.0f, 0.5f);
  hinge.axis = PfxVector3(0, 0, 1);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(ids[0]), world.getRigidState(ids[1]),
                                    hinge),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
}

// Far from the base: two spheres resting on the ground, joined by hinges to a third, with
// the two hinges coupled.
void addExtras(PfxWorld& world) {
  const PfxUInt32 first = world.getNumRigidBodies();
  for (int i = 0; i < 3; ++i) {
    PfxBodyInit ball;
    ball.position = PfxVector3(8 + 0.5f * i, 0.25f, 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.25f)), ball), PFX_OK);
  }
  PfxUInt32 hinges[2];
  for (int i = 0; i < 2; ++i) {
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = PfxVector3(8.25f + 0.5f * i, 0.25f, 0);
    PfxJoint joint;
    ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(first + i),
                                      world.getRigidState(first + i + 1), hinge),
              PFX_OK);
    ASSERT_EQ(world.addJoint(joint, &hinges[i]), PFX_OK);
  }
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = hinges[0];
  coupling.m_followerJointId = hinges[1];
  coupling.m_leaderAxis = coupling.m_followerAxis = kPfxJointAxisTwist;
  ASSERT_EQ(world.addJointCoupling(coupling), PFX_OK);
}

std::vector<unsigned char> stateBytes(const PfxWorld& world, PfxUInt32 numBodies) {
  const auto* begin = reinterpret_cast<const unsigned char*>(world.getRigidStates());
  return std::vector<unsigned char>(begin, begin + numBodies * sizeof(PfxRigidState));
}

}  // namespace

TEST(WorldTruncate, KeptBodiesMoveAsIfTheOthersHadNeverBeen) {
  PfxWorld plain, grown;
  buildBase(plain);
  buildBase(grown);
  const PfxUInt32 bodies = plain.getNumRigidBodies(), joints = plain.getNumJoints();
  for (int i = 0; i < 30; ++i) {
    ASSERT_EQ(plain.step(), PFX_OK);
    ASSERT_EQ(grown.step(), PFX_OK);
  }
  addExtras(grown);
  for (int i = 0; i < 30; ++i) {
    ASSERT_EQ(plain.step(), PFX_OK);
    ASSERT_EQ(grown.step(), PFX_OK);
  }
  // The extras rest on the ground: their contact pairs exist until the truncation.
  bool extraPairs = false;
  for (PfxUInt32 i = 0; i < grown.getNumContactPairs(); ++i) {
    extraPairs = extraPairs || pfxGetObjectIdB(grown.getContactPair(i)) >= bodies;
  }
  EXPECT_TRUE(extraPairs);
  ASSERT_EQ(grown.truncate(bodies, joints, 0), PFX_OK);
  EXPECT_EQ(grown.getNumRigidBodies(), bodies);
  EXPECT_EQ(grown.getNumJoints(), joints);
  EXPECT_EQ(grown.getNumJointCouplings(), 0u);
  for (PfxUInt32 i = 0; i < grown.getNumContactPairs(); ++i) {
    EXPECT_LT(pfxGetObjectIdA(grown.getContactPair(i)), bodies);
    EXPECT_LT(pfxGetObjectIdB(grown.getContactPair(i)), bodies);
  }
  for (int i = 0; i < 120; ++i) {
    ASSERT_EQ(plain.step(), PFX_OK);
    ASSERT_EQ(grown.step(), PFX_OK);
  }
  EXPECT_TRUE(stateBytes(plain, bodies) == stateBytes(grown, bodies));
  EXPECT_EQ(plain.getNumContactPairs(), grown.getNumContactPairs());

  // Rays no longer find the removed spheres.
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(8.5f, 3, 0);
  ray.m_direction = PfxVector3(0, -4, 0);
  PfxRayOutput out;
  ASSERT_EQ(grown.castRay(ray, out), PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_objectId, 0u);  // the ground, below where the spheres were
  EXPECT_NEAR(out.m_contactPoint.y(), 0, 1e-5);
}

TEST(WorldTruncate, RemovedJointsNoLongerKeepTheirBodiesApart) {
  // Two overlapping spheres joined by a joint do not collide; once the joint is truncated
  // away (bodies kept), they push apart.
  PfxWorld world;
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit init;
  PfxUInt32 a, b;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5f)), init, &a), PFX_OK);
  init.position = PfxVector3(0.5f, 0, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5f)), init, &b), PFX_OK);
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(0.25f, 0, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(a), world.getRigidState(b), ball),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  for (int i = 0; i < 10; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_EQ(world.getStats().numContactPairs, 0u);
  ASSERT_EQ(world.truncate(2, 0, 0), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxFloat gap =
      (world.getRigidState(b).getPosition() - world.getRigidState(a).getPosition()).norm();
  printf("spheres 0.5 m apart after their joint was truncated away: %.3f m apart after 1 s\n", gap);
  EXPECT_GT(gap, 0.9f);
}

TEST(WorldTruncate, BadCountsAreRejectedWithNothingChanged) {
  PfxWorld world;
  buildBase(world);
  addExtras(world);
  for (int i = 0; i < 5; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxUInt32 bodies = world.getNumRigidBodies(), joints = world.getNumJoints(),
                  couplings = world.getNumJointCouplings();
  const std::vector<unsigned char> before = stateBytes(world, bodies);
  EXPECT_EQ(world.truncate(bodies + 1, joints, couplings), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.truncate(bodies, joints + 1, couplings), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.truncate(bodies, joints, couplings + 1), PFX_ERR_OUT_OF_RANGE);
  // A kept joint that holds a removed body, a kept coupling of a removed joint.
  EXPECT_EQ(world.truncate(bodies - 1, joints, couplings), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.truncate(bodies, joints - 1, couplings), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.getNumRigidBodies(), bodies);
  EXPECT_EQ(world.getNumJoints(), joints);
  EXPECT_EQ(world.getNumJointCouplings(), couplings);
  EXPECT_TRUE(stateBytes(world, bodies) == before);
  // Keeping everything is allowed and changes nothing.
  EXPECT_EQ(world.truncate(bodies, joints, couplings), PFX_OK);
  EXPECT_TRUE(stateBytes(world, bodies) == before);
  ASSERT_EQ(world.step(), PFX_OK);
}
