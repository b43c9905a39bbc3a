// Joints whose rotations are measured as Euler angles (kPfxJointRotationEulerYZX): the
// coordinates are the angles of the turns about Y, the turned Z and the twice-turned X;
// the rows drive exactly those angles, so limits on each hold when they act together; and
// bad values of the field are rejected.
#include <gtest/gtest.h>

#include <cmath>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"

using namespace pfx;

namespace {

PfxMatrix3 turn(PfxFloat angle, const PfxVector3& axis) {
  return Eigen::AngleAxis<PfxFloat>(angle, axis).toRotationMatrix();
}

PfxRigidState stateAt(PfxUInt32 id, const PfxMatrix3& rotation, const PfxVector3& position) {
  PfxRigidState state;
  state.reset();
  state.setRigidBodyId(id);
  state.setPosition(position);
  state.setOrientation(PfxQuat(rotation));
  return state;
}

// A ball joint at the world origin between bodies a and b, with the joint frame `frame`
// (world) and Euler coordinates.
PfxJoint eulerJoint(const PfxRigidState& a, const PfxRigidState& b, const PfxMatrix3& frame) {
  PfxBallJointInitParam param;
  param.enableJointFrame = true;
  param.jointFrame = frame;
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeBallJoint(joint, a, b, param), PFX_OK);
  joint.m_rotation = kPfxJointRotationEulerYZX;
  return joint;
}

// A world with a small fixed sphere at the origin (body A) and a moving body B made from
// `init` with the given shape: the two ends of a joint.
void addPivotAndBody(PfxWorld& world, const PfxWorldParam& param, const PfxShape& shape,
                     const PfxBodyInit& init, PfxUInt32& idA, PfxUInt32& idB) {
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit pivot;
  pivot.mass = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.05f)), pivot, &idA), PFX_OK);
  ASSERT_EQ(pfxAddBody(world, shape, init, &idB), PFX_OK);
}

}  // namespace

TEST(JointEuler, CoordinatesAreTheAnglesOfTheThreeTurns) {
  const PfxMatrix3 frame = turn(0.4f, PfxVector3(1, 2, 3).normalized());
  const PfxMatrix3 turnA = turn(-0.7f, PfxVector3(0, 1, 1).normalized());
  const PfxRigidState a = stateAt(0, turnA, PfxVector3(0.3f, 0, 0));
  const PfxRigidState b0 = stateAt(1, PfxMatrix3::Identity(), PfxVector3(0, 0, -0.5f));
  const PfxJoint joint = eulerJoint(a, b0, frame);
  const PfxFloat angles[][3] = {{0.5f, -0.3f, 1.1f}, {-2.5f, 1.2f, -3.0f}, {0.01f, 0.02f, 0.03f}};
  for (const auto& q : angles) {
    // B turned about the joint point by frame * Ry Rz Rx * frame^T.
    const PfxMatrix3 relative = turn(q[0], PfxVector3::UnitY()) * turn(q[1], PfxVector3::UnitZ()) *
                                turn(q[2], PfxVector3::UnitX());
    const PfxMatrix3 worldTurn = frame * relative * frame.transpose();
    const PfxRigidState b = stateAt(1, worldTurn, worldTurn * b0.getPosition());
    PfxFloat coordinates[6];
    pfxCalcJointCoordinates(joint, a, b, coordinates);
    EXPECT_NEAR(coordinates[kPfxJointAxisSwing1], q[0], 2e-5);
    EXPECT_NEAR(coordinates[kPfxJointAxisSwing2], q[1], 2e-5);
    EXPECT_NEAR(coordinates[kPfxJointAxisTwist], q[2], 2e-5);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(coordinates[i], 0, 2e-6);
  }
}

