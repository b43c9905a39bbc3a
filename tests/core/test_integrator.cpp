// The integrator and the external-force stage on single bodies, without contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "pfx/base_level/collision/pfx_mass_properties.h"
#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"
#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"

using namespace pfx;

namespace {

PfxRigidBody makeBody(PfxFloat mass, const PfxMatrix3& inertia) {
  PfxRigidBody body;
  body.reset();
  body.setMass(mass);
  body.setInertia(inertia);
  return body;
}

PfxVector3 angularMomentum(const PfxRigidState& s, const PfxRigidBody& b) {
  const PfxMatrix3 r = s.getOrientation().toRotationMatrix();
  return pfxRotateInertia(r, b.getInertia()) * s.getAngularVelocity();
}

PfxFloat rotationalEnergy(const PfxRigidState& s, const PfxRigidBody& b) {
  return PfxFloat(0.5) * s.getAngularVelocity().dot(angularMomentum(s, b));
}

}  // namespace

// Body-frame angular velocity by Euler's equations, integrated with classical RK4 at a
// tiny step: the reference the integrator's tumbling is compared with.
PfxVector3 eulerEquations(const PfxVector3& w, const PfxVector3& inertia) {
  return PfxVector3((inertia[1] - inertia[2]) * w[1] * w[2] / inertia[0],
                    (inertia[2] - inertia[0]) * w[2] * w[0] / inertia[1],
                    (inertia[0] - inertia[1]) * w[0] * w[1] / inertia[2]);
}

std::vector<double> referenceFlipTimes(PfxVector3 w, const PfxVector3& inertia, double seconds) {
  std::vector<double> flips;
  const PfxFloat h = 1e-4f;
  const int steps = static_cast<int>(seconds / h);
  for (int i = 0; i < steps; ++i) {
    const PfxVector3 k1 = eulerEquations(w, inertia);
    const PfxVector3 k2 = eulerEquations(w + 0.5f * h * k1, inertia);
    const PfxVector3 k3 = eulerEquations(w + 0.5f * h * k2, inertia);
    const PfxVector3 k4 = eulerEquations(w + h * k3, inertia);
    const PfxVector3 next = w + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
    if ((next[1] >= 0) != (w[1] >= 0)) flips.push_back((i + 1) * double(h));
    w = next;
  }
  return flips;
}

// A 1 x 0.5 x 0.25 m box spun about its intermediate (Y) axis with a slight disturbance:
// the Dzhanibekov instability turns it over and back again, while the angular momentum
// stays fixed in space. With Ix < Iy < Iz the disturbance grows at
// w sqrt((Iy-Ix)(Iz-Iy)/(Ix Iz)) ~ 6 /s, so the first flip comes after about a second.
TEST(Integrator, IntermediateAxisSpinKeepsAngularMomentumAndFlips) {
  const PfxFloat mass = 1;
  const PfxRigidBody body = makeBody(mass, pfxCalcInertiaBox(PfxVector3(0.5f, 0.25f, 0.125f), mass));
  const PfxVector3 w0(0.02f, 10.0f, 0);
  PfxRigidState state;
  state.reset();
  state.setAngularVelocity(w0);

  const PfxVector3 l0 = angularMomentum(state, body);
  const PfxFloat e0 = rotationalEnergy(state, body);
  const PfxFloat dt = 1.0f / 60.0f;
  std::vector<double> flips;
  PfxFloat previousY = w0.y();
  PfxFloat maxEnergyDrift = 0;
  for (int i = 0; i < 600; ++i) {
    pfxIntegrate(state, body, dt);
    const PfxFloat bodyY = (state.getOrientation().conjugate() * state.getAngularVelocity()).y();
    if ((bodyY >= 0) != (previousY >= 0)) flips.push_back((i + 1) * dt);
    previousY = bodyY;
    maxEnergyDrift =
        std::max(maxEnergyDrift, std::abs(rotationalEnergy(state, body) - e0) / e0);
  }
  const std::vector<double> expected = referenceFlipTimes(w0, body.getInertia().diagonal(), 10);
  const PfxVector3 l1 = angularMomentum(state, body);
  const PfxFloat magnitudeDrift = std::abs(l1.norm() - l0.norm()) / l0.norm();
  const PfxFloat directionDrift = (l1 - l0).norm() / l0.norm();
  std::printf("spinner 10 s at 1/60: |L| drift %.2e, L drift %.2e, max energy drift %.2e\n",
              magnitudeDrift, directionDrift, maxEnergyDrift);
  std::printf("flips at");
  for (double t : flips) std::printf(" %.3f", t);
  std::printf(" s; reference");
  for (double t : expected) std::printf(" %.3f", t);
  std::printf(" s\n");
  EXPECT_LT(magnitudeDrift, 1e-3f);
  EXPECT_LT(directionDrift, 1e-3f);
  EXPECT_LT(maxEnergyDrift, 0.01f);
  ASSERT_GE(expected.size(), 2u);
  ASSERT_EQ(flips.size(), expected.size());
  // The first flip comes when the disturbance has grown, at the same time as the reference.
  EXPECT_NEAR(flips[0], expected[0], 0.05 * expected[0]);
}

