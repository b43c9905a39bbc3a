// Joint couplings (URDF <mimic>): a follower axis kept at multiplier * leader + offset while
// the leader is driven, with the ratio held over long runs, on hinges and sliders, against
// limits on either side, and bad couplings rejected without changing the world.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx_allocation_counter.h"
#include "pfx_object_bytes.h"

using namespace pfx;

namespace {

constexpr PfxFloat kNaN = std::numeric_limits<PfxFloat>::quiet_NaN();
constexpr PfxFloat kInf = std::numeric_limits<PfxFloat>::infinity();

PfxUInt32 addBody(PfxWorld& world, const PfxShape& shape, const PfxVector3& position,
                  PfxFloat mass) {
  PfxBodyInit init;
  init.mass = mass;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
  return id;
}

PfxFloat jointCoordinate(const PfxWorld& world, PfxUInt32 jointId, PfxUInt32 axis) {
  const PfxJoint& joint = world.getJoint(jointId);
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(joint, world.getRigidState(joint.m_rigidBodyIdA),
                          world.getRigidState(joint.m_rigidBodyIdB), coordinates);
  return coordinates[axis];
}

// Two rods on hinges about Z, side by side along Z so that they never touch, each hanging
// from a fixed pivot, under gravity along -Y: gravity loads both axes as they turn.
struct HingePair {
  PfxWorld world;
  PfxUInt32 leader = 0;
  PfxUInt32 follower = 0;
  PfxUInt32 leaderRod = 0;
  PfxUInt32 followerRod = 0;

  explicit HingePair(PfxFloat followerLower = -PFX_PI, PfxFloat followerUpper = PFX_PI,
                     PfxFloat leaderLower = -PFX_PI, PfxFloat leaderUpper = PFX_PI) {
    PfxWorldParam param;
    param.timeStep = PfxFloat(1) / 60;
    EXPECT_EQ(world.initialize(param), PFX_OK);
    leader = addHinge(0, leaderLower, leaderUpper, leaderRod);
    follower = addHinge(PfxFloat(0.5), followerLower, followerUpper, followerRod);
  }

  PfxUInt32 addHinge(PfxFloat z, PfxFloat lower, PfxFloat upper, PfxUInt32& rod) {
    const PfxUInt32 pivot =
        addBody(world, pfxMakeShape(PfxSphere(0.01f)), PfxVector3(0, 0, z), 0);
    rod = addBody(world, pfxMakeShape(PfxBox(0.25f, 0.02f, 0.02f)), PfxVector3(0.25f, 0, z), 1);
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = PfxVector3(0, 0, z);
    hinge.axis = PfxVector3::UnitZ();
    hinge.lowerAngle = lower;
    hinge.upperAngle = upper;
    PfxJoint joint;
    EXPECT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(pivot),
                                      world.getRigidState(rod), hinge),
              PFX_OK);
    PfxUInt32 id = 0;
    EXPECT_EQ(world.addJoint(joint, &id), PFX_OK);
    return id;
  }

  void drive(PfxUInt32 jointId, PfxJointDrive mode, PfxFloat target, PfxFloat maxForce) {
    PfxJoint joint = world.getJoint(jointId);
    PfxJointConstraint& twist = joint.m_constraints[kPfxJointAxisTwist];
    twist.m_drive = mode;
    twist.m_driveTarget = target;
    twist.m_driveMaxForce = maxForce;
    ASSERT_EQ(world.setJoint(jointId, joint), PFX_OK);
  }

  PfxInt32 couple(PfxFloat multiplier, PfxFloat offset, PfxUInt32* id = nullptr) {
    PfxJointCoupling coupling;
    coupling.reset();
    coupling.m_leaderJointId = leader;
    coupling.m_followerJointId = follower;
    coupling.m_leaderAxis = kPfxJointAxisTwist;
    coupling.m_followerAxis = kPfxJointAxisTwist;
    coupling.m_multiplier = multiplier;
    coupling.m_offset = offset;
    return world.addJointCoupling(coupling, id);
  }

  PfxFloat leaderAngle() const { return jointCoordinate(world, leader, kPfxJointAxisTwist); }
  PfxFloat followerAngle() const { return jointCoordinate(world, follower, kPfxJointAxisTwist); }

  // The coupling's error, with whole turns taken out (the multipliers here are integers, so
  // a turn of either coordinate changes it by a multiple of 2 pi).
  PfxFloat ratioError(PfxFloat multiplier, PfxFloat offset) const {
    return std::abs(std::remainder(followerAngle() - multiplier * leaderAngle() - offset,
                                   2 * PFX_PI));
  }
};

