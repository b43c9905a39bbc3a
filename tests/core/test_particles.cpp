// The particle stages on their own (low_level/particle): known answers first (a pendulum's
// period, a hanging rope against the analytic catenary), then a rope carrying a payload a
// thousand times its own mass, then bad input, each rejected with a detail naming it and
// nothing changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "pfx/high_level/pfx_particle_group.h"
#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"
#include "pfx/low_level/particle/pfx_collide_particle_groups.h"
#include "pfx/low_level/particle/pfx_detect_particle_contacts.h"
#include "pfx/low_level/particle/pfx_integrate_particles.h"
#include "pfx/low_level/particle/pfx_refresh_particle_contacts.h"
#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"
#include "pfx/low_level/particle/pfx_update_particles.h"
#include "pfx/low_level/pfx_error_detail.h"

using namespace pfx;

namespace {

constexpr double kGravity = 9.80665;
constexpr double kPi = 3.14159265358979323846;

// The three sub-step stages over a builder's arrays, without bodies or contacts.
void stepParticles(PfxParticleGroupBuilder& b, PfxFloat timeStep, PfxUInt32 subSteps,
                   PfxUInt32 iterations, PfxFloat damping = 0) {
  const PfxFloat h = timeStep / PfxFloat(subSteps);
  const PfxUInt32 n = static_cast<PfxUInt32>(b.particles.size());
  for (PfxUInt32 s = 0; s < subSteps; ++s) {
    PfxIntegrateParticlesParam integrate;
    integrate.particles = b.particles.data();
    integrate.numParticles = n;
    integrate.linearDamping = damping;
    integrate.timeStep = h;
    ASSERT_EQ(pfxIntegrateParticles(integrate), PFX_OK) << pfxGetLastErrorDetail();
    PfxSolveParticleConstraintsParam solve;
    solve.particles = b.particles.data();
    solve.numParticles = n;
    solve.distanceConstraints = b.distanceConstraints.data();
    solve.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
    solve.angleConstraints = b.angleConstraints.data();
    solve.numAngleConstraints = static_cast<PfxUInt32>(b.angleConstraints.size());
    solve.tethers = b.tethers.data();
    solve.numTethers = static_cast<PfxUInt32>(b.tethers.size());
    solve.pins = b.pins.data();
    solve.numPins = static_cast<PfxUInt32>(b.pins.size());
    solve.timeStep = h;
    solve.iteration = iterations;
    ASSERT_EQ(pfxSolveParticleConstraints(solve), PFX_OK) << pfxGetLastErrorDetail();
    PfxUpdateParticlesParam update;
    update.particles = b.particles.data();
    update.numParticles = n;
    update.timeStep = h;
    ASSERT_EQ(pfxUpdateParticles(update), PFX_OK) << pfxGetLastErrorDetail();
  }
}

// Period of a pendulum of any amplitude: 2 pi sqrt(L / g) / AGM(1, cos(amplitude / 2)).
double exactPendulumPeriod(double length, double amplitude) {
  double a = 1, b = std::cos(amplitude / 2);
  for (int i = 0; i < 30; ++i) {
    const double mean = (a + b) / 2;
    b = std::sqrt(a * b);
    a = mean;
  }
  return 2 * kPi * std::sqrt(length / kGravity) / a;
}

double measurePendulumPeriod(PfxUInt32 subSteps, PfxFloat compliance) {
  const double length = 1, amplitude = 0.3;
  PfxParticleGroupBuilder b;
  PfxParticleGroupBuilder::Material m;
  m.particleMass = 1;
  m.stretchCompliance = compliance;
  b.addRope(PfxVector3::Zero(),
            PfxVector3(PfxFloat(length * std::sin(amplitude)), PfxFloat(-length * std::cos(amplitude)), 0),
            2, m);
  b.setMass(0, 0);
  const PfxFloat dt = PfxFloat(1) / 60;
  std::vector<double> upCrossings;
  double previousX = b.particles[1].m_position.x();
  for (int step = 0; step < 60 * 20; ++step) {
    stepParticles(b, dt, subSteps, 1);
    const double x = b.particles[1].m_position.x();
    if (previousX < 0 && x >= 0) {
      upCrossings.push_back((step + previousX / (previousX - x)) * dt);
    }
    previousX = x;
  }
  if (upCrossings.size() < 2) return 0;
  return (upCrossings.back() - upCrossings.front()) / double(upCrossings.size() - 1);
}

// The catenary through (-halfSpan, 0) and (halfSpan, 0) of the given length:
// y = c (cosh(x / c) - cosh(halfSpan / c)) with 2 c sinh(halfSpan / c) = length.
double catenaryParameter(double halfSpan, double length) {
  double lo = 1e-3, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double c = std::sqrt(lo * hi);
    (2 * c * std::sinh(halfSpan / c) > length ? lo : hi) = c;
  }
  return std::sqrt(lo * hi);
}

struct CatenaryRun {
  double maxError;         // m, largest distance of a particle to the curve
  double cpuSecondsPerSimulatedSecond;
};

