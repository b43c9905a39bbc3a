// Joints: the seed's types move only along their free axes, a hinge pendulum keeps its
// period and energy, chains hold together, drives reach their targets within their force,
// and bad joints are rejected without changing anything.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"
#include "pfx_object_bytes.h"

using namespace pfx;

namespace {

constexpr PfxFloat kGravity = 9.80665f;

PfxUInt32 addFixed(PfxWorld& world, const PfxVector3& position) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.01f)), init, &id), PFX_OK);
  return id;
}

PfxUInt32 addBall(PfxWorld& world, const PfxVector3& position, PfxFloat mass = 1,
                  PfxFloat radius = 0.05f) {
  PfxBodyInit init;
  init.mass = mass;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(radius)), init, &id), PFX_OK);
  return id;
}

PfxFloat jointGap(const PfxWorld& world, const PfxJoint& j) {
  const PfxRigidState& a = world.getRigidState(j.m_rigidBodyIdA);
  const PfxRigidState& b = world.getRigidState(j.m_rigidBodyIdB);
  return ((a.getPosition() + a.getOrientation() * j.m_anchorA) -
          (b.getPosition() + b.getOrientation() * j.m_anchorB))
      .norm();
}

}  // namespace

TEST(Joints, InitializationRejectsBadInputAndLeavesTheJointAlone) {
  PfxRigidState a, b;
  a.reset();
  b.reset();
  a.setRigidBodyId(0);
  b.setRigidBodyId(1);
  b.setPosition(PfxVector3(1, 0, 0));
  PfxJoint joint;
  joint.reset();
  joint.m_rigidBodyIdA = 77;
  const std::vector<unsigned char> before = pfx_test::objectBytes(joint);
  auto unchanged = [&] { return pfx_test::sameBytes(before, joint); };

  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(std::numeric_limits<PfxFloat>::quiet_NaN(), 0, 0);
  EXPECT_EQ(pfxInitializeBallJoint(joint, a, b, ball), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(unchanged());
  ball.anchorPoint.setZero();
  EXPECT_EQ(pfxInitializeBallJoint(joint, a, a, ball), PFX_ERR_INVALID_VALUE);  // same body
  EXPECT_TRUE(unchanged());
  PfxHingeJointInitParam hinge;
  hinge.axis = PfxVector3::Zero();
  EXPECT_EQ(pfxInitializeHingeJoint(joint, a, b, hinge), PFX_ERR_INVALID_VALUE);
  hinge.axis = PfxVector3::UnitZ();
  hinge.lowerAngle = 0.5f;
  hinge.upperAngle = -0.5f;
  EXPECT_EQ(pfxInitializeHingeJoint(joint, a, b, hinge), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(unchanged());
  PfxSliderJointInitParam slider;
  slider.enableJointFrame = true;
  slider.jointFrame = PfxMatrix3::Constant(std::numeric_limits<PfxFloat>::quiet_NaN());
  EXPECT_EQ(pfxInitializeSliderJoint(joint, a, b, slider), PFX_ERR_INVALID_VALUE);
  PfxSwingTwistJointInitParam swing;
  swing.swingUpperAngle = -0.1f;
  EXPECT_EQ(pfxInitializeSwingTwistJoint(joint, a, b, swing), PFX_ERR_INVALID_VALUE);
  PfxFixedJointInitParam fixed;
  fixed.bias = 2;
  EXPECT_EQ(pfxInitializeFixedJoint(joint, a, b, fixed), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(unchanged());

  // The world rejects a joint naming a body it does not have, and keeps its joints.
  PfxWorld world;
  addFixed(world, PfxVector3::Zero());
  addBall(world, PfxVector3(1, 0, 0));
  ASSERT_EQ(pfxInitializeBallJoint(joint, a, b, ball), PFX_OK);
  PfxJoint stray = joint;
  stray.m_rigidBodyIdB = 5;
  EXPECT_EQ(world.addJoint(stray), PFX_ERR_OUT_OF_RANGE);
  stray = joint;
  stray.m_constraints[kPfxJointAxisTwist].m_lock = kPfxJointLockLimit;
  stray.m_constraints[kPfxJointAxisTwist].m_movableLowerLimit = 1;
  stray.m_constraints[kPfxJointAxisTwist].m_movableUpperLimit = -1;
  EXPECT_EQ(world.addJoint(stray), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumJoints(), 0u);
  EXPECT_EQ(world.addJoint(joint), PFX_OK);
  EXPECT_EQ(world.setJoint(0, stray), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getJoint(0).m_constraints[kPfxJointAxisTwist].m_lock, kPfxJointLockFree);
}

// A ball on a rigid arm swinging about a hinge: small-angle period 2 pi sqrt(I / (m g d)),
// with I the inertia about the hinge, and no energy lost over 10 s.
TEST(Joints, HingePendulumKeepsPeriodAndEnergy) {
  PfxWorldParam param;
  param.timeStep = 1.0f / 240.0f;
  // At 0.16 m/s through the bottom, slower than the sleep threshold everywhere else: with
  // sleep, the swing would stop at a turning point.
  param.enableSleep = false;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxFloat d = 1.0f, radius = 0.1f, mass = 2.0f;
  const PfxUInt32 pivot = addFixed(world, PfxVector3::Zero());
  const PfxFloat angle0 = 0.05f;
  const PfxUInt32 bob =
      addBall(world, PfxVector3(d * std::sin(angle0), -d * std::cos(angle0), 0), mass, radius);
  PfxHingeJointInitParam hinge;
  hinge.axis = PfxVector3::UnitZ();
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(pivot), world.getRigidState(bob),
                                    hinge),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);

  const PfxFloat inertia = 0.4f * mass * radius * radius + mass * d * d;
  const double expectedPeriod = 2 * PFX_PI * std::sqrt(inertia / (mass * kGravity * d));
  auto energy = [&] {
    const PfxRigidState& s = world.getRigidState(bob);
    const PfxRigidBody& b = world.getRigidBody(bob);
    return 0.5 * mass * s.getLinearVelocity().squaredNorm() +
           0.5 * s.getAngularVelocity().dot(b.getInertia() * s.getAngularVelocity()) +
           mass * kGravity * s.getPosition().y();
  };
  const double e0 = energy();
  const double swing = mass * kGravity * d * (1 - std::cos(angle0));  // energy in play
  std::vector<double> crossings;
  PfxFloat previousX = world.getRigidState(bob).getPosition().x();
  double worstEnergyLoss = 0;
  PfxFloat worstGap = 0;
  for (int i = 1; i <= 2400; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxFloat x = world.getRigidState(bob).getPosition().x();
    if ((x >= 0) != (previousX >= 0)) {
      crossings.push_back((i - 1 + previousX / (previousX - x)) * param.timeStep);
    }
    previousX = x;
    worstEnergyLoss = std::max(worstEnergyLoss, (e0 - energy()) / swing);
    worstGap = std::max(worstGap, jointGap(world, world.getJoint(0)));
  }
  ASSERT_GE(crossings.size(), 4u);
  const double period = 2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
  std::printf("hinge pendulum: period %.5f s, expected %.5f s; energy lost %.3f%%, gap %.2e m\n",
              period, expectedPeriod, 100 * worstEnergyLoss, worstGap);
  EXPECT_NEAR(period, expectedPeriod, 0.01 * expectedPeriod);
  EXPECT_LT(worstEnergyLoss, 0.02);
  EXPECT_LT(worstGap, 1e-4f);
  // The hinge keeps the bob in its plane.
  EXPECT_NEAR(world.getRigidState(bob).getPosition().z(), 0, 1e-5f);
}

// Body B, held to a fixed body A by each joint type, is pushed along each of the six axes
// in turn (no gravity): it moves only along the axes the type leaves free.
TEST(Joints, EachTypeMovesOnlyAlongItsFreeAxes) {
  enum Type { kBall, kSwingTwist, kHinge, kSlider, kFixed, kUniversal };
  const char* names[] = {"ball", "swing-twist", "hinge", "slider", "fixed", "universal"};
  // Free axes (x, y, z translations; rotations about x, y, z) of each type, joint axis X.
  const bool free[6][6] = {{0, 0, 0, 1, 1, 1}, {0, 0, 0, 1, 1, 1}, {0, 0, 0, 1, 0, 0},
                           {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 1, 1}};
  for (int type = 0; type < 6; ++type) {
    for (int axis = 0; axis < 6; ++axis) {
      PfxWorldParam param;
      param.gravity.setZero();
      PfxWorld world;
      ASSERT_EQ(world.initialize(param), PFX_OK);
      const PfxUInt32 a = addFixed(world, PfxVector3::Zero());
      const PfxUInt32 b = addBall(world, PfxVector3(0.3f, 0, 0), 1, 0.1f);
      const PfxRigidState& sa = world.getRigidState(a);
      const PfxRigidState& sb = world.getRigidState(b);
      const PfxVector3 anchor(0.3f, 0, 0);  // at B's centre, so pushes do not turn it
      PfxJoint joint;
      PfxInt32 err = PFX_OK;
      switch (type) {
        case kBall: { PfxBallJointInitParam p; p.anchorPoint = anchor; err = pfxInitializeBallJoint(joint, sa, sb, p); break; }
        case kSwingTwist: { PfxSwingTwistJointInitParam p; p.anchorPoint = anchor; p.twistAxis = PfxVector3::UnitX(); p.twistLowerAngle = -1; p.twistUpperAngle = 1; p.swingUpperAngle = 1; err = pfxInitializeSwingTwistJoint(joint, sa, sb, p); break; }
        case kHinge: { PfxHingeJointInitParam p; p.anchorPoint = anchor; p.axis = PfxVector3::UnitX(); p.lowerAngle = -1; p.upperAngle = 1; err = pfxInitializeHingeJoint(joint, sa, sb, p); break; }
        case kSlider: { PfxSliderJointInitParam p; p.anchorPoint = anchor; p.direction = PfxVector3::UnitX(); err = pfxInitializeSliderJoint(joint, sa, sb, p); break; }
        case kFixed: { PfxFixedJointInitParam p; p.anchorPoint = anchor; err = pfxInitializeFixedJoint(joint, sa, sb, p); break; }
        case kUniversal: { PfxUniversalJointInitParam p; p.anchorPoint = anchor; p.axis = PfxVector3::UnitX(); p.swing1LowerAngle = p.swing2LowerAngle = -1; p.swing1UpperAngle = p.swing2UpperAngle = 1; err = pfxInitializeUniversalJoint(joint, sa, sb, p); break; }
      }
      ASSERT_EQ(err, PFX_OK) << names[type];
      ASSERT_EQ(world.addJoint(joint), PFX_OK);
      // A push small enough to stay inside every limit within the test.
      const PfxVector3 direction = PfxVector3::Unit(axis % 3);
      for (int i = 0; i < 20; ++i) {
        world.applyForce(b, axis < 3 ? PfxVector3(direction * 2) : PfxVector3::Zero(),
                         axis < 3 ? PfxVector3::Zero() : PfxVector3(direction * 0.02f));
        ASSERT_EQ(world.step(), PFX_OK);
      }
      const PfxRigidState& s = world.getRigidState(b);
      const PfxFloat moved = (s.getPosition() - PfxVector3(0.3f, 0, 0)).dot(direction);
      const PfxFloat turned = (s.getOrientation().vec() * 2).dot(direction);
      const PfxFloat motion = axis < 3 ? moved : turned;
      if (free[type][axis]) {
        EXPECT_GT(std::abs(motion), 0.02f) << names[type] << " axis " << axis;
      } else {
        EXPECT_LT(std::abs(motion), 1e-3f) << names[type] << " axis " << axis;
      }
    }
  }
}

// Capsule chains hanging from a fixed point, released horizontally at dt = 1/60 with the
// default settings, with an end payload of 1, 10, 100 and 1000 link masses, and a chain of
// 100 links: the largest gap between the two anchors of any joint over 10 s, and bounded
// velocities. Under the sanitizers 3 s, the first swing down and back (10 s took 29 s under
// ASan), which runs every stage the later swings run; the largest gaps come later (100
// links: 6.8e-5 m over 10 s, 3.8e-6 m over 3 s), so the release and double builds, which
// swing them for 10 s, are where the bounds are held.
#if defined(PFX_TEST_SANITIZED)
constexpr int kChainSteps = 180;
#else
constexpr int kChainSteps = 600;
#endif

TEST(Joints, ChainsHoldUnderHeavyPayloads) {
  struct Case { int links; PfxFloat ratio; PfxFloat bound; };
  for (const Case& test : {Case{20, 1, 1e-3f}, Case{20, 10, 1e-3f}, Case{20, 100, 1e-3f},
                           Case{20, 1000, 5e-3f}, Case{100, 1, 5e-3f}}) {
    const int links = test.links;
    const PfxFloat ratio = test.ratio;
    PfxWorld world;
    ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    PfxUInt32 previous = addFixed(world, PfxVector3::Zero());
    const PfxFloat half = 0.1f;
    for (int i = 0; i <= links; ++i) {
      PfxBodyInit init;
      init.mass = i < links ? 1 : ratio;
      init.position = PfxVector3(half + 2 * half * i, 0, 0);
      PfxUInt32 id = 0;
      const PfxShape shape = i < links ? pfxMakeShape(PfxCapsule(half, 0.02f))
                                       : pfxMakeShape(PfxSphere(half));
      ASSERT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
      PfxBallJointInitParam p;
      p.anchorPoint = PfxVector3(2 * half * i, 0, 0);
      PfxJoint joint;
      ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(previous),
                                       world.getRigidState(id), p),
                PFX_OK);
      ASSERT_EQ(world.addJoint(joint), PFX_OK);
      previous = id;
    }
    PfxFloat worstGap = 0, fastest = 0;
    for (int step = 0; step < kChainSteps; ++step) {
      ASSERT_EQ(world.step(), PFX_OK);
      for (PfxUInt32 j = 0; j < world.getNumJoints(); ++j) {
        worstGap = std::max(worstGap, jointGap(world, world.getJoint(j)));
      }
      for (PfxUInt32 b = 0; b < world.getNumRigidBodies(); ++b) {
        fastest = std::max(fastest, world.getRigidState(b).getLinearVelocity().norm());
      }
    }
    const PfxFloat length = 2 * half * links + 2 * half;
    std::printf("%d-link chain 1:%.0f: largest gap %.2e m, fastest body %.2f m/s\n", links, ratio,
                worstGap, fastest);
    EXPECT_LT(worstGap, test.bound);
    // A whip's tip outruns a free fall from the chain's length, but not by orders of magnitude.
    EXPECT_LT(fastest, 10 * std::sqrt(2 * kGravity * length));
  }
}