bool allFinite(const PfxWorld& world) {
  for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
    const PfxRigidState& s = world.getRigidState(i);
    if (!pfxIsFinite(s.getPosition()) || !pfxIsFinite(s.getLinearVelocity()) ||
        !pfxIsFinite(s.getAngularVelocity()) || !pfxIsFinite(s.getOrientation())) {
      return false;
    }
  }
  return true;
}

}  // namespace

// The leader turns at 1 rad/s under a velocity drive, through several whole turns, against
// gravity on both rods; the follower mirrors it (multiplier -1) to within 1e-4 rad for 10 s.
TEST(JointCoupling, MirroredHingeFollowsVelocityDrivenLeader) {
  HingePair rig;
  rig.drive(rig.leader, kPfxJointDriveVelocity, 1, 100);
  ASSERT_EQ(rig.couple(-1, 0), PFX_OK);
  PfxFloat worst = 0;
  PfxFloat travelled = 0;
  PfxFloat previous = rig.leaderAngle();
  for (int i = 0; i < 600; ++i) {
    ASSERT_EQ(rig.world.step(), PFX_OK);
    worst = std::max(worst, rig.ratioError(-1, 0));
    const PfxFloat angle = rig.leaderAngle();
    travelled += std::remainder(angle - previous, 2 * PFX_PI);
    previous = angle;
  }
  EXPECT_LT(worst, 1e-4f);
  EXPECT_NEAR(travelled, 10, 0.2);  // the drive was not held back
  EXPECT_NEAR(rig.world.getRigidState(rig.followerRod).getAngularVelocity().z(), -1, 0.02);
}

// Multiplier 2 and an offset, the leader following a sine under a position drive. The
// follower starts 0.3 rad off its target; the error is gone within a few steps and stays
// below 1e-4 rad for the rest of the 10 s. (Removing it moves the leader too, which its
// drive then brings back to the sine within half a second.)
TEST(JointCoupling, DoubledHingeWithOffsetFollowsPositionDrivenLeader) {
  HingePair rig;
  const PfxFloat multiplier = 2, offset = 0.3f;
  ASSERT_EQ(rig.couple(multiplier, offset), PFX_OK);
  EXPECT_NEAR(rig.world.getJointCoupling(0).m_error, -offset, 1e-6);
  PfxFloat worst = 0;
  PfxFloat worstLeaderLag = 0;
  for (int i = 0; i < 600; ++i) {
    const PfxFloat t = (i + 1) * rig.world.getParam().timeStep;
    const PfxFloat target = 0.6f * std::sin(2 * t);
    rig.drive(rig.leader, kPfxJointDrivePosition, target, 200);
    ASSERT_EQ(rig.world.step(), PFX_OK);
    if (i >= 5) worst = std::max(worst, rig.ratioError(multiplier, offset));
    if (i >= 30) worstLeaderLag = std::max(worstLeaderLag, std::abs(rig.leaderAngle() - target));
  }
  EXPECT_LT(worst, 1e-4f);
  EXPECT_LT(worstLeaderLag, 1e-3f);
  EXPECT_LT(std::abs(rig.world.getJointCoupling(0).m_error), 1e-3f);
}