CatenaryRun runCatenary(PfxUInt32 numParticles, PfxUInt32 subSteps, PfxUInt32 iterations,
                        bool tethers) {
  const double halfSpan = 0.8, length = 2.0;
  // Start as a V of the rope's length, the tip below the middle, and let it settle.
  const double drop = std::sqrt((length / 2) * (length / 2) - halfSpan * halfSpan);
  PfxParticleGroupBuilder b;
  PfxParticleGroupBuilder::Material m;
  m.particleMass = PfxFloat(0.01);
  const PfxUInt32 half = (numParticles - 1) / 2;
  b.addRope(PfxVector3(PfxFloat(-halfSpan), 0, 0), PfxVector3(0, PfxFloat(-drop), 0), half + 1, m);
  // Second leg: continue from the tip without repeating it.
  PfxParticleGroupBuilder leg;
  leg.addRope(PfxVector3(0, PfxFloat(-drop), 0), PfxVector3(PfxFloat(halfSpan), 0, 0), half + 1, m);
  for (PfxUInt32 i = 1; i < leg.particles.size(); ++i) b.particles.push_back(leg.particles[i]);
  for (const PfxParticleDistanceConstraint& c : leg.distanceConstraints) {
    PfxParticleDistanceConstraint shifted = c;
    shifted.m_particleA += half;
    shifted.m_particleB += half;
    b.distanceConstraints.push_back(shifted);
  }
  const PfxUInt32 last = static_cast<PfxUInt32>(b.particles.size() - 1);
  b.setMass(0, 0);
  b.setMass(last, 0);
  if (tethers) {
    b.tetherRope(0, last + 1, 0);
    b.tetherRope(0, last + 1, last);
  }
  const auto start = std::chrono::steady_clock::now();
  const double seconds = 20;
  const PfxFloat dt = PfxFloat(1) / 60;
  for (int step = 0; step < int(seconds * 60); ++step) {
    stepParticles(b, dt, subSteps, iterations, PfxFloat(1.0));
  }
  const double cpu = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double c = catenaryParameter(halfSpan, length);
  constexpr int kSamples = 20001;
  std::vector<PfxVector3> curve(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double x = -halfSpan + 2 * halfSpan * k / (kSamples - 1);
    curve[k] = PfxVector3(PfxFloat(x), PfxFloat(c * (std::cosh(x / c) - std::cosh(halfSpan / c))), 0);
  }
  double maxError = 0;
  for (const PfxParticle& p : b.particles) {
    double nearest = 1e9;
    for (const PfxVector3& q : curve) nearest = std::min(nearest, double((p.m_position - q).norm()));
    maxError = std::max(maxError, nearest);
  }
  return {maxError, cpu / seconds};
}

}  // namespace

TEST(Particles, PendulumKeepsItsPeriod) {
  const double expected = exactPendulumPeriod(1, 0.3);
  for (PfxUInt32 subSteps : {4u, 10u, 20u}) {
    const double period = measurePendulumPeriod(subSteps, 0);
    const double error = std::abs(period - expected) / expected;
    std::printf("particle pendulum, 1 m, amplitude 0.3 rad, dt 1/60, %2u sub-steps: period %.5f s, "
                "exact %.5f s, error %.3f%%\n",
                subSteps, period, expected, 100 * error);
    EXPECT_LT(error, 0.01) << subSteps << " sub-steps";
  }
}

TEST(Particles, SoftPendulumStretchesAsItsComplianceSays) {
  // A 1 kg bob hanging still on a distance constraint of compliance 1e-3 m/N stretches by
  // m g alpha = 9.8 mm, whatever the sub-step or iteration count.
  for (PfxUInt32 subSteps : {1u, 4u, 16u}) {
    for (PfxUInt32 iterations : {1u, 8u}) {
      PfxParticleGroupBuilder b;
      PfxParticleGroupBuilder::Material m;
      m.particleMass = 1;
      m.stretchCompliance = PfxFloat(1e-3);
      b.addRope(PfxVector3::Zero(), PfxVector3(0, -1, 0), 2, m);
      b.setMass(0, 0);
      for (int step = 0; step < 600; ++step) stepParticles(b, PfxFloat(1) / 60, subSteps, iterations, 2);
      const double stretch = -b.particles[1].m_position.y() - 1;
      EXPECT_NEAR(stretch, kGravity * 1e-3, 2e-4) << subSteps << " sub-steps, " << iterations
                                                  << " iterations";
    }
  }
}

TEST(Particles, WorldPinsHoldExactlyOrAsCompliantAsAsked) {
  // A 10-particle rope of 10 g particles hangs from a pin on its first particle (which has
  // a mass of its own): a rigid pin holds it where it was put; a pin of compliance 1e-3 m/N
  // gives way by the weight it carries times that compliance.
  for (const PfxFloat compliance : {PfxFloat(0), PfxFloat(1e-3)}) {
    PfxParticleGroupBuilder b;
    PfxParticleGroupBuilder::Material m;
    m.particleMass = PfxFloat(0.01);
    b.addRope(PfxVector3::Zero(), PfxVector3(0, -1, 0), 10, m);
    b.pinToWorld(0);
    b.pins[0].m_compliance = compliance;
    for (int step = 0; step < 600; ++step) stepParticles(b, PfxFloat(1) / 60, 10, 2, 2);
    const double sag = -b.particles[0].m_position.y();
    const double expected = compliance * 10 * 0.01 * kGravity;
    std::printf("world pin of compliance %g m/N under 0.98 N: gives %.4f mm, expected %.4f mm\n",
                double(compliance), 1000 * sag, 1000 * expected);
    EXPECT_NEAR(sag, expected, 1e-4 + 0.02 * expected);
  }
}

TEST(Particles, HangingRopeMatchesTheCatenary) {
  std::printf("catenary, rope 2 m between pins 1.6 m apart, 41 particles, 20 s settled:\n");
  std::printf("  tethers  sub-steps  iterations  max error (mm)  cpu ms per simulated s\n");
  struct Setting {
    PfxUInt32 subSteps, iterations;
    bool tethers;
    double bound;  // m
  };
  const Setting settings[] = {
      {1, 1, false, 1},      {1, 10, false, 0.2},    {4, 1, false, 0.15},  {4, 10, false, 0.015},
      {10, 1, false, 0.03},  {20, 1, false, 0.008},  {20, 5, false, 0.002}, {1, 10, true, 0.08},
      {4, 1, true, 0.06},    {20, 1, true, 0.006},
  };
  for (const Setting& s : settings) {
    const CatenaryRun run = runCatenary(41, s.subSteps, s.iterations, s.tethers);
    std::printf("  %-7s  %9u  %10u  %14.3f  %22.2f\n", s.tethers ? "yes" : "no", s.subSteps,
                s.iterations, 1000 * run.maxError, 1000 * run.cpuSecondsPerSimulatedSecond);
    EXPECT_LT(run.maxError, s.bound) << s.subSteps << " sub-steps, " << s.iterations
                                     << " iterations, tethers " << s.tethers;
  }
}