TEST(Joints, DrivesReachTheirTargetsWithinTheirForce) {
  PfxWorldParam param;
  param.gravity.setZero();
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxUInt32 base = addFixed(world, PfxVector3::Zero());
  const PfxUInt32 wheel = addBall(world, PfxVector3::Zero(), 1, 0.2f);
  PfxHingeJointInitParam hinge;
  hinge.axis = PfxVector3::UnitZ();
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(base), world.getRigidState(wheel),
                                    hinge),
            PFX_OK);
  PfxJointConstraint& twist = joint.m_constraints[kPfxJointAxisTwist];
  twist.m_drive = kPfxJointDriveVelocity;
  twist.m_driveTarget = 3;
  twist.m_driveMaxForce = 0.01f;  // N m: the wheel's inertia 0.016 kg m^2 needs 5 s
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  // After 1 s at most 0.01 N m: w = 0.01 / 0.016 = 0.625 rad/s.
  const PfxFloat inertia = 0.4f * 1 * 0.2f * 0.2f;
  EXPECT_NEAR(world.getRigidState(wheel).getAngularVelocity().z(), 0.01f / inertia, 0.02f);
  EXPECT_NEAR(world.getJoint(0).getAppliedTorque(param.timeStep).z(), 0.01f, 1e-3f);
  for (int i = 0; i < 600; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getRigidState(wheel).getAngularVelocity().z(), 3, 1e-3f);

  // A position drive holds the wheel at 1 rad.
  joint = world.getJoint(0);
  joint.m_constraints[kPfxJointAxisTwist].m_drive = kPfxJointDrivePosition;
  joint.m_constraints[kPfxJointAxisTwist].m_driveTarget = 1;
  joint.m_constraints[kPfxJointAxisTwist].m_driveMaxForce = 100;
  ASSERT_EQ(world.setJoint(0, joint), PFX_OK);
  for (int i = 0; i < 120; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getJoint(0).m_constraints[kPfxJointAxisTwist].m_position, 1, 1e-2f);
  EXPECT_NEAR(world.getRigidState(wheel).getAngularVelocity().z(), 0, 1e-2f);
}

