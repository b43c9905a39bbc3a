// Joint damping: an axis whose damping fraction is 1 - exp(-c h / I) per step h (as the URDF
// loader sets it from a viscous coefficient c) loses its speed as exp(-c t / I), whatever
// the step, for a joint to a fixed body and for one inside a chain that the joint tree
// solves directly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"

using namespace pfx;

namespace {

constexpr PfxFloat kRadius = 0.05f;  // of the 1 kg balls that make every body

// The viscous coefficient per unit of the inertia it damps: the speed falls to exp(-0.5) =
// 0.607 of itself in 1 s.
constexpr double kDecayRate = 0.5;

PfxUInt32 addBall(PfxWorld& world, const PfxVector3& position, PfxFloat mass) {
  PfxBodyInit init;
  init.mass = mass;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(kRadius)), init, &id), PFX_OK);
  return id;
}

// The damping fraction for a step of `dt` from a viscous coefficient c = kDecayRate I, for
// whatever inertia (or mass) I the axis moves: the speed goes down as exp(-kDecayRate t).
PfxFloat fractionFor(double dt) { return PfxFloat(1 - std::exp(-kDecayRate * dt)); }

struct Run {
  PfxWorld world;
  PfxUInt32 moving = 0;  // the body whose speed is measured
};

void initialize(Run& run, PfxFloat dt) {
  PfxWorldParam param;
  param.timeStep = dt;
  param.gravity.setZero();
  param.enableSleep = false;  // the decay is measured, not granted
  ASSERT_EQ(run.world.initialize(param), PFX_OK);
}

void addJoint(PfxWorld& world, PfxJoint& joint) { ASSERT_EQ(world.addJoint(joint), PFX_OK); }

// Steps 1 s and returns the speed kept, as measured by `speed` of the moving body, which
// is asked before the first step and after each.
template <typename Speed>
double keptAfterOneSecond(Run& run, PfxFloat dt, Speed speed) {
  const double start = speed(run.world.getRigidState(run.moving));
  const int steps = static_cast<int>(std::lround(1 / double(dt)));
  double last = start;
  for (int i = 0; i < steps; ++i) {
    EXPECT_EQ(run.world.step(), PFX_OK);
    if (!run.world.getRigidState(run.moving).isValid()) return -1;
    last = speed(run.world.getRigidState(run.moving));
  }
  return last / start;
}

// A 1 kg ball on a 1 m arm (I = 1.001 kg m^2 about the hinge) turning at 1 rad/s about a
// damped hinge to a fixed body.
double hingeKept(PfxFloat dt) {
  Run run;
  initialize(run, dt);
  const PfxUInt32 base = addBall(run.world, PfxVector3::Zero(), 0);
  run.moving = addBall(run.world, PfxVector3(1, 0, 0), 1);
  PfxRigidState s = run.world.getRigidState(run.moving);
  s.setAngularVelocity(PfxVector3(0, 0, 1));
  s.setLinearVelocity(PfxVector3(0, 1, 0));
  EXPECT_EQ(run.world.setRigidState(run.moving, s), PFX_OK);
  PfxHingeJointInitParam hinge;
  hinge.axis = PfxVector3::UnitZ();
  hinge.damping = fractionFor(dt);
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeHingeJoint(joint, run.world.getRigidState(base),
                                    run.world.getRigidState(run.moving), hinge),
            PFX_OK);
  addJoint(run.world, joint);
  return keptAfterOneSecond(
      run, dt, [](const PfxRigidState& state) { return double(state.getAngularVelocity().z()); });
}

// A 1 kg ball sliding at 1 m/s along a damped slider to a fixed body.
double sliderKept(PfxFloat dt) {
  Run run;
  initialize(run, dt);
  const PfxUInt32 base = addBall(run.world, PfxVector3::Zero(), 0);
  run.moving = addBall(run.world, PfxVector3::Zero(), 1);
  PfxRigidState s = run.world.getRigidState(run.moving);
  s.setLinearVelocity(PfxVector3(1, 0, 0));
  EXPECT_EQ(run.world.setRigidState(run.moving, s), PFX_OK);
  PfxSliderJointInitParam slider;
  slider.direction = PfxVector3::UnitX();
  slider.lowerDistance = -5;
  slider.upperDistance = 5;
  slider.damping = fractionFor(dt);
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeSliderJoint(joint, run.world.getRigidState(base),
                                     run.world.getRigidState(run.moving), slider),
            PFX_OK);
  addJoint(run.world, joint);
  return keptAfterOneSecond(
      run, dt, [](const PfxRigidState& state) { return double(state.getLinearVelocity().x()); });
}