// A sub-step solved in calls of one iteration each, every call after the first going on from
// the multipliers of the one before (continueSubStep), is the same bits as one call of as
// many iterations: what PfxWorld relies on to solve the contacts between two groups between
// the iterations. Starting each call afresh is not the same solve.
TEST(Particles, ASubStepSolvedOneIterationPerCallIsTheSameBits) {
  PfxParticleGroupBuilder start;
  PfxParticleGroupBuilder::Material m;
  m.stretchCompliance = PfxFloat(1e-3);
  m.bendCompliance = PfxFloat(0.5);
  start.addRope(PfxVector3::Zero(), PfxVector3(1, -0.2, 0), 12, m);
  start.pinToWorld(0);
  start.pins[0].m_compliance = PfxFloat(1e-4);
  const auto solveSubStep = [&](PfxParticleGroupBuilder& b, PfxUInt32 calls, PfxUInt32 iterations,
                                bool goOn) {
    PfxIntegrateParticlesParam integrate;
    integrate.particles = b.particles.data();
    integrate.numParticles = static_cast<PfxUInt32>(b.particles.size());
    integrate.timeStep = PfxFloat(1) / 60;
    ASSERT_EQ(pfxIntegrateParticles(integrate), PFX_OK);
    for (PfxUInt32 call = 0; call < calls; ++call) {
      PfxSolveParticleConstraintsParam solve;
      solve.particles = b.particles.data();
      solve.numParticles = integrate.numParticles;
      solve.distanceConstraints = b.distanceConstraints.data();
      solve.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
      solve.angleConstraints = b.angleConstraints.data();
      solve.numAngleConstraints = static_cast<PfxUInt32>(b.angleConstraints.size());
      solve.pins = b.pins.data();
      solve.numPins = static_cast<PfxUInt32>(b.pins.size());
      solve.timeStep = integrate.timeStep;
      solve.iteration = iterations;
      solve.continueSubStep = goOn && call > 0;
      ASSERT_EQ(pfxSolveParticleConstraints(solve), PFX_OK) << pfxGetLastErrorDetail();
    }
  };
  PfxParticleGroupBuilder once = start, split = start, afresh = start;
  solveSubStep(once, 1, 8, false);
  solveSubStep(split, 8, 1, true);
  solveSubStep(afresh, 8, 1, false);
  ASSERT_EQ(once.particles.size(), split.particles.size());
  for (std::size_t i = 0; i < once.particles.size(); ++i) {
    EXPECT_EQ(once.particles[i].m_position, split.particles[i].m_position) << "particle " << i;
  }
  for (std::size_t i = 0; i < once.distanceConstraints.size(); ++i) {
    EXPECT_EQ(once.distanceConstraints[i].m_lambda, split.distanceConstraints[i].m_lambda);
  }
  PfxFloat apart = 0;
  for (std::size_t i = 0; i < once.particles.size(); ++i) {
    apart = std::max(apart, (once.particles[i].m_position - afresh.particles[i].m_position).norm());
  }
  EXPECT_GT(apart, 0) << "the multipliers carried over make no difference here";
}

// The refresh places each body's shape once for the contacts that follow with the same one;
// contacts alternating between bodies get the planes they get refreshed alone.
TEST(Particles, RefreshedContactsAlternatingBetweenBodiesMatchEachRefreshedAlone) {
  PfxRigidState states[3];
  PfxCollidable collidables[3];
  for (PfxRigidState& s : states) s.reset();
  for (PfxCollidable& c : collidables) c.reset();
  PfxShape ball, box, capsule;
  ball.reset();
  ball.setSphere(PfxSphere(1));
  box.reset();
  box.setBox(PfxBox(0.5, 0.3, 0.4));
  capsule.reset();
  capsule.setCapsule(PfxCapsule(0.6, 0.2));
  capsule.setOffsetPosition(PfxVector3(0, 0, 2));
  capsule.setOffsetOrientation(PfxQuat(Eigen::AngleAxis<PfxFloat>(PfxFloat(0.7), PfxVector3::UnitY())));
  collidables[0].addShape(ball);
  collidables[0].finish();
  collidables[1].addShape(box);
  collidables[1].finish();
  collidables[2].addShape(capsule);
  collidables[2].finish();
  const PfxQuat tilt(Eigen::AngleAxis<PfxFloat>(PfxFloat(0.4), PfxVector3(1, 1, 0).normalized()));
  for (PfxUInt32 i = 1; i < 3; ++i) {
    states[i].setPosition(PfxVector3(4, 1, 0));
    states[i].setOrientation(tilt);
  }
  const PfxVector3 capsuleCentre = states[2].getPosition() + tilt * PfxVector3(0, 0, 2);
  const PfxVector3 places[] = {PfxVector3(0, 1.1, 0),
                               states[1].getPosition() + tilt * PfxVector3(0.1, 0.45, 0),
                               capsuleCentre + PfxVector3(0, 0.35, 0),
                               capsuleCentre + PfxVector3(0.1, -0.3, 0.1),
                               PfxVector3(0.1, -1.15, 0),
                               PfxVector3(9, 9, 9)};
  const PfxUInt32 bodies[] = {0, 1, 2, 2, 0, 1};
  std::vector<PfxParticle> particles(6);
  std::vector<PfxParticleContact> contacts(6);
  for (PfxUInt32 i = 0; i < 6; ++i) {
    particles[i].m_position = particles[i].m_previousPosition = places[i];
    particles[i].m_radius = PfxFloat(0.1);
    contacts[i].m_particle = i;
    contacts[i].m_other = bodies[i];
    contacts[i].m_localNormal = PfxVector3::UnitX();
  }
  PfxRefreshParticleContactsParam refresh;
  refresh.particles = particles.data();
  refresh.numParticles = 6;
  refresh.offsetRigidStates = states;
  refresh.offsetCollidables = collidables;
  refresh.numRigidBodies = 3;
  std::vector<PfxParticleContact> alone = contacts;
  refresh.contacts = contacts.data();
  refresh.numContacts = 6;
  ASSERT_EQ(pfxRefreshParticleContacts(refresh), PFX_OK) << pfxGetLastErrorDetail();
  for (PfxUInt32 i = 0; i < 6; ++i) {
    refresh.contacts = &alone[i];
    refresh.numContacts = 1;
    ASSERT_EQ(pfxRefreshParticleContacts(refresh), PFX_OK);
    EXPECT_EQ(contacts[i].m_localPoint, alone[i].m_localPoint) << "contact " << i;
    EXPECT_EQ(contacts[i].m_localNormal, alone[i].m_localNormal) << "contact " << i;
  }
  // The first on the ball's top: its normal up; the last, far from the box: out of reach.
  EXPECT_NEAR(contacts[0].m_localNormal.y(), 1, 1e-5);
  EXPECT_NEAR(contacts[4].m_localNormal.y(), -1, 0.1);
  EXPECT_EQ(contacts[5].m_localNormal, PfxVector3::Zero());
  for (PfxUInt32 i = 1; i < 4; ++i) EXPECT_NEAR(contacts[i].m_localNormal.norm(), 1, 1e-5);
}