// |L| of a principal-axes body in double, from the state with the carries pfxIntegrate
// keeps (what its rounding left out), so that the measure sees the error the steps piled
// up, not the one rounding of the state to float that any single step makes.
double momentumMagnitude(const PfxRigidState& s, const PfxRigidBody& b) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(s.getOrientation().coeffs().cast<double>() +
                                                  s.getOrientationCarry().coeffs().cast<double>())
                                   .normalized();
  const Eigen::Vector3d omega =
      s.getAngularVelocity().cast<double>() + s.getAngularVelocityCarry().cast<double>();
  return b.getInertia().cast<double>().diagonal().cwiseProduct(q.conjugate() * omega).norm();
}

// The largest relative change of |L| over 10 s of the benchmark's spinner, checked every
// 1/60 s, on average over four starting spins 1e-4 rad/s apart: round-off is a walk, and
// one spin's figure alone says little about a trend.
double spinnerMomentumDrift(PfxFloat timeStep) {
  const PfxRigidBody body = makeBody(1, pfxCalcInertiaBox(PfxVector3(0.5f, 0.25f, 0.125f), 1));
  const int stepsPerCheck = static_cast<int>(std::lround(1 / (60 * timeStep)));
  constexpr int kSpins = 4;
  double sum = 0;
  for (int spin = 0; spin < kSpins; ++spin) {
    PfxRigidState state;
    state.reset();
    state.setAngularVelocity(PfxVector3(0.02f + 1e-4f * spin, 10.0f, 0));
    const double l0 = momentumMagnitude(state, body);
    double drift = 0;
    for (int i = 1; i <= 600 * stepsPerCheck; ++i) {
      pfxIntegrate(state, body, timeStep);
      if (i % stepsPerCheck == 0) {
        drift = std::max(drift, std::abs(momentumMagnitude(state, body) - l0) / l0);
      }
    }
    sum += drift;
  }
  return sum / kSpins;
}

// The spinner of the benchmark (a box tumbling about its intermediate axis at 10 rad/s,
// flipping every 1.5 s) for 10 s at steps of 1/240, 1/960 and 1/3840 s. Each step's sums
// of orientation and velocity rounded afresh, and the drift grew with the number of
// steps: in float, 4.9e-6 at 1/240 and 1.1e-5 at 1/3840 (pfx_bench). With the carries of
// pfxIntegrate only the round-off of each step's change is left, which follows the angle
// turned, not the steps taken: the drift is flat, about 2e-7 at every step here, and a
// smaller step may exceed a larger one's by no more than the quarter that separates the
// three today (1.7e-7, 1.9e-7, 1.8e-7).
TEST(Integrator, MomentumDriftDoesNotGrowAsTheStepShrinks) {
  const double coarse = spinnerMomentumDrift(PfxFloat(1) / 240);
  const double middle = spinnerMomentumDrift(PfxFloat(1) / 960);
  const double fine = spinnerMomentumDrift(PfxFloat(1) / 3840);
  std::printf("spinner 10 s, largest |L| drift: %.2e at 1/240, %.2e at 1/960, %.2e at 1/3840\n",
              coarse, middle, fine);
  EXPECT_LE(middle, 1.25 * coarse);
  EXPECT_LE(fine, 1.25 * coarse);
  EXPECT_LT(coarse, 1e-6);
}

// Spinning exactly about a principal axis is an equilibrium: nothing changes but the angle.
TEST(Integrator, SpinAboutMajorAxisIsSteady) {
  const PfxRigidBody body = makeBody(2, pfxCalcInertiaBox(PfxVector3(0.5f, 0.25f, 0.125f), 2));
  PfxRigidState state;
  state.reset();
  state.setAngularVelocity(PfxVector3(0, 0, 3));
  for (int i = 0; i < 60; ++i) pfxIntegrate(state, body, 1.0f / 60.0f);
  EXPECT_NEAR(state.getAngularVelocity().z(), 3, 1e-5);
  EXPECT_NEAR(state.getAngularVelocity().head<2>().norm(), 0, 1e-5);
  // 3 rad in one second about Z.
  const PfxQuat expected(Eigen::AngleAxis<PfxFloat>(3, PfxVector3::UnitZ()));
  EXPECT_NEAR(std::abs(state.getOrientation().dot(expected)), 1, 1e-5);
}