// The chain's hinge and what it turns: a viscous decay rate (per s, the coefficient per unit
// of the inertia it damps) and a friction torque (N m).
struct ChainHinge {
  double decayRate = kDecayRate;
  PfxFloat friction = 0;
};

// The inertia (kg m^2) the chain's hinge turns: the last three balls at 0.5, 1 and 1.5 m.
constexpr double kChainInertia = 0.25 + 1 + 2.25 + 3 * 0.4 * kRadius * kRadius;

// A chain of five balls 0.5 m apart along X: the first fixed to a fixed body, the second
// fixed to the first, a damped hinge about Z at the second, and the last three fixed to each
// other beyond it, turning at 1 rad/s. The hinge turns the last three (I = 0.25 + 1 + 2.25 m^2
// times 1 kg plus their own 0.001 each) against the first two, which the fixed joints hold to the
// ground: alone, the hinge's two bodies would answer its impulse with a ball's 0.001 kg m^2.
// `speeds`, if given, receives the hinge's speed at the start and after every step.
double chainKept(PfxFloat dt, const ChainHinge& hingeAxis = ChainHinge(),
                 std::vector<double>* speeds = nullptr) {
  Run run;
  initialize(run, dt);
  const PfxUInt32 base = addBall(run.world, PfxVector3::Zero(), 0);
  PfxUInt32 ids[5];
  for (int i = 0; i < 5; ++i) ids[i] = addBall(run.world, PfxVector3(0.5f * PfxFloat(i), 0, 0), 1);
  const PfxVector3 pivot(0.5f, 0, 0);
  const PfxFloat spin = 1;
  for (int i = 2; i < 5; ++i) {
    PfxRigidState s = run.world.getRigidState(ids[i]);
    s.setAngularVelocity(PfxVector3(0, 0, spin));
    s.setLinearVelocity(PfxVector3::UnitZ().cross(s.getPosition() - pivot) * spin);
    EXPECT_EQ(run.world.setRigidState(ids[i], s), PFX_OK);
  }
  const auto fix = [&](PfxUInt32 a, PfxUInt32 b) {
    PfxFixedJointInitParam fixed;
    fixed.anchorPoint = run.world.getRigidState(b).getPosition();
    PfxJoint joint;
    EXPECT_EQ(pfxInitializeFixedJoint(joint, run.world.getRigidState(a), run.world.getRigidState(b),
                                      fixed),
              PFX_OK);
    addJoint(run.world, joint);
  };
  fix(base, ids[0]);
  fix(ids[0], ids[1]);
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = pivot;
  hinge.axis = PfxVector3::UnitZ();
  hinge.damping = PfxFloat(1 - std::exp(-hingeAxis.decayRate * dt));
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeHingeJoint(joint, run.world.getRigidState(ids[1]),
                                    run.world.getRigidState(ids[2]), hinge),
            PFX_OK);
  joint.m_constraints[kPfxJointAxisTwist].m_friction = hingeAxis.friction;
  addJoint(run.world, joint);
  fix(ids[2], ids[3]);
  fix(ids[3], ids[4]);
  run.moving = ids[4];
  return keptAfterOneSecond(run, dt, [speeds](const PfxRigidState& state) {
    const double speed = state.getAngularVelocity().z();
    if (speeds) speeds->push_back(speed);
    return speed;
  });
}

// The speed kept after 1 s by an axis at 1 rad/s (1 m/s) that a viscous decay rate k and a
// friction deceleration a slow down: w' = -k w - a gives (1 + a / k) exp(-k) - a / k.
double keptWithFriction(double decayRate, double deceleration) {
  const double ratio = deceleration / decayRate;
  return (1 + ratio) * std::exp(-decayRate) - ratio;
}

}  // namespace