TEST(Particles, RopeCarriesAThousandTimesItsMassWithinOnePercent) {
  // 1 m, 21 particles of 1 g (the top one pinned), and at the end a payload of 1,000 times
  // the 20 g that hang: 20 kg, released with the rope horizontal, so that it swings through
  // the bottom at three times its weight.
  for (bool tethers : {true, false}) {
    PfxParticleGroupBuilder b;
    PfxParticleGroupBuilder::Material m;
    m.particleMass = PfxFloat(0.001);
    b.addRope(PfxVector3::Zero(), PfxVector3(1, 0, 0), 21, m);
    b.setMass(0, 0);
    b.setMass(20, 20);
    // Tethered from both ends: the payload weighs 20,000 times a particle, so it anchors the
    // rope's lower end as the pin anchors the upper one.
    if (tethers) {
      b.tetherRope(0, 21, 0);
      b.tetherRope(0, 21, 20);
    }
    double worstStretch = 0, worstPayloadStretch = 0;
    bool finite = true;
    for (int step = 0; step < 60 * 10; ++step) {
      stepParticles(b, PfxFloat(1) / 60, 4, 2);
      double length = 0;
      for (PfxUInt32 i = 0; i < 20; ++i) {
        length += (b.particles[i + 1].m_position - b.particles[i].m_position).norm();
      }
      for (const PfxParticle& p : b.particles) finite = finite && pfxIsFinite(p.m_position);
      worstStretch = std::max(worstStretch, length - 1);
      worstPayloadStretch = std::max(worstPayloadStretch, double(b.particles[20].m_position.norm()) - 1);
    }
    std::printf("rope 1 m of 1 g particles, 20 kg payload, dt 1/60, 4 sub-steps x 2 iterations, "
                "tethers %s: largest stretch along the rope %.3f%%, of the payload's distance "
                "to the pin %.3f%%\n",
                tethers ? "on" : "off", 100 * worstStretch, 100 * worstPayloadStretch);
    EXPECT_TRUE(finite);
    if (tethers) {
      EXPECT_LT(worstStretch, 0.01);
      EXPECT_LT(worstPayloadStretch, 0.01);
    }
  }
}

TEST(Particles, BendingStiffensAHair) {
  // A strand pinned at its root by its first two particles, held out sideways: without
  // angle constraints it hangs down, with stiff ones its tip stays near the horizontal.
  auto tipDrop = [](PfxFloat bendCompliance) {
    PfxParticleGroupBuilder b;
    PfxParticleGroupBuilder::Material m;
    m.particleMass = PfxFloat(0.001);
    m.bendCompliance = bendCompliance;
    b.addRope(PfxVector3::Zero(), PfxVector3(PfxFloat(0.2), 0, 0), 11, m);
    b.setMass(0, 0);
    b.setMass(1, 0);
    for (int step = 0; step < 300; ++step) stepParticles(b, PfxFloat(1) / 60, 10, 1, 2);
    return -double(b.particles[10].m_position.y());
  };
  const double limp = tipDrop(-1);
  const double stiff = tipDrop(PfxFloat(1e-4));
  std::printf("hair strand 0.2 m: tip drop %.4f m limp, %.4f m with bending compliance 1e-4\n",
              limp, stiff);
  EXPECT_GT(limp, 0.15);
  EXPECT_LT(stiff, limp / 3);
}

// Bad input: each rejected with a detail naming what was wrong, and nothing changed.
class ParticleBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    PfxParticleGroupBuilder::Material m;
    b.addRope(PfxVector3::Zero(), PfxVector3(1, 0, 0), 5, m);
    b.pinToWorld(0);
  }
  PfxSolveParticleConstraintsParam solveParam() {
    PfxSolveParticleConstraintsParam p;
    p.particles = b.particles.data();
    p.numParticles = static_cast<PfxUInt32>(b.particles.size());
    p.distanceConstraints = b.distanceConstraints.data();
    p.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
    p.pins = b.pins.data();
    p.numPins = static_cast<PfxUInt32>(b.pins.size());
    return p;
  }
  void expectUnchanged(const std::vector<PfxParticle>& before) {
    ASSERT_EQ(before.size(), b.particles.size());
    EXPECT_EQ(std::memcmp(before.data(), b.particles.data(), before.size() * sizeof(PfxParticle)), 0);
  }
  PfxParticleGroupBuilder b;
};

TEST_F(ParticleBadInput, NanNegativeRadiusAndNegativeMassAreRejected) {
  struct Case {
    void (*spoil)(PfxParticle&);
    const char* named;
  };
  const Case cases[] = {
      {[](PfxParticle& p) { p.m_position.y() = std::nanf(""); }, "particles[2]: position is not finite"},
      {[](PfxParticle& p) { p.m_velocity.x() = INFINITY; }, "particles[2]: velocity is not finite"},
      {[](PfxParticle& p) { p.m_radius = -1; }, "particles[2]: radius is not positive"},
      {[](PfxParticle& p) { p.m_massInv = -1; }, "particles[2]: inverse mass is negative"},
      {[](PfxParticle& p) { p.m_friction = std::nanf(""); }, "particles[2]: friction"},
  };
  for (const Case& c : cases) {
    b = PfxParticleGroupBuilder();
    SetUp();
    c.spoil(b.particles[2]);
    const std::vector<PfxParticle> before = b.particles;
    PfxIntegrateParticlesParam integrate;
    integrate.particles = b.particles.data();
    integrate.numParticles = static_cast<PfxUInt32>(b.particles.size());
    EXPECT_EQ(pfxIntegrateParticles(integrate), PFX_ERR_INVALID_VALUE);
    EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), c.named), nullptr) << pfxGetLastErrorDetail();
    EXPECT_EQ(pfxSolveParticleConstraints(solveParam()), PFX_ERR_INVALID_VALUE);
    EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), c.named), nullptr) << pfxGetLastErrorDetail();
    expectUnchanged(before);
  }
}

