// Effort drives (kPfxJointDriveEffort): a commanded torque or force along a joint axis,
// cut to the axis' force limit, acting on both bodies each sub-step. Known answers: a wheel
// of inertia I under torque tau turns up at tau / I, a slider of mass m under force F at
// F / m, two free bodies share the torque as action and reaction; the same holds for a
// joint the tree solver holds and for one closing a loop that is iterated. Bad efforts are
// refused with nothing changed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/low_level/pfx_error_detail.h"
#include "pfx/low_level/rigidbody/pfx_apply_joint_efforts.h"

using namespace pfx;

namespace {

constexpr PfxFloat kRadius = 0.2f;
constexpr PfxFloat kDt = PfxFloat(1) / 60;
constexpr int kStepsPerSecond = 60;
// The acceleration's relative error allowed after 1 s: the joints' position correction
// nudges the bodies a little each step, nothing else stands between the effort and the
// inertia. Measured: below 1e-5 in float (see the printed figures).
constexpr double kTolerance = 2e-3;

void initialize(PfxWorld& world, PfxUInt32 subSteps = 1) {
  PfxWorldParam param;
  param.timeStep = kDt;
  param.subStep = subSteps;
  param.gravity.setZero();
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
}

PfxUInt32 addBall(PfxWorld& world, const PfxVector3& position, PfxFloat mass) {
  PfxBodyInit init;
  init.mass = mass;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(kRadius)), init, &id), PFX_OK);
  return id;
}

PfxFloat inertiaZ(const PfxWorld& world, PfxUInt32 id) {
  return world.getRigidBody(id).getInertia()(2, 2);
}

PfxUInt32 addHinge(PfxWorld& world, PfxUInt32 a, PfxUInt32 b, const PfxVector3& anchor) {
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = anchor;
  hinge.axis = PfxVector3::UnitZ();
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(a), world.getRigidState(b), hinge),
            PFX_OK);
  PfxUInt32 id = 0;
  EXPECT_EQ(world.addJoint(joint, &id), PFX_OK);
  return id;
}

void addFixed(PfxWorld& world, PfxUInt32 a, PfxUInt32 b) {
  PfxFixedJointInitParam fixed;
  fixed.anchorPoint = world.getRigidState(b).getPosition();
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeFixedJoint(joint, world.getRigidState(a), world.getRigidState(b), fixed),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
}

PfxInt32 commandEffort(PfxWorld& world, PfxUInt32 jointId, PfxUInt32 axis, PfxFloat effort,
                       PfxFloat maxForce) {
  PfxJoint joint = world.getJoint(jointId);
  joint.m_constraints[axis].m_drive = kPfxJointDriveEffort;
  joint.m_constraints[axis].m_driveTarget = effort;
  joint.m_constraints[axis].m_driveMaxForce = maxForce;
  return world.setJoint(jointId, joint);
}

void stepOneSecond(PfxWorld& world) {
  for (int i = 0; i < kStepsPerSecond; ++i) ASSERT_EQ(world.step(), PFX_OK);
}

// A wheel (a ball) on a hinge about Z to a fixed body.
struct Wheel {
  PfxUInt32 base, wheel, hinge;
};

Wheel addWheel(PfxWorld& world) {
  Wheel w;
  w.base = addBall(world, PfxVector3::Zero(), 0);
  w.wheel = addBall(world, PfxVector3(0, 0, 1), 2);
  w.hinge = addHinge(world, w.base, w.wheel, PfxVector3(0, 0, 1));
  return w;
}

// The wheel's spin after 1 s from rest under the effort.
double wheelSpin(PfxFloat effort, PfxFloat maxForce, PfxUInt32 subSteps, PfxFloat* inertia) {
  PfxWorld world;
  initialize(world, subSteps);
  const Wheel w = addWheel(world);
  EXPECT_EQ(commandEffort(world, w.hinge, kPfxJointAxisTwist, effort, maxForce), PFX_OK);
  stepOneSecond(world);
  *inertia = inertiaZ(world, w.wheel);
  return double(world.getRigidState(w.wheel).getAngularVelocity().z());
}

}  // namespace