// The damping fraction is exact for the implicit step, so the speed kept after 1 s is
// exp(-0.5) = 0.6065 at every step. The tolerance, 1 % of it, is what the turning arm loses
// undamped at dt 1/60 (0.8 %, its joint's position correction pulling it back onto its
// circle every step; 0.05 % at 1/1000); the slider loses nothing. At dt 1/1000 the tree
// rows used to keep 0.999 of the arm's speed: their update, 0.5 mrad/s, was too small to
// measure the tree's response from, and the damping acted through the ball alone.
TEST(JointDamping, SpeedDecaysAsTheViscousCoefficientSaysAtEveryStep) {
  const double expected = std::exp(-kDecayRate);
  for (const int hz : {1000, 240, 60}) {
    const PfxFloat dt = PfxFloat(1) / PfxFloat(hz);
    SCOPED_TRACE(hz);
    const double hinge = hingeKept(dt);
    const double slider = sliderKept(dt);
    const double chain = chainKept(dt);
    std::printf(
        "dt 1/%d: speed kept after 1 s: hinge %.4f, slider %.4f, chain %.4f "
        "(exp(-0.5) = %.4f)\n",
        hz, hinge, slider, chain, expected);
    EXPECT_NEAR(hinge, expected, 0.01 * expected);
    EXPECT_NEAR(slider, expected, 0.01 * expected);
    EXPECT_NEAR(chain, expected, 0.01 * expected);
  }
}

// URDF joints usually have both: <dynamics damping friction>. Damping must act as it does
// alone, implicitly and with the inertia of the whole tree behind the joint, and friction
// only add its small torque: 0.02 N m on the chain's 3.5 kg m^2 takes 0.7 % more of the
// speed in 1 s. The tolerance is the damping-only test's, 1 % of the expected speed. The
// friction row used to add the damping as a share of its bound, sized by the hinge's two
// bodies (a ball's 0.001 kg m^2) and not by the tree (3.5 kg m^2): the chain kept nearly
// all its speed.
TEST(JointDamping, FrictionAddsItsTorqueToDampingInATree) {
  ChainHinge axis;
  axis.friction = PfxFloat(0.02);
  const double expected = keptWithFriction(kDecayRate, axis.friction / kChainInertia);
  for (const int hz : {30, 60, 240}) {
    const PfxFloat dt = PfxFloat(1) / PfxFloat(hz);
    SCOPED_TRACE(hz);
    const double dampedOnly = chainKept(dt);
    const double withFriction = chainKept(dt, axis);
    std::printf(
        "dt 1/%d: chain speed kept after 1 s: damping %.4f, damping and friction %.4f "
        "(expected %.4f and %.4f)\n",
        hz, dampedOnly, withFriction, std::exp(-kDecayRate), expected);
    EXPECT_NEAR(withFriction, expected, 0.01 * expected);
    // Friction only ever takes speed away.
    EXPECT_LT(withFriction, dampedOnly);
  }
}

// Heavy damping with friction stops the chain without reversing it: a decay rate of 100 / s
// removes 96 % of the speed in one step of 1/30 s, and an explicit update sized by the
// wrong inertia would overshoot through zero or keep the chain turning.
TEST(JointDamping, HeavyDampingWithFrictionStopsWithoutReversing) {
  ChainHinge axis;
  axis.decayRate = 100;
  axis.friction = PfxFloat(0.02);
  for (const int hz : {30, 60, 240}) {
    const PfxFloat dt = PfxFloat(1) / PfxFloat(hz);
    SCOPED_TRACE(hz);
    std::vector<double> speeds;
    const double kept = chainKept(dt, axis, &speeds);
    double lowest = 1;
    for (const double speed : speeds) lowest = std::min(lowest, speed);
    // 0.1 s in, the damping alone leaves exp(-10) = 4.5e-5 of the speed.
    const double atTenth = speeds[static_cast<std::size_t>(hz / 10)];
    std::printf("dt 1/%d: heavy damping: speed after 0.1 s %.3g, after 1 s %.3g, lowest %.3g\n",
                hz, atTenth, kept, lowest);
    EXPECT_LT(std::abs(atTenth), 1e-3);
    EXPECT_LT(std::abs(kept), 1e-3);
    EXPECT_GT(lowest, -1e-3);
  }
}