TEST_F(ParticleBadInput, ConstraintsNamingMissingParticlesAreRejected) {
  b.distanceConstraints[1].m_particleB = 7;
  const std::vector<PfxParticle> before = b.particles;
  const std::vector<PfxParticleDistanceConstraint> constraintsBefore = b.distanceConstraints;
  EXPECT_EQ(pfxSolveParticleConstraints(solveParam()), PFX_ERR_OUT_OF_RANGE);
  EXPECT_STREQ(pfxGetLastErrorDetail(),
               "pfxSolveParticleConstraints: PfxSolveParticleConstraintsParam::"
               "distanceConstraints[1].particleB is 7, but numParticles is 5");
  expectUnchanged(before);
  EXPECT_EQ(std::memcmp(constraintsBefore.data(), b.distanceConstraints.data(),
                        constraintsBefore.size() * sizeof(PfxParticleDistanceConstraint)),
            0);

  b.distanceConstraints[1].m_particleB = 2;
  b.distanceConstraints[3].m_compliance = -1;
  EXPECT_EQ(pfxSolveParticleConstraints(solveParam()), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "distanceConstraints[3].compliance is -1"), nullptr)
      << pfxGetLastErrorDetail();
  b.distanceConstraints[3].m_compliance = 0;

  b.pins[0].m_rigidBodyId = 3;
  EXPECT_EQ(pfxSolveParticleConstraints(solveParam()), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "pins[0].rigid body id is 3, but numRigidBodies is 0"),
            nullptr)
      << pfxGetLastErrorDetail();
  b.pins[0].m_rigidBodyId = PFX_PARTICLE_PIN_WORLD;

  PfxParticleAngleConstraint angle;
  angle.m_particleA = 0;
  angle.m_particleB = 1;
  angle.m_particleC = 9;
  b.angleConstraints.push_back(angle);
  PfxSolveParticleConstraintsParam param = solveParam();
  param.angleConstraints = b.angleConstraints.data();
  param.numAngleConstraints = 1;
  EXPECT_EQ(pfxSolveParticleConstraints(param), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "angleConstraints[0].particleC is 9"), nullptr)
      << pfxGetLastErrorDetail();
  expectUnchanged(before);
}

TEST_F(ParticleBadInput, TooSmallBuffersAreRejected) {
  const PfxUInt32 n = static_cast<PfxUInt32>(b.particles.size());
  std::vector<PfxVector4> work(pfxGetWorkBytesOfDetectParticleContacts(n) / sizeof(PfxVector4) + 1);
  std::vector<PfxParticleContact> contacts(8);
  PfxDetectParticleContactsParam param;
  param.workBuff = work.data();
  param.workBytes = pfxGetWorkBytesOfDetectParticleContacts(n) - 16;
  param.particles = b.particles.data();
  param.numParticles = n;
  param.contacts = contacts.data();
  param.maxContacts = 8;
  PfxDetectParticleContactsResult result;
  result.numContacts = 77;
  EXPECT_EQ(pfxDetectParticleContacts(param, result), PFX_ERR_OUT_OF_BUFFER);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "workBytes"), nullptr) << pfxGetLastErrorDetail();
  EXPECT_EQ(result.numContacts, 77u);

  param.workBytes = pfxGetWorkBytesOfDetectParticleContacts(n);
  param.contacts = nullptr;
  EXPECT_EQ(pfxDetectParticleContacts(param, result), PFX_ERR_NULL_POINTER);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "contacts is null, but maxContacts is 8"), nullptr)
      << pfxGetLastErrorDetail();
  EXPECT_EQ(result.numContacts, 77u);

  // The right sizes work, and the rope's touching neighbours are found.
  param.contacts = contacts.data();
  for (PfxParticle& p : b.particles) p.m_radius = PfxFloat(0.2);
  EXPECT_EQ(pfxDetectParticleContacts(param, result), PFX_OK) << pfxGetLastErrorDetail();
  EXPECT_EQ(result.numContacts, 4u);
  EXPECT_FALSE(result.truncated);

  param.maxContacts = 2;
  EXPECT_EQ(pfxDetectParticleContacts(param, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 2u);
  EXPECT_TRUE(result.truncated);
}

TEST_F(ParticleBadInput, ContactsNamingMissingBodiesOrShapesAreRejected) {
  PfxParticleContact contact;
  contact.m_particle = 1;
  contact.m_other = 0;
  contact.m_localNormal = PfxVector3::UnitY();
  contact.m_lambdaNormal = 1;
  const std::vector<PfxParticle> before = b.particles;

  // Velocities after a solve need the bodies the contacts name.
  PfxUpdateParticlesParam update;
  update.particles = b.particles.data();
  update.numParticles = static_cast<PfxUInt32>(b.particles.size());
  update.contacts = &contact;
  update.numContacts = 1;
  EXPECT_EQ(pfxUpdateParticles(update), PFX_ERR_NULL_POINTER);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "offsetRigidStates is null"), nullptr)
      << pfxGetLastErrorDetail();

  // A refresh of a contact with body 0 of no bodies, then with shape 3 of a body of one.
  PfxRigidState state;
  state.reset();
  PfxCollidable collidable;
  collidable.reset();
  PfxShape sphere;
  sphere.reset();
  sphere.setSphere(PfxSphere(1));
  collidable.addShape(sphere);
  collidable.finish();
  PfxRefreshParticleContactsParam refresh;
  refresh.particles = b.particles.data();
  refresh.numParticles = static_cast<PfxUInt32>(b.particles.size());
  refresh.contacts = &contact;
  refresh.numContacts = 1;
  EXPECT_EQ(pfxRefreshParticleContacts(refresh), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "names rigid body 0, but numRigidBodies is 0"),
            nullptr)
      << pfxGetLastErrorDetail();
  refresh.offsetRigidStates = &state;
  refresh.offsetCollidables = &collidable;
  refresh.numRigidBodies = 1;
  contact.m_shapeId = 3;
  const PfxParticleContact contactBefore = contact;
  EXPECT_EQ(pfxRefreshParticleContacts(refresh), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "names shape 3 of rigid body 0, which has 1"),
            nullptr)
      << pfxGetLastErrorDetail();
  EXPECT_EQ(contact.m_localNormal, contactBefore.m_localNormal);
  EXPECT_EQ(contact.m_localPoint, contactBefore.m_localPoint);
  expectUnchanged(before);
}