TEST(JointEffort, WheelTurnsUpAtTorqueOverInertia) {
  for (const PfxUInt32 subSteps : {1u, 4u}) {
    SCOPED_TRACE(subSteps);
    PfxFloat inertia = 0;
    const PfxFloat torque = 0.064f;
    const double spin = wheelSpin(torque, 10, subSteps, &inertia);
    const double expected = double(torque) / double(inertia);  // rad/s after 1 s
    std::printf("wheel, %u sub-steps: %.6f rad/s after 1 s, tau / I = %.6f (error %.2e)\n",
                subSteps, spin, expected, std::abs(spin / expected - 1));
    EXPECT_NEAR(spin, expected, kTolerance * expected);
  }
}

TEST(JointEffort, EffortIsCutToTheForceLimitBothWays) {
  PfxFloat inertia = 0;
  const PfxFloat limit = 0.032f;
  const double up = wheelSpin(0.5f, limit, 1, &inertia);
  const double down = wheelSpin(-0.5f, limit, 1, &inertia);
  const double expected = double(limit) / double(inertia);
  EXPECT_NEAR(up, expected, kTolerance * expected);
  EXPECT_NEAR(down, -expected, kTolerance * expected);
  // A limit of 0 lets nothing through.
  EXPECT_EQ(wheelSpin(0.5f, 0, 1, &inertia), 0);
}

TEST(JointEffort, SliderAcceleratesAtForceOverMass) {
  PfxWorld world;
  initialize(world);
  const PfxUInt32 base = addBall(world, PfxVector3::Zero(), 0);
  const PfxFloat mass = 3;
  const PfxUInt32 slider = addBall(world, PfxVector3(0, 0, 1), mass);
  PfxSliderJointInitParam param;
  param.anchorPoint = PfxVector3(0, 0, 1);
  param.direction = PfxVector3::UnitX();
  param.lowerDistance = -5;
  param.upperDistance = 5;
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeSliderJoint(joint, world.getRigidState(base),
                                     world.getRigidState(slider), param),
            PFX_OK);
  PfxUInt32 jointId = 0;
  ASSERT_EQ(world.addJoint(joint, &jointId), PFX_OK);
  const PfxFloat force = 6;
  ASSERT_EQ(commandEffort(world, jointId, kPfxJointAxisX, force, 100), PFX_OK);
  stepOneSecond(world);
  const PfxRigidState& state = world.getRigidState(slider);
  const double expected = double(force / mass);  // m/s after 1 s
  std::printf("slider: %.6f m/s after 1 s, F / m = %.6f\n",
              double(state.getLinearVelocity().x()), expected);
  EXPECT_NEAR(state.getLinearVelocity().x(), expected, kTolerance * expected);
  EXPECT_NEAR(state.getLinearVelocity().y(), 0, 1e-4);
  EXPECT_NEAR(state.getPosition().z(), 1, 1e-4);
  EXPECT_NEAR(state.getAngularVelocity().norm(), 0, 1e-4);
}

// Two free bodies, nothing fixed: B turns one way, A the other, each at tau over its own
// inertia, and the total angular momentum stays zero.
TEST(JointEffort, TwoFreeBodiesShareTheTorqueAsActionAndReaction) {
  PfxWorld world;
  initialize(world);
  const PfxUInt32 a = addBall(world, PfxVector3::Zero(), 4);
  const PfxUInt32 b = addBall(world, PfxVector3::Zero(), 2);
  const PfxUInt32 hinge = addHinge(world, a, b, PfxVector3::Zero());
  const PfxFloat torque = 0.064f;
  ASSERT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, torque, 10), PFX_OK);
  stepOneSecond(world);
  const double spinA = world.getRigidState(a).getAngularVelocity().z();
  const double spinB = world.getRigidState(b).getAngularVelocity().z();
  const double expectedA = -double(torque / inertiaZ(world, a));
  const double expectedB = double(torque / inertiaZ(world, b));
  EXPECT_NEAR(spinA, expectedA, kTolerance * std::abs(expectedA));
  EXPECT_NEAR(spinB, expectedB, kTolerance * expectedB);
  const double momentum = inertiaZ(world, a) * spinA + inertiaZ(world, b) * spinB;
  EXPECT_NEAR(momentum, 0, 1e-4 * double(torque));
}