TEST(JointEuler, RowsFollowTheRatesOfTheAngles) {
  // One step of a joint in a world sets its row directions; each dotted with the relative
  // angular velocity must give the rate of its angle, as a finite difference measures it.
  PfxWorld world;
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  PfxBodyInit init;  // B turns about its own centre, the joint's anchor: no linear coupling
  PfxUInt32 idA, idB;
  ASSERT_NO_FATAL_FAILURE(
      addPivotAndBody(world, param, pfxMakeShape(PfxBox(0.3f, 0.2f, 0.1f)), init, idA, idB));
  const PfxMatrix3 start = turn(0.6f, PfxVector3::UnitY()) * turn(-0.5f, PfxVector3::UnitZ()) *
                           turn(0.4f, PfxVector3::UnitX());
  PfxJoint joint =
      eulerJoint(world.getRigidState(idA), world.getRigidState(idB), PfxMatrix3::Identity());
  PfxRigidState b = world.getRigidState(idB);
  b.setOrientation(PfxQuat(start));
  const PfxVector3 w(0.3f, -0.8f, 0.5f);
  b.setAngularVelocity(w);
  ASSERT_EQ(world.setRigidState(idB, b), PFX_OK);
  PfxUInt32 jointId;
  ASSERT_EQ(world.addJoint(joint, &jointId), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  // The last set-up (in the position correction) saw B as it is now.
  const PfxJoint& stepped = world.getJoint(jointId);
  const PfxRigidState& a = world.getRigidState(idA);
  const PfxRigidState& now = world.getRigidState(idB);
  const PfxVector3 spin = now.getAngularVelocity();
  const PfxFloat h = 1e-3f;
  PfxRigidState later = now;
  later.setOrientation(
      PfxQuat(turn(h * spin.norm(), spin.normalized()) * now.getOrientation().toRotationMatrix()));
  PfxFloat c0[6], c1[6];
  pfxCalcJointCoordinates(stepped, a, now, c0);
  pfxCalcJointCoordinates(stepped, a, later, c1);
  for (const PfxUInt32 axis : {kPfxJointAxisTwist, kPfxJointAxisSwing1, kPfxJointAxisSwing2}) {
    EXPECT_NEAR(stepped.m_axes[axis].dot(spin), (c1[axis] - c0[axis]) / h, 2e-3) << "axis " << axis;
  }
}

TEST(JointEuler, LimitsOnEachAngleHoldWhenTheyActTogether) {
  // A rod hanging from a fixed body on a ball joint, thrown about, with a limit on each
  // angle: the angles reach their limits at once and stay within them.
  PfxWorld world;
  PfxWorldParam param;
  param.subStep = 2;
  PfxBodyInit init;
  init.mass = 2;
  init.position = PfxVector3(0, -0.5f, 0);
  init.angularVelocity = PfxVector3(4, 3, -5);
  PfxUInt32 idA, idB;
  ASSERT_NO_FATAL_FAILURE(
      addPivotAndBody(world, param, pfxMakeShape(PfxBox(0.05f, 0.4f, 0.05f)), init, idA, idB));
  PfxJoint joint =
      eulerJoint(world.getRigidState(idA), world.getRigidState(idB), PfxMatrix3::Identity());
  const PfxFloat lower[3] = {-0.15f, -0.3f, -0.1f}, upper[3] = {0.1f, 0.25f, 0.08f};
  for (PfxUInt32 i = 0; i < 3; ++i) {
    PfxJointConstraint& c = joint.m_constraints[kPfxJointAxisTwist + i];
    c.m_lock = kPfxJointLockLimit;
    c.m_movableLowerLimit = lower[i];
    c.m_movableUpperLimit = upper[i];
  }
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  PfxFloat worst = 0, reached[3] = {0, 0, 0};
  for (int step = 0; step < 240; ++step) {
    ASSERT_EQ(world.step(), PFX_OK);
    worst = std::max(worst, pfxGetJointLimitViolation(world.getJoint(0), world.getRigidState(idA),
                                                      world.getRigidState(idB)));
    PfxFloat coordinates[6];
    pfxCalcJointCoordinates(world.getJoint(0), world.getRigidState(idA), world.getRigidState(idB),
                            coordinates);
    for (int i = 0; i < 3; ++i) reached[i] = std::max(reached[i], std::abs(coordinates[3 + i]));
  }
  printf(
      "Euler limits under a thrown rod: worst violation %.4f rad; largest |twist|, |swing1|, "
      "|swing2| %.3f %.3f %.3f\n",
      worst, reached[0], reached[1], reached[2]);
  EXPECT_LT(worst, 0.01f);
  for (int i = 0; i < 3; ++i) EXPECT_GT(reached[i], 0.9f * std::min(-lower[i], upper[i]));
}

TEST(JointEuler, BadRotationValuesAreRejected) {
  const PfxRigidState a = stateAt(0, PfxMatrix3::Identity(), PfxVector3::Zero());
  const PfxRigidState b = stateAt(1, PfxMatrix3::Identity(), PfxVector3(0, -1, 0));
  PfxJoint joint = eulerJoint(a, b, PfxMatrix3::Identity());
  EXPECT_EQ(pfxCheckJoint(joint), PFX_OK);
  joint.m_rotation = kPfxJointRotationCount;
  EXPECT_EQ(pfxCheckJoint(joint), PFX_ERR_INVALID_FLAG);
  // A swing-twist joint's cone needs swing-twist coordinates.
  PfxSwingTwistJointInitParam cone;
  ASSERT_EQ(pfxInitializeSwingTwistJoint(joint, a, b, cone), PFX_OK);
  EXPECT_EQ(joint.m_rotation, kPfxJointRotationSwingTwist);
  joint.m_rotation = kPfxJointRotationEulerYZX;
  EXPECT_EQ(pfxCheckJoint(joint), PFX_ERR_INVALID_FLAG);
  PfxWorld world;
  PfxBodyInit init;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.1f)), init), PFX_OK);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.1f)), init), PFX_OK);
  EXPECT_EQ(world.addJoint(joint), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(world.getNumJoints(), 0u);
}