namespace {

struct Batched {
  std::vector<PfxUInt32> distanceOrder, angleOrder, distanceChainStart, angleChainStart;
  PfxParticleConstraintBatches distance, angle;
  std::vector<PfxVector4> work;
};

PfxInt32 batchBuilder(const PfxParticleGroupBuilder& b, Batched& out, PfxUInt32 numParticles) {
  out.distanceOrder.assign(b.distanceConstraints.size(), 0);
  out.angleOrder.assign(b.angleConstraints.size(), 0);
  out.distanceChainStart.assign(b.distanceConstraints.size() + 1, 0);
  out.angleChainStart.assign(b.angleConstraints.size() + 1, 0);
  out.distance.order = out.distanceOrder.data();
  out.angle.order = out.angleOrder.data();
  out.distance.chainStart = out.distanceChainStart.data();
  out.angle.chainStart = out.angleChainStart.data();
  const PfxUInt32 bytes = pfxGetWorkBytesOfBatchParticleConstraints(
      numParticles, static_cast<PfxUInt32>(
                        std::max(b.distanceConstraints.size(), b.angleConstraints.size())));
  out.work.resize(bytes / sizeof(PfxVector4) + 1);
  PfxBatchParticleConstraintsParam param;
  param.workBuff = out.work.data();
  param.workBytes = bytes;
  param.numParticles = numParticles;
  param.distanceConstraints = b.distanceConstraints.data();
  param.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
  param.angleConstraints = b.angleConstraints.data();
  param.numAngleConstraints = static_cast<PfxUInt32>(b.angleConstraints.size());
  param.distanceBatches = &out.distance;
  param.angleBatches = &out.angle;
  return pfxBatchParticleConstraints(param);
}

}  // namespace

// Chains and phases of a cloth with bending and a hair: each constraint once, each chain a
// run of constraints that start where the one before ended, no particle in two chains of a
// phase; the solve takes them and refuses batches made for other constraints.
TEST(Particles, BatchesNameEachConstraintOnceAndNoParticleTwiceInAPhase) {
  PfxParticleGroupBuilder b;
  PfxParticleGroupBuilder::Material material;
  material.bendCompliance = PfxFloat(0.1);
  const PfxUInt32 nu = 12, nv = 9;
  b.addCloth(PfxVector3::Zero(), PfxVector3(1, 0, 0), PfxVector3(0, 0, 1), nu, nv, material);
  b.addRope(PfxVector3(0, 1, 0), PfxVector3(1, 1, 0), 30, material);
  const PfxUInt32 n = static_cast<PfxUInt32>(b.particles.size());
  ASSERT_GT(b.angleConstraints.size(), 0u);
  Batched batched;
  ASSERT_EQ(batchBuilder(b, batched, n), PFX_OK) << pfxGetLastErrorDetail();
  // The cloth's rows, columns, lines of either diagonal, and for bending the even and the
  // odd particles of each row and column; the rope's links one more chain. Its angles, a
  // lone chain, are taken one by one.
  EXPECT_EQ(batched.distance.numChains, nv + nu + 2 * (nu + nv - 3) + 2 * (nv + nu) + 1);
  EXPECT_EQ(batched.angle.numChains, b.angleConstraints.size());
  const auto checkPhases = [&](const PfxParticleConstraintBatches& batches, PfxUInt32 count,
                               auto particlesOf) {
    ASSERT_EQ(batches.numConstraints, count);
    EXPECT_GE(batches.numPhases, 1u);
    EXPECT_EQ(batches.phaseStart[batches.numPhases], batches.numChains) << "nothing left over";
    EXPECT_EQ(batches.chainStart[batches.numChains], count);
    std::vector<int> seen(count, 0);
    for (PfxUInt32 phase = 0; phase < batches.numPhases; ++phase) {
      std::vector<PfxUInt32> chainOf(n, ~0u);
      for (PfxUInt32 chain = batches.phaseStart[phase]; chain < batches.phaseStart[phase + 1];
           ++chain) {
        for (PfxUInt32 k = batches.chainStart[chain]; k < batches.chainStart[chain + 1]; ++k) {
          ++seen[batches.order[k]];
          const std::vector<PfxUInt32> members = particlesOf(batches.order[k]);
          if (k > batches.chainStart[chain]) {
            EXPECT_EQ(particlesOf(batches.order[k - 1])[1], members[0])
                << "constraint " << batches.order[k] << " does not continue its chain";
          }
          for (const PfxUInt32 p : members) {
            EXPECT_TRUE(chainOf[p] == ~0u || chainOf[p] == chain)
                << "particle " << p << " in two chains of phase " << phase;
            chainOf[p] = chain;
          }
        }
      }
    }
    for (PfxUInt32 i = 0; i < count; ++i) EXPECT_EQ(seen[i], 1) << "constraint " << i;
  };
  checkPhases(batched.distance, static_cast<PfxUInt32>(b.distanceConstraints.size()),
              [&](PfxUInt32 i) {
                const auto& c = b.distanceConstraints[i];
                return std::vector<PfxUInt32>{c.m_particleA, c.m_particleB};
              });
  checkPhases(batched.angle, static_cast<PfxUInt32>(b.angleConstraints.size()), [&](PfxUInt32 i) {
    const auto& c = b.angleConstraints[i];
    return std::vector<PfxUInt32>{c.m_particleA, c.m_particleB, c.m_particleC};
  });

  PfxSolveParticleConstraintsParam solve;
  solve.particles = b.particles.data();
  solve.numParticles = n;
  solve.distanceConstraints = b.distanceConstraints.data();
  solve.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
  solve.angleConstraints = b.angleConstraints.data();
  solve.numAngleConstraints = static_cast<PfxUInt32>(b.angleConstraints.size());
  solve.distanceBatches = &batched.distance;
  solve.angleBatches = &batched.angle;
  EXPECT_EQ(pfxSolveParticleConstraints(solve), PFX_OK) << pfxGetLastErrorDetail();
  // Batches made for other constraints are refused, and nothing moves.
  const std::vector<PfxParticle> before = b.particles;
  --batched.distance.numConstraints;
  EXPECT_EQ(pfxSolveParticleConstraints(solve), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "distanceBatches"), nullptr)
      << pfxGetLastErrorDetail();
  ++batched.distance.numConstraints;
  solve.angleBatches = nullptr;
  EXPECT_EQ(pfxSolveParticleConstraints(solve), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(std::memcmp(before.data(), b.particles.data(), n * sizeof(PfxParticle)), 0);
}