// A wheel on an axle held by two hinges: one of them closes a loop, which the tree solver
// leaves to iteration. The effort acts the same on either.
TEST(JointEffort, ActsTheSameOnATreeJointAndOnOneClosingALoop) {
  for (const int commanded : {0, 1}) {
    SCOPED_TRACE(commanded);
    PfxWorld world;
    initialize(world);
    const PfxUInt32 base = addBall(world, PfxVector3::Zero(), 0);
    const PfxUInt32 wheel = addBall(world, PfxVector3(0, 0, 1), 2);
    const PfxUInt32 hinges[2] = {addHinge(world, base, wheel, PfxVector3(0, 0, 0.9f)),
                                 addHinge(world, base, wheel, PfxVector3(0, 0, 1.1f))};
    const PfxFloat torque = 0.064f;
    ASSERT_EQ(commandEffort(world, hinges[commanded], kPfxJointAxisTwist, torque, 10), PFX_OK);
    stepOneSecond(world);
    const double expected = double(torque / inertiaZ(world, wheel));
    EXPECT_NEAR(world.getRigidState(wheel).getAngularVelocity().z(), expected,
                kTolerance * expected);
  }
}

// A hinge in the middle of a chain of fixed joints, all solved directly as one tree: the
// effort between the second and third balls turns the last three about the pivot, with
// their inertia about it, I = sum of (I_ball + m d^2). Within 1 %: the solver adds the
// geometric stiffness of the loaded fixed joints to the bodies' inertia (measured: the
// spin 0.4 % above tau / I).
TEST(JointEffort, TurnsTheWholeSubtreeBeyondATreeJoint) {
  PfxWorld world;
  initialize(world);
  const PfxUInt32 base = addBall(world, PfxVector3::Zero(), 0);
  PfxUInt32 ids[5];
  const PfxFloat spacing = 0.5f, mass = 1;
  for (int i = 0; i < 5; ++i) ids[i] = addBall(world, PfxVector3(spacing * PfxFloat(i), 0, 0), mass);
  const PfxVector3 pivot(spacing, 0, 0);
  ASSERT_NO_FATAL_FAILURE(addFixed(world, base, ids[0]));
  ASSERT_NO_FATAL_FAILURE(addFixed(world, ids[0], ids[1]));
  const PfxUInt32 hinge = addHinge(world, ids[1], ids[2], pivot);
  ASSERT_NO_FATAL_FAILURE(addFixed(world, ids[2], ids[3]));
  ASSERT_NO_FATAL_FAILURE(addFixed(world, ids[3], ids[4]));
  double inertia = 0;
  for (int i = 2; i < 5; ++i) {
    const double d = double(spacing) * (i - 1);
    inertia += double(inertiaZ(world, ids[i])) + double(mass) * d * d;
  }
  const PfxFloat torque = 0.35f;
  ASSERT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, torque, 10), PFX_OK);
  // A short push, so that the spin stays small and the arm's turn does not matter.
  for (int i = 0; i < 6; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const double expected = double(torque) / inertia * 6 * double(kDt);
  const double spin = world.getRigidState(ids[4]).getAngularVelocity().z();
  std::printf("chain: %.6f rad/s after 0.1 s, tau / I t = %.6f\n", spin, expected);
  EXPECT_NEAR(spin, expected, 0.01 * expected);
  EXPECT_NEAR(world.getRigidState(ids[1]).getAngularVelocity().norm(), 0, 1e-4 * expected);
}