// A gripper: a palm floating free (no gravity) with two fingers on sliders along +Y and -Y,
// the second finger mimicking the first (multiplier 1: both open together). The palm is a
// body of both joints, so the coupling acts on three bodies; being internal, neither the
// drive nor the coupling may change the total momentum.
TEST(JointCoupling, GripperFingersOnSlidersMoveTogether) {
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxUInt32 palm = addBody(world, pfxMakeShape(PfxBox(0.05f, 0.1f, 0.05f)),
                                 PfxVector3::Zero(), 0.5f);
  PfxUInt32 joints[2];
  PfxUInt32 fingers[2];
  for (int side = 0; side < 2; ++side) {
    const PfxFloat sign = side == 0 ? 1 : -1;
    fingers[side] = addBody(world, pfxMakeShape(PfxBox(0.01f, 0.01f, 0.04f)),
                            PfxVector3(0, sign * 0.02f, 0.1f), 0.05f);
    PfxSliderJointInitParam slider;
    slider.anchorPoint = PfxVector3(0, sign * 0.02f, 0.1f);
    slider.direction = PfxVector3(0, sign, 0);
    slider.lowerDistance = 0;
    slider.upperDistance = 0.04f;
    PfxJoint joint;
    ASSERT_EQ(pfxInitializeSliderJoint(joint, world.getRigidState(palm),
                                       world.getRigidState(fingers[side]), slider),
              PFX_OK);
    ASSERT_EQ(world.addJoint(joint, &joints[side]), PFX_OK);
  }
  PfxJoint leader = world.getJoint(joints[0]);
  leader.m_constraints[kPfxJointAxisX].m_drive = kPfxJointDriveVelocity;
  leader.m_constraints[kPfxJointAxisX].m_driveTarget = 0.02f;
  leader.m_constraints[kPfxJointAxisX].m_driveMaxForce = 20;
  ASSERT_EQ(world.setJoint(joints[0], leader), PFX_OK);
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = joints[0];
  coupling.m_followerJointId = joints[1];
  coupling.m_leaderAxis = kPfxJointAxisX;
  coupling.m_followerAxis = kPfxJointAxisX;
  ASSERT_EQ(world.addJointCoupling(coupling), PFX_OK);

  PfxFloat worst = 0;
  PfxFloat worstMomentum = 0;
  for (int i = 0; i < 180; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    worst = std::max(worst, std::abs(jointCoordinate(world, joints[1], kPfxJointAxisX) -
                                     jointCoordinate(world, joints[0], kPfxJointAxisX)));
    PfxVector3 momentum = PfxVector3::Zero();
    for (PfxUInt32 id : {palm, fingers[0], fingers[1]}) {
      momentum += world.getRigidBody(id).getMass() * world.getRigidState(id).getLinearVelocity();
    }
    worstMomentum = std::max(worstMomentum, momentum.norm());
  }
  EXPECT_LT(worst, 1e-4f);
  EXPECT_LT(worstMomentum, 1e-5f);
  // Opened at the drive's speed until the upper limit (0.04 m after 2 s), both fingers.
  EXPECT_NEAR(jointCoordinate(world, joints[0], kPfxJointAxisX), 0.04f, 1e-3);
  EXPECT_NEAR(jointCoordinate(world, joints[1], kPfxJointAxisX), 0.04f, 1e-3);
  const PfxFloat width = (world.getRigidState(fingers[0]).getPosition() -
                          world.getRigidState(fingers[1]).getPosition()).norm();
  EXPECT_NEAR(width, 0.04f + 2 * 0.04f, 2e-3);
}

// The follower meets its limit at 0.5 rad: the coupling holds the leader there too, against
// a drive of limited force, and neither passes the limit's value.
TEST(JointCoupling, FollowerLimitStopsTheLeader) {
  HingePair rig(-0.5f, 0.5f);
  rig.drive(rig.leader, kPfxJointDriveVelocity, 1, 20);
  ASSERT_EQ(rig.couple(1, 0), PFX_OK);
  PfxFloat highestFollower = -kInf;
  PfxFloat worst = 0;
  for (int i = 0; i < 180; ++i) {
    ASSERT_EQ(rig.world.step(), PFX_OK);
    highestFollower = std::max(highestFollower, rig.followerAngle());
    worst = std::max(worst, rig.ratioError(1, 0));
  }
  EXPECT_LT(highestFollower, 0.5f + 2e-3f);
  EXPECT_NEAR(rig.followerAngle(), 0.5f, 2e-3);
  EXPECT_NEAR(rig.leaderAngle(), 0.5f, 3e-3);
  EXPECT_LT(worst, 3e-3f);
  EXPECT_LT(std::abs(rig.world.getRigidState(rig.leaderRod).getAngularVelocity().z()), 1e-2f);
}

// A position drive without a force limit on the leader, its target beyond both joints'
// limits, the follower's limit the narrower: the follower's limit stops both, the ratio
// holds and the rods stay on their pivots (a mimic finger drifted 13 mm).
TEST(JointCoupling, UnlimitedDrivePastTheLimitsLeavesTheFollowerWithinItsOwn) {
  for (const PfxFloat target : {2.5f, -2.5f}) {
    SCOPED_TRACE(target);
    HingePair rig(-0.5f, 0.5f, -1, 1);
    rig.drive(rig.leader, kPfxJointDrivePosition, target, std::numeric_limits<PfxFloat>::max());
    ASSERT_EQ(rig.couple(1, 0), PFX_OK);
    PfxFloat followerExcursion = 0, worstRatio = 0, worstGap = 0;
    for (int i = 0; i < 180; ++i) {
      ASSERT_EQ(rig.world.step(), PFX_OK);
      ASSERT_TRUE(allFinite(rig.world));
      followerExcursion = std::max(followerExcursion, std::abs(rig.followerAngle()) - 0.5f);
      worstRatio = std::max(worstRatio, rig.ratioError(1, 0));
      worstGap = std::max(worstGap, rig.world.getStats().maxJointGap);
    }
    std::printf("target %.1f: follower past its limit by %.2e rad, ratio error %.2e rad, "
                "joint gap %.2e m\n",
                target, followerExcursion, worstRatio, worstGap);
    EXPECT_LT(followerExcursion, 0.01f);
    EXPECT_LT(worstRatio, 0.01f);
    EXPECT_LT(worstGap, 1e-3f);
    EXPECT_NEAR(std::abs(rig.followerAngle()), 0.5f, 0.01f);
  }
}