// A chain of rigid links is solved as one system: four ropes side by side (so that they are
// chains, not single links), straight and stretched by a tenth, are back at their rest
// lengths after one iteration, where link after link one pass took back only a part, and
// their centres of mass have not moved (the links only push particles against each other).
TEST(Particles, OneIterationTakesAChainOfLinksBackToItsRestLength) {
  PfxParticleGroupBuilder b;
  const PfxUInt32 numRopes = 4, perRope = 100;
  const PfxFloat restLength = PfxFloat(1) / (perRope - 1);
  for (PfxUInt32 r = 0; r < numRopes; ++r) {
    b.addRope(PfxVector3(0, 0, PfxFloat(r)), PfxVector3(PfxFloat(1.1), 0, PfxFloat(r)), perRope,
              PfxParticleGroupBuilder::Material());
  }
  for (PfxParticleDistanceConstraint& c : b.distanceConstraints) c.m_restLength = restLength;
  const PfxUInt32 n = static_cast<PfxUInt32>(b.particles.size());
  Batched batched;
  ASSERT_EQ(batchBuilder(b, batched, n), PFX_OK) << pfxGetLastErrorDetail();
  ASSERT_EQ(batched.distance.numChains, numRopes);
  PfxVector3 centreBefore = PfxVector3::Zero();
  for (const PfxParticle& p : b.particles) centreBefore += p.m_position / PfxFloat(n);
  PfxSolveParticleConstraintsParam solve;
  solve.particles = b.particles.data();
  solve.numParticles = n;
  solve.distanceConstraints = b.distanceConstraints.data();
  solve.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
  solve.distanceBatches = &batched.distance;
  solve.angleBatches = &batched.angle;
  ASSERT_EQ(pfxSolveParticleConstraints(solve), PFX_OK) << pfxGetLastErrorDetail();
  for (const PfxParticleDistanceConstraint& c : b.distanceConstraints) {
    const PfxFloat length =
        (b.particles[c.m_particleA].m_position - b.particles[c.m_particleB].m_position).norm();
    EXPECT_NEAR(length, restLength, 1e-6) << "link " << c.m_particleA << "-" << c.m_particleB;
  }
  PfxVector3 centreAfter = PfxVector3::Zero();
  for (const PfxParticle& p : b.particles) centreAfter += p.m_position / PfxFloat(n);
  EXPECT_LT((centreAfter - centreBefore).norm(), 1e-5);
}

TEST(Particles, BatchingRefusesMissingParticlesAndSmallBuffers) {
  PfxParticleGroupBuilder b;
  b.addRope(PfxVector3::Zero(), PfxVector3(1, 0, 0), 10, PfxParticleGroupBuilder::Material());
  const PfxUInt32 n = static_cast<PfxUInt32>(b.particles.size());
  Batched batched;
  ASSERT_EQ(batchBuilder(b, batched, n), PFX_OK);
  const PfxParticleConstraintBatches good = batched.distance;
  const std::vector<PfxUInt32> goodOrder = batched.distanceOrder;

  b.distanceConstraints[3].m_particleB = n;
  EXPECT_EQ(batchBuilder(b, batched, n), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "distanceConstraints[3].particleB is 10"),
            nullptr)
      << pfxGetLastErrorDetail();
  b.distanceConstraints[3].m_particleB = 4;

  PfxBatchParticleConstraintsParam param;
  param.workBuff = batched.work.data();
  param.workBytes = pfxGetWorkBytesOfBatchParticleConstraints(n, 9) - 1;
  param.numParticles = n;
  param.distanceConstraints = b.distanceConstraints.data();
  param.numDistanceConstraints = static_cast<PfxUInt32>(b.distanceConstraints.size());
  param.distanceBatches = &batched.distance;
  param.angleBatches = &batched.angle;
  std::vector<PfxUInt32> order(b.distanceConstraints.size(), 0);
  batched.distance.order = order.data();
  batched.distance.numPhases = 7;
  EXPECT_EQ(pfxBatchParticleConstraints(param), PFX_ERR_OUT_OF_BUFFER);
  param.workBytes += 1;
  param.distanceBatches = nullptr;
  EXPECT_EQ(pfxBatchParticleConstraints(param), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(batched.distance.numPhases, 7u) << "untouched after a refusal";
  EXPECT_EQ(order, std::vector<PfxUInt32>(b.distanceConstraints.size(), 0));
  // A lone rope, one chain, is taken link by link: two phases, alternate links.
  EXPECT_EQ(good.numChains, 9u);
  EXPECT_EQ(good.numPhases, 2u);
  EXPECT_EQ(goodOrder[0], 0u);
  EXPECT_EQ(goodOrder[1], 2u);
}