// A body hanging still from a fixed joint: the joint carries its weight.
TEST(Joints, ReportsTheForceItApplies) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 top = addFixed(world, PfxVector3::Zero());
  const PfxUInt32 load = addBall(world, PfxVector3(0, -0.5f, 0), 3);
  PfxFixedJointInitParam p;
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeFixedJoint(joint, world.getRigidState(top), world.getRigidState(load), p),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxVector3 force = world.getJoint(0).getAppliedForce(world.getParam().timeStep);
  EXPECT_NEAR(force.y(), 3 * kGravity, 0.01f * 3 * kGravity);
  EXPECT_NEAR(force.x(), 0, 1e-3f);
  EXPECT_LT(world.getRigidState(load).getLinearVelocity().norm(), 1e-4f);
}

// Seed 6_joint's ragdoll dropped from 2 m onto a box: no joint strays more than 2 degrees
// past its limits, the anchors stay together, and it comes to rest.
TEST(Joints, RagdollKeepsItsLimitsAndComesToRest) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 0.5f, 20)), ground), PFX_OK);
  PfxBodyInit box;
  box.mass = 0;
  box.position = PfxVector3(0, 0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(1.5f, 0.5f, 1.0f)), box), PFX_OK);
  PfxRagdoll doll;
  const PfxQuat tumble(Eigen::AngleAxis<PfxFloat>(0.5f, PfxVector3(1, 0, 0.4f).normalized()));
  ASSERT_EQ(pfxAddRagdoll(world, PfxVector3(0.2f, 1 + 2 + 1, 0), tumble, &doll), PFX_OK);
  PfxFloat violation = 0, gap = 0, lastSecond = 0;
  for (int i = 0; i < 600; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    for (PfxUInt32 j = 0; j < world.getNumJoints(); ++j) {
      const PfxJoint& joint = world.getJoint(j);
      violation = std::max(violation,
                           pfxGetJointLimitViolation(joint, world.getRigidState(joint.m_rigidBodyIdA),
                                                     world.getRigidState(joint.m_rigidBodyIdB)));
      gap = std::max(gap, jointGap(world, joint));
    }
    if (i >= 540) {
      for (PfxUInt32 b : doll.bodies) {
        lastSecond = std::max(lastSecond, world.getRigidState(b).getLinearVelocity().norm());
      }
    }
  }
  std::printf("ragdoll: largest limit excursion %.3f deg, gap %.2e m, last-second speed %.4f m/s\n",
              violation * 180 / PFX_PI, gap, lastSecond);
  EXPECT_LT(violation, 2 * PFX_PI / 180);
  EXPECT_LT(gap, 1e-3f);
  EXPECT_LT(lastSecond, 0.05f);
}