TEST(JointEffort, NonFiniteOrNegativeEffortsAreRefusedWithNothingChanged) {
  PfxWorld world;
  initialize(world);
  const PfxUInt32 hinge = addWheel(world).hinge;
  ASSERT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, 0.1f, 1), PFX_OK);
  const PfxJoint before = world.getJoint(hinge);
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  const PfxFloat inf = std::numeric_limits<PfxFloat>::infinity();
  EXPECT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, nan, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, inf, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, -inf, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, 0.1f, inf), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(commandEffort(world, hinge, kPfxJointAxisTwist, 0.1f, -1), PFX_ERR_INVALID_VALUE);
  PfxJoint unknownDrive = before;
  unknownDrive.m_constraints[kPfxJointAxisTwist].m_drive = kPfxJointDriveEffort + 1;
  EXPECT_EQ(world.setJoint(hinge, unknownDrive), PFX_ERR_INVALID_FLAG);
  const PfxJoint& after = world.getJoint(hinge);
  EXPECT_EQ(after.m_constraints[kPfxJointAxisTwist].m_drive, kPfxJointDriveEffort);
  EXPECT_EQ(after.m_constraints[kPfxJointAxisTwist].m_driveTarget, 0.1f);
  EXPECT_EQ(after.m_constraints[kPfxJointAxisTwist].m_driveMaxForce, 1);
}

// The stage itself, for callers of the low-level pipeline: every joint is checked before
// any state is touched.
TEST(JointEffort, StageRefusesBadJointsBeforeTouchingAnyState) {
  PfxWorld world;
  initialize(world);
  const auto [base, wheel, hinge] = addWheel(world);
  std::vector<PfxJoint> joints = {world.getJoint(hinge), world.getJoint(hinge)};
  for (PfxJoint& joint : joints) {
    joint.m_constraints[kPfxJointAxisTwist].m_drive = kPfxJointDriveEffort;
    joint.m_constraints[kPfxJointAxisTwist].m_driveTarget = 1;
    joint.m_constraints[kPfxJointAxisTwist].m_driveMaxForce = 1;
  }
  std::vector<PfxRigidState> states(world.getRigidStates(),
                                    world.getRigidStates() + world.getNumRigidBodies());
  std::vector<PfxRigidBody> bodies = {world.getRigidBody(base), world.getRigidBody(wheel)};
  const std::vector<PfxRigidState> original = states;
  PfxApplyJointEffortsParam param;
  param.joints = joints.data();
  param.numJoints = 2;
  param.states = states.data();
  param.bodies = bodies.data();
  param.numRigidBodies = 2;
  param.timeStep = kDt;
  const auto unchanged = [&] {
    return std::memcmp(states.data(), original.data(), sizeof(PfxRigidState) * states.size()) == 0;
  };

  joints[1].m_constraints[kPfxJointAxisTwist].m_driveTarget =
      std::numeric_limits<PfxFloat>::quiet_NaN();
  EXPECT_EQ(pfxApplyJointEfforts(param), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find("joints[1]"), std::string::npos)
      << pfxGetLastErrorDetail();
  EXPECT_TRUE(unchanged());
  joints[1].m_constraints[kPfxJointAxisTwist].m_driveTarget = 1;

  joints[1].m_rigidBodyIdB = 7;
  EXPECT_EQ(pfxApplyJointEfforts(param), PFX_ERR_OUT_OF_RANGE);
  EXPECT_TRUE(unchanged());
  joints[1].m_rigidBodyIdB = wheel;

  param.timeStep = 0;
  EXPECT_EQ(pfxApplyJointEfforts(param), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(unchanged());
  param.timeStep = kDt;
  param.states = nullptr;
  EXPECT_EQ(pfxApplyJointEfforts(param), PFX_ERR_NULL_POINTER);
  param.states = states.data();

  // Both joints push the wheel: twice the effort, over one step.
  ASSERT_EQ(pfxApplyJointEfforts(param), PFX_OK);
  const double expected = 2 * double(kDt) / double(inertiaZ(world, wheel));
  EXPECT_NEAR(states[wheel].getAngularVelocity().z(), expected, 1e-5 * expected);
  EXPECT_EQ(states[base].getAngularVelocity().norm(), 0);  // fixed: forces do not move it
}