// Contacts between two groups: a particle of A resting on one of B is found and pushed out;
// bad input is refused with the output untouched.
TEST(Particles, GroupContactsAreFoundSolvedAndBadInputRefused) {
  std::vector<PfxParticle> a(2), b(3);
  for (PfxUInt32 i = 0; i < 3; ++i) b[i].m_position = PfxVector3(PfxFloat(i), 0, 0);
  a[0].m_position = PfxVector3(1, PfxFloat(0.015), 0);  // overlapping b[1] by 5 mm
  a[1].m_position = PfxVector3(5, 5, 5);
  for (PfxParticle& p : a) p.m_previousPosition = p.m_position;
  for (PfxParticle& p : b) p.m_previousPosition = p.m_position;
  std::vector<PfxVector4> work(pfxGetWorkBytesOfDetectParticleGroupContacts(3) / sizeof(PfxVector4) + 1);
  std::vector<PfxParticleContact> contacts(4);
  PfxDetectParticleGroupContactsParam detect;
  detect.workBuff = work.data();
  detect.workBytes = static_cast<PfxUInt32>(work.size() * sizeof(PfxVector4));
  detect.particlesA = a.data();
  detect.numParticlesA = 2;
  detect.particlesB = b.data();
  detect.numParticlesB = 3;
  detect.contacts = contacts.data();
  detect.maxContacts = 4;
  PfxDetectParticleGroupContactsResult found;
  ASSERT_EQ(pfxDetectParticleGroupContacts(detect, found), PFX_OK) << pfxGetLastErrorDetail();
  ASSERT_EQ(found.numContacts, 1u);
  EXPECT_EQ(contacts[0].m_particle, 0u);
  EXPECT_EQ(contacts[0].m_other, 1u);

  PfxSolveParticleGroupContactsParam solve;
  solve.particlesA = a.data();
  solve.numParticlesA = 2;
  solve.particlesB = b.data();
  solve.numParticlesB = 3;
  solve.contacts = contacts.data();
  solve.numContacts = 1;
  ASSERT_EQ(pfxSolveParticleGroupContacts(solve), PFX_OK) << pfxGetLastErrorDetail();
  EXPECT_NEAR((a[0].m_position - b[1].m_position).norm(), a[0].m_radius + b[1].m_radius, 1e-6);
  EXPECT_NEAR(a[0].m_position.y() + b[1].m_position.y(), 0.015, 1e-6) << "equal masses, equal shares";
  // The pair pushed: the speed with which it parts along its normal is taken out, shared by
  // inverse mass; the speed across the normal stays.
  a[0].m_velocity = PfxVector3(PfxFloat(0.5), 2, 0);
  b[1].m_velocity = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxUpdateParticleGroupContacts(solve), PFX_OK) << pfxGetLastErrorDetail();
  EXPECT_NEAR(a[0].m_velocity.y(), 0.5, 1e-5);
  EXPECT_NEAR(b[1].m_velocity.y(), 0.5, 1e-5);
  EXPECT_NEAR(a[0].m_velocity.x(), 0.5, 1e-5);
  a[0].m_velocity = PfxVector3(0, -1, 0);  // closing: left alone
  b[1].m_velocity.setZero();
  ASSERT_EQ(pfxUpdateParticleGroupContacts(solve), PFX_OK);
  EXPECT_EQ(a[0].m_velocity.y(), -1);

  // Filters that do not match: no contact.
  a[0].m_contactFilterSelf = 2;
  a[0].m_contactFilterTarget = 2;
  a[0].m_position = PfxVector3(1, PfxFloat(0.015), 0);
  ASSERT_EQ(pfxDetectParticleGroupContacts(detect, found), PFX_OK);
  EXPECT_EQ(found.numContacts, 0u);

  const std::vector<PfxParticleContact> before = contacts;
  PfxDetectParticleGroupContactsResult untouched;
  untouched.numContacts = 77;
  b[2].m_position.x() = std::nanf("");
  EXPECT_EQ(pfxDetectParticleGroupContacts(detect, untouched), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "particles[2]"), nullptr) << pfxGetLastErrorDetail();
  b[2].m_position.x() = 2;
  detect.workBytes = pfxGetWorkBytesOfDetectParticleGroupContacts(3) - 1;
  EXPECT_EQ(pfxDetectParticleGroupContacts(detect, untouched), PFX_ERR_OUT_OF_BUFFER);
  detect.workBytes = static_cast<PfxUInt32>(work.size() * sizeof(PfxVector4));
  detect.contactMargin = -1;
  EXPECT_EQ(pfxDetectParticleGroupContacts(detect, untouched), PFX_ERR_INVALID_VALUE);
  detect.contactMargin = PfxFloat(0.01);
  detect.contacts = nullptr;
  EXPECT_EQ(pfxDetectParticleGroupContacts(detect, untouched), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(untouched.numContacts, 77u);
  // Field by field: the contact's padding is not copied with it (Eigen members make the copy
  // member-wise), and AddressSanitizer fills fresh memory, so bytes would differ there.
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const PfxParticleContact& was = before[i];
    const PfxParticleContact& is = contacts[i];
    EXPECT_TRUE(was.m_localPoint == is.m_localPoint && was.m_localNormal == is.m_localNormal &&
                was.m_particle == is.m_particle && was.m_other == is.m_other &&
                was.m_friction == is.m_friction && was.m_kind == is.m_kind &&
                was.m_shapeId == is.m_shapeId && was.m_lambdaNormal == is.m_lambdaNormal &&
                was.m_lambdaTangent == is.m_lambdaTangent)
        << "contact " << i << " changed by a refused call";
  }

  const std::vector<PfxParticle> beforeA = a;
  contacts[0].m_other = 3;
  EXPECT_EQ(pfxSolveParticleGroupContacts(solve), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "contacts[0]"), nullptr) << pfxGetLastErrorDetail();
  EXPECT_EQ(pfxUpdateParticleGroupContacts(solve), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(std::strstr(pfxGetLastErrorDetail(), "pfxUpdateParticleGroupContacts"), nullptr)
      << pfxGetLastErrorDetail();
  solve.particlesB = nullptr;
  EXPECT_EQ(pfxSolveParticleGroupContacts(solve), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(pfxUpdateParticleGroupContacts(solve), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(std::memcmp(beforeA.data(), a.data(), a.size() * sizeof(PfxParticle)), 0);
}