// A body with a non-diagonal inertia (a rotated box) keeps its momentum too.
TEST(Integrator, RotatedInertiaKeepsAngularMomentum) {
  const PfxMatrix3 r = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.7f, PfxVector3(1, 2, 3).normalized()))
                           .toRotationMatrix();
  const PfxRigidBody body =
      makeBody(1, pfxRotateInertia(r, pfxCalcInertiaBox(PfxVector3(0.5f, 0.25f, 0.125f), 1)));
  PfxRigidState state;
  state.reset();
  state.setAngularVelocity(PfxVector3(1, -4, 2));
  const PfxVector3 l0 = angularMomentum(state, body);
  for (int i = 0; i < 600; ++i) pfxIntegrate(state, body, 1.0f / 60.0f);
  EXPECT_LT((angularMomentum(state, body) - l0).norm() / l0.norm(), 1e-3f);
}

TEST(Integrator, LinearMotionAndMotionTypes) {
  const PfxRigidBody body = makeBody(1, pfxCalcInertiaSphere(0.5f, 1));
  for (PfxMotionType type : {kPfxMotionTypeFixed, kPfxMotionTypeActive, kPfxMotionTypeKeyframe,
                             kPfxMotionTypeOneWay, kPfxMotionTypeTrigger}) {
    PfxRigidState state;
    state.reset();
    state.setMotionType(type);
    state.setLinearVelocity(PfxVector3(1, 2, 3));
    pfxIntegrate(state, body, 0.5f);
    const bool moves = type != kPfxMotionTypeFixed && type != kPfxMotionTypeTrigger;
    EXPECT_NEAR((state.getPosition() - (moves ? PfxVector3(0.5f, 1, 1.5f) : PfxVector3::Zero())).norm(),
                0, 1e-6)
        << int(type);
  }
  PfxRigidState sleeping;
  sleeping.reset();
  sleeping.setLinearVelocity(PfxVector3(1, 0, 0));
  sleeping.sleep();
  pfxIntegrate(sleeping, body, 1);
  EXPECT_EQ(sleeping.getPosition(), PfxVector3::Zero());
}

TEST(ApplyExternalForce, GravityForceAndTorque) {
  const PfxRigidBody body = makeBody(2, PfxMatrix3(PfxVector3(1, 2, 4).asDiagonal()));
  PfxRigidState state;
  state.reset();
  ASSERT_EQ(pfxApplyExternalForce(state, body, PfxVector3(4, 0, 0), PfxVector3(0, 0, 8),
                                  PfxVector3(0, -10, 0), 0.5f),
            PFX_OK);
  // v = (F/m + g) dt = (2, -10, 0) * 0.5; w = I^-1 T dt = (0, 0, 2) * 0.5.
  EXPECT_NEAR((state.getLinearVelocity() - PfxVector3(1, -5, 0)).norm(), 0, 1e-6);
  EXPECT_NEAR((state.getAngularVelocity() - PfxVector3(0, 0, 1)).norm(), 0, 1e-6);

  PfxRigidState fixed;
  fixed.reset();
  fixed.setMotionType(kPfxMotionTypeFixed);
  pfxApplyExternalForce(fixed, body, PfxVector3(4, 0, 0), PfxVector3::Zero(), PfxVector3(0, -10, 0), 1);
  EXPECT_EQ(fixed.getLinearVelocity(), PfxVector3::Zero());
}

TEST(ApplyExternalForce, RejectsBadInputAndChangesNothing) {
  PfxRigidBody bodies[2] = {makeBody(1, PfxMatrix3::Identity()), makeBody(1, PfxMatrix3::Identity())};
  PfxRigidState states[2];
  states[0].reset();
  states[1].reset();
  PfxRigidState before[2];
  std::memcpy(static_cast<void*>(before), states, sizeof(states));
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  PfxVector3 forces[2] = {PfxVector3::Zero(), PfxVector3(nan, 0, 0)};

  PfxApplyExternalForceParam param;
  param.states = states;
  param.bodies = bodies;
  param.numRigidBodies = 2;
  param.timeStep = 0.1f;
  param.forces = forces;
  EXPECT_EQ(pfxApplyExternalForce(param), PFX_ERR_INVALID_VALUE);
  param.forces = nullptr;
  param.timeStep = 0;
  EXPECT_EQ(pfxApplyExternalForce(param), PFX_ERR_INVALID_VALUE);
  param.timeStep = 0.1f;
  param.gravity = PfxVector3(0, std::numeric_limits<PfxFloat>::infinity(), 0);
  EXPECT_EQ(pfxApplyExternalForce(param), PFX_ERR_INVALID_VALUE);
  param.gravity = PfxVector3(0, -9.8f, 0);
  param.states = nullptr;
  EXPECT_EQ(pfxApplyExternalForce(param), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(std::memcmp(before, states, sizeof(states)), 0);

  PfxUpdateRigidStatesParam update;
  update.states = states;
  update.bodies = bodies;
  update.numRigidBodies = 2;
  update.timeStep = nan;
  EXPECT_EQ(pfxUpdateRigidStates(update), PFX_ERR_INVALID_VALUE);
  update.timeStep = 0.1f;
  update.bodies = nullptr;
  EXPECT_EQ(pfxUpdateRigidStates(update), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(std::memcmp(before, states, sizeof(states)), 0);
}