// The seed's contradicting constraints: a box held by a fixed joint where a wall overlaps
// it, and pushed into the wall. The two cannot both hold; what matters is that nothing
// explodes or turns NaN.
TEST(Joints, ContradictingJointAndContactStayBounded) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit wall;
  wall.mass = 0;
  wall.position = PfxVector3(0.5f, 1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.25f, 1, 1)), wall), PFX_OK);
  const PfxUInt32 post = addFixed(world, PfxVector3(-1, 1, 0));
  PfxBodyInit init;
  init.position = PfxVector3(0.1f, 1, 0);  // 15 cm into the wall
  PfxUInt32 box = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), init, &box), PFX_OK);
  PfxFixedJointInitParam p;
  p.anchorPoint = PfxVector3(-1, 1, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeFixedJoint(joint, world.getRigidState(post), world.getRigidState(box), p),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  PfxFloat fastest = 0;
  for (int i = 0; i < 600; ++i) {
    ASSERT_EQ(world.applyForce(box, PfxVector3(500, 0, 0), PfxVector3::Zero()), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxRigidState& s = world.getRigidState(box);
    ASSERT_TRUE(s.isValid()) << "step " << i;
    fastest = std::max(fastest, s.getLinearVelocity().norm());
  }
  std::printf("contradicting constraints: fastest %.3f m/s, box at x = %.3f\n", fastest,
              world.getRigidState(box).getPosition().x());
  EXPECT_LT(fastest, 1.0f);
  EXPECT_LT((world.getRigidState(box).getPosition() - init.position).norm(), 0.5f);
}

// The seed's damping removes its fraction of the relative velocity on a free axis each
// step; friction holds against a torque below it and gives way above it.
TEST(Joints, DampingAndFrictionResistMotion) {
  auto spinWheel = [](PfxFloat damping, PfxFloat friction, PfxFloat torque, PfxFloat spin) {
    PfxWorldParam param;
    param.gravity.setZero();
    param.enableSleep = false;  // the decay is measured down to 0.004 rad/s
    PfxWorld world;
    EXPECT_EQ(world.initialize(param), PFX_OK);
    const PfxUInt32 base = addFixed(world, PfxVector3::Zero());
    const PfxUInt32 wheel = addBall(world, PfxVector3::Zero(), 1, 0.2f);
    PfxRigidState s = world.getRigidState(wheel);
    s.setAngularVelocity(PfxVector3(0, 0, spin));
    EXPECT_EQ(world.setRigidState(wheel, s), PFX_OK);
    PfxHingeJointInitParam hinge;
    hinge.axis = PfxVector3::UnitZ();
    hinge.damping = damping;
    PfxJoint joint;
    EXPECT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(base), world.getRigidState(wheel),
                                      hinge),
              PFX_OK);
    joint.m_constraints[kPfxJointAxisTwist].m_friction = friction;
    EXPECT_EQ(world.addJoint(joint), PFX_OK);
    for (int i = 0; i < 60; ++i) {
      world.applyForce(wheel, PfxVector3::Zero(), PfxVector3(0, 0, torque));
      EXPECT_EQ(world.step(), PFX_OK);
    }
    return world.getRigidState(wheel).getAngularVelocity().z();
  };
  // Undamped and frictionless: the spin stays.
  EXPECT_NEAR(spinWheel(0, 0, 0, 2), 2, 1e-3f);
  // Damping 0.1 per step: 2 * 0.9^60.
  EXPECT_NEAR(spinWheel(0.1f, 0, 0, 2), 2 * std::pow(0.9f, 60.0f), 1e-3f);
  // Friction 0.05 N m holds against 0.04 N m and gives way to 0.1 N m: the wheel (inertia
  // 0.016 kg m^2) then gains (0.1 - 0.05) / 0.016 rad/s^2 for 1 s.
  EXPECT_NEAR(spinWheel(0, 0.05f, 0.04f, 0), 0, 1e-4f);
  EXPECT_NEAR(spinWheel(0, 0.05f, 0.1f, 0), 0.05f / 0.016f, 0.02f);
}