// A drive on the follower far stronger than the rods (it would reach 20 rad/s in one step)
// pulls the leader into its limit at 0.3 rad. Drive, coupling and limit are iterated
// together, and their impulses grow to the balance over a few steps with warm starting:
// meanwhile the leader may pass its limit a little, but nothing speeds up beyond what the
// drive asks, the ratio holds throughout, and after half a second both rest at the limit.
TEST(JointCoupling, LeaderBlockedByLimitDoesNotExplode) {
  HingePair rig(-PFX_PI, PFX_PI, -0.3f, 0.3f);
  rig.drive(rig.follower, kPfxJointDriveVelocity, 20, 1000);
  ASSERT_EQ(rig.couple(2, 0), PFX_OK);
  PfxFloat fastest = 0;
  PfxFloat highestLeader = -kInf;
  PfxFloat worst = 0;
  PfxFloat settledOvershoot = 0;
  for (int i = 0; i < 300; ++i) {
    ASSERT_EQ(rig.world.step(), PFX_OK);
    ASSERT_TRUE(allFinite(rig.world));
    highestLeader = std::max(highestLeader, rig.leaderAngle());
    worst = std::max(worst, rig.ratioError(2, 0));
    if (i >= 30) settledOvershoot = std::max(settledOvershoot, rig.leaderAngle() - 0.3f);
    for (PfxUInt32 rod : {rig.leaderRod, rig.followerRod}) {
      fastest = std::max(fastest, rig.world.getRigidState(rod).getAngularVelocity().norm());
    }
  }
  EXPECT_LT(highestLeader, 0.3f + 0.02f);
  EXPECT_LT(settledOvershoot, 1e-3f);
  EXPECT_LT(worst, 5e-3f);
  EXPECT_NEAR(rig.leaderAngle(), 0.3f, 1e-3);
  EXPECT_NEAR(rig.followerAngle(), 0.6f, 2e-3);
  EXPECT_LT(fastest, 20.5f);  // never faster than the drive asks
  EXPECT_LT(rig.world.getRigidState(rig.followerRod).getAngularVelocity().norm(), 0.05f);
}

TEST(JointCoupling, InvalidCouplingsAreRejectedAndChangeNothing) {
  HingePair rig;
  PfxUInt32 id = 77;
  ASSERT_EQ(rig.couple(2, 0.1f, &id), PFX_OK);
  ASSERT_EQ(id, 0u);
  const std::vector<unsigned char> kept = pfx_test::objectBytes(rig.world.getJointCoupling(0));
  auto unchanged = [&] {
    return rig.world.getNumJointCouplings() == 1 &&
           pfx_test::sameBytes(kept, rig.world.getJointCoupling(0));
  };

  PfxJointCoupling good;
  good.reset();
  good.m_leaderJointId = rig.leader;
  good.m_followerJointId = rig.follower;
  good.m_leaderAxis = good.m_followerAxis = kPfxJointAxisTwist;
  struct Case {
    const char* what;
    void (*spoil)(PfxJointCoupling&);
    PfxInt32 expected;
  };
  const Case cases[] = {
      {"unknown leader", [](PfxJointCoupling& c) { c.m_leaderJointId = 9; }, PFX_ERR_OUT_OF_RANGE},
      {"unknown follower", [](PfxJointCoupling& c) { c.m_followerJointId = 2; },
       PFX_ERR_OUT_OF_RANGE},
      {"axis 6", [](PfxJointCoupling& c) { c.m_followerAxis = 6; }, PFX_ERR_OUT_OF_RANGE},
      {"locked leader axis", [](PfxJointCoupling& c) { c.m_leaderAxis = kPfxJointAxisY; },
       PFX_ERR_INVALID_VALUE},
      {"locked follower axis", [](PfxJointCoupling& c) { c.m_followerAxis = kPfxJointAxisSwing1; },
       PFX_ERR_INVALID_VALUE},
      {"axis coupled to itself", [](PfxJointCoupling& c) { c.m_followerJointId = c.m_leaderJointId; },
       PFX_ERR_INVALID_VALUE},
      {"NaN multiplier", [](PfxJointCoupling& c) { c.m_multiplier = kNaN; }, PFX_ERR_INVALID_VALUE},
      {"infinite offset", [](PfxJointCoupling& c) { c.m_offset = kInf; }, PFX_ERR_INVALID_VALUE},
      // Found by fuzz_world_file: a saved offset of 3.4e38 made the error over the step
      // infinite and the coupled bodies NaN in the first step.
      {"offset whose square overflows",
       [](PfxJointCoupling& c) { c.m_offset = std::numeric_limits<PfxFloat>::max(); },
       PFX_ERR_INVALID_VALUE},
      {"tracked position whose square overflows",
       [](PfxJointCoupling& c) { c.m_leaderPosition = -std::numeric_limits<PfxFloat>::max(); },
       PFX_ERR_INVALID_VALUE},
      {"multiplier whose square overflows",
       [](PfxJointCoupling& c) { c.m_multiplier = std::numeric_limits<PfxFloat>::max() / 2; },
       PFX_ERR_INVALID_VALUE},
      {"bias above 1", [](PfxJointCoupling& c) { c.m_bias = 1.5f; }, PFX_ERR_INVALID_VALUE},
      {"negative bias", [](PfxJointCoupling& c) { c.m_bias = -0.1f; }, PFX_ERR_INVALID_VALUE},
      {"NaN bias", [](PfxJointCoupling& c) { c.m_bias = kNaN; }, PFX_ERR_INVALID_VALUE},
      {"NaN force limit", [](PfxJointCoupling& c) { c.m_maxImpulseForce = kNaN; },
       PFX_ERR_INVALID_VALUE},
  };
  for (const Case& c : cases) {
    PfxJointCoupling bad = good;
    c.spoil(bad);
    PfxUInt32 badId = 55;
    EXPECT_EQ(rig.world.addJointCoupling(bad, &badId), c.expected) << c.what;
    EXPECT_EQ(badId, 55u) << c.what;
    EXPECT_EQ(rig.world.setJointCoupling(0, bad), c.expected) << c.what;
    EXPECT_TRUE(unchanged()) << c.what;
  }
  EXPECT_EQ(rig.world.setJointCoupling(1, good), PFX_ERR_OUT_OF_RANGE);
  EXPECT_TRUE(unchanged());

  // Locking a coupled axis afterwards is refused as well.
  PfxJoint locked = rig.world.getJoint(rig.follower);
  locked.m_constraints[kPfxJointAxisTwist].m_lock = kPfxJointLockLocked;
  EXPECT_EQ(rig.world.setJoint(rig.follower, locked), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rig.world.getJoint(rig.follower).m_constraints[kPfxJointAxisTwist].m_lock,
            kPfxJointLockLimit);

  // A world that is re-initialized forgets its couplings with its joints.
  ASSERT_EQ(rig.world.initialize(rig.world.getParam()), PFX_OK);
  EXPECT_EQ(rig.world.getNumJointCouplings(), 0u);
}

// An inactive coupling leaves the follower alone: it hangs still while the leader turns.
TEST(JointCoupling, InactiveCouplingDoesNothing) {
  HingePair rig;
  rig.drive(rig.leader, kPfxJointDriveVelocity, 1, 100);
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = rig.leader;
  coupling.m_followerJointId = rig.follower;
  coupling.m_leaderAxis = coupling.m_followerAxis = kPfxJointAxisTwist;
  coupling.m_active = 0;
  ASSERT_EQ(rig.world.addJointCoupling(coupling), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(rig.world.step(), PFX_OK);
  EXPECT_NEAR(rig.leaderAngle(), 1, 0.05);
  // Hanging from the pivot along +X, gravity swings it down: it is free, not held at zero
  // nor made to follow.
  EXPECT_LT(rig.followerAngle(), -0.3f);
}

// Stepping a coupled pair allocates nothing once the world is warm.
TEST(JointCoupling, StepAllocatesNothing) {
  HingePair rig;
  rig.drive(rig.leader, kPfxJointDriveVelocity, 1, 100);
  ASSERT_EQ(rig.couple(-1, 0), PFX_OK);
  for (int i = 0; i < 10; ++i) ASSERT_EQ(rig.world.step(), PFX_OK);
  const long before = pfx_test::pfxAllocationCount();
  for (int i = 0; i < 10; ++i) ASSERT_EQ(rig.world.step(), PFX_OK);
  EXPECT_EQ(pfx_test::pfxAllocationCount() - before, 0);
}