// A drive with no force limit asked for a position or a speed beyond the joint's limit:
// the limit wins. A chain of three arms on free hinges under gravity, the middle joint a
// limited hinge (or slider) driven past its limit each way while the outer arm swings on
// it; every step the driven joint stays within its limit and no joint of the chain opens.
// (Before, the drive, solved after the limit, won: 1.8 rad past the limit, joints 0.6 m
// apart.)
TEST(Joints, LimitsHoldAgainstDrivesWithoutForceLimit) {
  constexpr PfxFloat kUnlimited = std::numeric_limits<PfxFloat>::max();
  constexpr PfxFloat kLimit = 0.4f;
  struct Case {
    const char* name;
    bool slider;
    PfxJointDrive drive;
    PfxFloat target;
  };
  for (const Case& test : {Case{"hinge position +", false, kPfxJointDrivePosition, 1.5f},
                           Case{"hinge position -", false, kPfxJointDrivePosition, -2.5f},
                           Case{"hinge velocity", false, kPfxJointDriveVelocity, 20},
                           Case{"slider position +", true, kPfxJointDrivePosition, 1.2f},
                           Case{"slider position -", true, kPfxJointDrivePosition, -3},
                           Case{"slider velocity", true, kPfxJointDriveVelocity, -10}}) {
    SCOPED_TRACE(test.name);
    PfxWorldParam param;
    param.enableSleep = false;
    PfxWorld world;
    ASSERT_EQ(world.initialize(param), PFX_OK);
    // Base, then three arms of 0.3 m along X; the middle joint is the driven one.
    PfxUInt32 previous = addFixed(world, PfxVector3::Zero());
    constexpr int kLinks = 3;
    constexpr PfxUInt32 kDriven = 1;
    for (int i = 0; i < kLinks; ++i) {
      PfxBodyInit init;
      init.mass = 1;
      init.position = PfxVector3(0.15f + 0.3f * i, 0, 0);
      PfxUInt32 id = 0;
      ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.15f, 0.03f, 0.03f)), init, &id), PFX_OK);
      PfxJoint joint;
      if (test.slider && PfxUInt32(i) == kDriven) {
        PfxSliderJointInitParam p;
        p.anchorPoint = PfxVector3(0.3f * i, 0, 0);
        p.direction = PfxVector3::UnitY();
        p.lowerDistance = -kLimit;
        p.upperDistance = kLimit;
        ASSERT_EQ(pfxInitializeSliderJoint(joint, world.getRigidState(previous),
                                           world.getRigidState(id), p),
                  PFX_OK);
      } else {
        PfxHingeJointInitParam p;
        p.anchorPoint = PfxVector3(0.3f * i, 0, 0);
        p.axis = PfxVector3::UnitZ();
        if (PfxUInt32(i) == kDriven) {
          p.lowerAngle = -kLimit;
          p.upperAngle = kLimit;
        }
        ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(previous),
                                          world.getRigidState(id), p),
                  PFX_OK);
      }
      if (PfxUInt32(i) == kDriven) {
        PfxJointConstraint& axis =
            joint.m_constraints[test.slider ? kPfxJointAxisX : kPfxJointAxisTwist];
        axis.m_drive = test.drive;
        axis.m_driveTarget = test.target;
        axis.m_driveMaxForce = kUnlimited;
      }
      ASSERT_EQ(world.addJoint(joint), PFX_OK);
      previous = id;
    }
    const PfxUInt32 drivenAxis = test.slider ? kPfxJointAxisX : kPfxJointAxisTwist;
    PfxFloat excursion = 0, lockedError = 0, gap = 0, reached = 0;
    for (int step = 0; step < 180; ++step) {
      ASSERT_EQ(world.step(), PFX_OK);
      for (PfxUInt32 j = 0; j < world.getNumJoints(); ++j) {
        const PfxJoint& joint = world.getJoint(j);
        const PfxRigidState& a = world.getRigidState(joint.m_rigidBodyIdA);
        const PfxRigidState& b = world.getRigidState(joint.m_rigidBodyIdB);
        // Every axis: the locked ones' errors and the limit's excursion.
        lockedError = std::max(lockedError, pfxGetJointLimitViolation(joint, a, b));
        if (j == kDriven) {
          PfxFloat coordinates[6];
          pfxCalcJointCoordinates(joint, a, b, coordinates);
          excursion = std::max(excursion, std::abs(coordinates[drivenAxis]) - kLimit);
          reached = std::max(reached, std::abs(coordinates[drivenAxis]));
        } else {
          gap = std::max(gap, jointGap(world, joint));
        }
      }
    }
    std::printf("%s: limit excursion %.2e, largest locked-axis error %.2e, largest gap %.2e m, "
                "reached %.3f of %.3f\n",
                test.name, excursion, lockedError, gap, reached, kLimit);
    EXPECT_LT(excursion, 0.01f);
    // A slider driven without a force limit crosses its whole range in the first step; its
    // locked axes then lag by up to a centimetre for that one step.
    EXPECT_LT(lockedError, 0.015f);
    EXPECT_LT(gap, 1e-3f);
    // The drive did get the joint to its limit.
    EXPECT_GT(reached, kLimit - 0.01f);
    for (PfxUInt32 b = 0; b < world.getNumRigidBodies(); ++b) {
      EXPECT_TRUE(world.getRigidState(b).isValid());
    }
  }
}
