// PfxWorld as a whole: bad input leaves it untouched, a warm step allocates nothing, and
// the same world stepped the same way gives the same bits.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx_allocation_counter.h"

using namespace pfx;


namespace {

const PfxFloat kNaN = std::numeric_limits<PfxFloat>::quiet_NaN();
const PfxFloat kInf = std::numeric_limits<PfxFloat>::infinity();

// A ground, a small pyramid, a few spheres, capsules and cylinders: every stage has work.
void buildScene(PfxWorld& world, PfxPipelineType pipeline, bool measureStages = false) {
  PfxWorldParam param;
  param.pipeline = pipeline;
  param.measureStages = measureStages;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  for (int layer = 0; layer < 4; ++layer) {
    for (int i = 0; i < 4 - layer; ++i) {
      PfxBodyInit init;
      init.position = PfxVector3(i - 0.5f * (3 - layer), 0.5f + layer * 1.01f, 0);
      ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init), PFX_OK);
    }
  }
  for (int i = 0; i < 6; ++i) {
    PfxBodyInit init;
    init.position = PfxVector3(-3 + i * 1.2f, 6 + 0.3f * i, 2);
    init.angularVelocity = PfxVector3(0.1f * i, 0.2f, -0.3f);
    const PfxShape shape = i % 3 == 0   ? pfxMakeShape(PfxSphere(0.4f))
                           : i % 3 == 1 ? pfxMakeShape(PfxCapsule(0.5f, 0.3f))
                                        : pfxMakeShape(PfxCylinder(0.4f, 0.3f));
    ASSERT_EQ(pfxAddBody(world, shape, init), PFX_OK);
  }
}

std::vector<unsigned char> snapshot(const PfxWorld& world) {
  const auto* begin = reinterpret_cast<const unsigned char*>(world.getRigidStates());
  return std::vector<unsigned char>(begin,
                                    begin + world.getNumRigidBodies() * sizeof(PfxRigidState));
}

PfxRigidState validState() {
  PfxRigidState s;
  s.reset();
  s.setPosition(PfxVector3(0, 5, 0));
  return s;
}

PfxRigidBody validBody() {
  PfxRigidBody b;
  b.reset();
  return b;
}

}  // namespace

TEST(World, AddRigidBodyRejectsBadInputAndChangesNothing) {
  PfxWorld world;
  buildScene(world, kPfxPipelineStable);
  for (int i = 0; i < 10; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxUInt32 numBodies = world.getNumRigidBodies();
  const std::vector<unsigned char> before = snapshot(world);
  const PfxShape box = pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f));

  auto expectRejected = [&](PfxInt32 expected, const PfxRigidState& s, const PfxRigidBody& b,
                            const PfxShape* shapes, PfxUInt32 n, const char* what) {
    PfxUInt32 id = 12345;
    EXPECT_EQ(world.addRigidBody(s, b, shapes, n, &id), expected) << what;
    EXPECT_EQ(id, 12345u) << what;
    EXPECT_EQ(world.getNumRigidBodies(), numBodies) << what;
    EXPECT_EQ(snapshot(world), before) << what;
  };

  PfxRigidState s = validState();
  s.setPosition(PfxVector3(kNaN, 0, 0));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "NaN position");
  s = validState();
  s.setPosition(PfxVector3(0, kInf, 0));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "infinite position");
  s = validState();
  s.setOrientation(PfxQuat(kNaN, 0, 0, 0));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "NaN orientation");
  s = validState();
  s.setOrientation(PfxQuat(2, 0, 0, 0));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "non-unit orientation");
  s = validState();
  s.setLinearVelocity(PfxVector3(0, 0, kInf));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "infinite velocity");
  s = validState();
  s.setAngularVelocity(PfxVector3(kNaN, 0, 0));
  expectRejected(PFX_ERR_INVALID_VALUE, s, validBody(), &box, 1, "NaN angular velocity");

  PfxRigidBody b = validBody();
  b.setMass(0);
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "zero mass");
  b.setMass(-1);
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "negative mass");
  b = validBody();
  b.setInertia(PfxMatrix3(PfxVector3(1, -1, 1).asDiagonal()));
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "negative inertia");
  b.setInertia(PfxMatrix3::Zero());
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "zero inertia");
  PfxMatrix3 skew = PfxMatrix3::Identity();
  skew(0, 1) = 0.5f;
  b.setInertia(skew);
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "asymmetric inertia");
  b = validBody();
  b.setFriction(kNaN);
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "NaN friction");
  b = validBody();
  b.setRestitution(1.5f);
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), b, &box, 1, "restitution > 1");

  const PfxShape negativeBox = pfxMakeShape(PfxBox(0.5f, -0.1f, 0.5f));
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), validBody(), &negativeBox, 1, "negative size");
  const PfxShape nanSphere = pfxMakeShape(PfxSphere(kNaN));
  expectRejected(PFX_ERR_INVALID_VALUE, validState(), validBody(), &nanSphere, 1, "NaN radius");
  const PfxShape nullMesh = pfxMakeShape(static_cast<const PfxConvexMesh*>(nullptr));
  expectRejected(PFX_ERR_NULL_POINTER, validState(), validBody(), &nullMesh, 1, "null mesh");
  std::vector<PfxShape> many(PFX_MAX_SHAPES_PER_COLLIDABLE + 1, box);
  expectRejected(PFX_ERR_OUT_OF_RANGE, validState(), validBody(), many.data(),
                 static_cast<PfxUInt32>(many.size()), "too many shapes");
  expectRejected(PFX_ERR_OUT_OF_RANGE, validState(), validBody(), many.data(), 0, "no shapes");
  expectRejected(PFX_ERR_NULL_POINTER, validState(), validBody(), nullptr, 1, "null shapes");

  // A fixed body needs no mass: zero is fine there.
  PfxRigidState fixed = validState();
  fixed.setMotionType(kPfxMotionTypeFixed);
  PfxRigidBody massless = validBody();
  massless.setMass(0);
  EXPECT_EQ(world.addRigidBody(fixed, massless, &box, 1), PFX_OK);
}

TEST(World, SettersRejectBadInputAndChangeNothing) {
  PfxWorld world;
  buildScene(world, kPfxPipelineStable);
  const std::vector<unsigned char> before = snapshot(world);
  PfxRigidState bad = world.getRigidState(3);
  bad.setLinearVelocity(PfxVector3(kNaN, 0, 0));
  EXPECT_EQ(world.setRigidState(3, bad), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setRigidState(world.getNumRigidBodies(), world.getRigidState(3)),
            PFX_ERR_OUT_OF_RANGE);
  PfxRigidBody badBody = world.getRigidBody(3);
  badBody.setMass(-2);
  EXPECT_EQ(world.setRigidBody(3, badBody), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.applyForce(3, PfxVector3(kInf, 0, 0), PfxVector3::Zero()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.applyForce(999, PfxVector3::Zero(), PfxVector3::Zero()), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.setKeyframeTarget(3, PfxVector3::Zero(), PfxQuat::Identity()),
            PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(snapshot(world), before);
  // The forces that were rejected must not act: a step matches a world that never saw them.
  PfxWorld reference;
  buildScene(reference, kPfxPipelineStable);
  ASSERT_EQ(world.step(), PFX_OK);
  ASSERT_EQ(reference.step(), PFX_OK);
  EXPECT_EQ(snapshot(world), snapshot(reference));
}

TEST(World, InitializeRejectsBadParameters) {
  PfxWorld world;
  const PfxWorldParam good;
  ASSERT_EQ(world.initialize(good), PFX_OK);
  auto rejects = [&](PfxWorldParam p, PfxInt32 code) {
    EXPECT_EQ(world.initialize(p), code);
    EXPECT_EQ(world.getParam().timeStep, good.timeStep);
  };
  PfxWorldParam p;
  p.timeStep = 0;
  rejects(p, PFX_ERR_INVALID_VALUE);
  p = good;
  p.timeStep = kNaN;
  rejects(p, PFX_ERR_INVALID_VALUE);
  p = good;
  p.iteration = 0;
  rejects(p, PFX_ERR_INVALID_VALUE);
  p = good;
  p.worldExtent = PfxVector3(10, -1, 10);
  rejects(p, PFX_ERR_INVALID_VALUE);
  p = good;
  p.gravity = PfxVector3(0, kNaN, 0);
  rejects(p, PFX_ERR_INVALID_VALUE);
  p = good;
  p.pipeline = static_cast<PfxPipelineType>(7);
  rejects(p, PFX_ERR_INVALID_FLAG);
  p = good;
  p.outOfWorldBehavior = 0x80;
  rejects(p, PFX_ERR_INVALID_FLAG);
  p = good;
  p.numThreads = PFX_MAX_THREADS + 1;
  p.timeStep = good.timeStep * 2;
  rejects(p, PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.getTaskManager()->getNumThreads(), 1u);
  p = good;
  p.timeStep = good.timeStep * 2;
  p.subStep = PFX_MAX_SUB_STEPS + 1;
  rejects(p, PFX_ERR_OUT_OF_RANGE);
  p.subStep = 0xffffffffu;
  rejects(p, PFX_ERR_OUT_OF_RANGE);
  p = good;
  p.timeStep = good.timeStep * 2;
  p.iteration = PFX_MAX_ITERATIONS + 1;
  rejects(p, PFX_ERR_OUT_OF_RANGE);
  p.iteration = 0xffffffffu;
  rejects(p, PFX_ERR_OUT_OF_RANGE);
  p.subStep = PFX_MAX_SUB_STEPS;
  p.iteration = PFX_MAX_ITERATIONS;
  EXPECT_EQ(world.initialize(p), PFX_OK);
}

TEST(World, SetStepParamKeepsTheBodiesAndRejectsBadValues) {
  PfxWorld world;
  buildScene(world, kPfxPipelineStable);
  for (int i = 0; i < 30; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxWorldParam before = world.getParam();
  const std::vector<unsigned char> states = snapshot(world);
  const PfxVector3 down(0, -9.8f, 0);
  EXPECT_EQ(world.setStepParam(0, 2, 5, down), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setStepParam(kNaN, 2, 5, down), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setStepParam(0.01f, 0, 5, down), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setStepParam(0.01f, 2, 0, down), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setStepParam(0.01f, 2, 5, PfxVector3(0, kInf, 0)), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setStepParam(0.01f, PFX_MAX_SUB_STEPS + 1, 5, down), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.setStepParam(0.01f, 2, PFX_MAX_ITERATIONS + 1, down), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.setStepParam(0.01f, 0xffffffffu, 0xffffffffu, down), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.getParam().timeStep, before.timeStep);
  EXPECT_EQ(world.getParam().subStep, before.subStep);
  EXPECT_EQ(world.getParam().iteration, before.iteration);
  EXPECT_EQ(world.getParam().gravity, before.gravity);

  ASSERT_EQ(world.setStepParam(0.01f, 2, 5, PfxVector3::Zero()), PFX_OK);
  EXPECT_EQ(world.getParam().timeStep, 0.01f);
  EXPECT_EQ(world.getParam().subStep, 2u);
  EXPECT_EQ(world.getParam().iteration, 5u);
  EXPECT_EQ(world.getParam().gravity, PfxVector3::Zero());
  EXPECT_EQ(snapshot(world), states) << "bodies untouched until the next step";
  const double time = world.getSimulatedTime();
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getSimulatedTime() - time, 0.01, 1e-6);
}

TEST(World, SetSimulatedTimeContinuesTheClockAndRefusesBadTimes) {
  PfxWorld world;
  buildScene(world, kPfxPipelineStable);
  ASSERT_EQ(world.step(), PFX_OK);
  const double stepped = world.getSimulatedTime();
  for (double bad : {-0.5, double(kNaN), double(kInf)}) {
    EXPECT_EQ(world.setSimulatedTime(bad), PFX_ERR_INVALID_VALUE) << bad;
    EXPECT_EQ(world.getSimulatedTime(), stepped) << bad;
  }
  ASSERT_EQ(world.setSimulatedTime(12.5), PFX_OK);
  EXPECT_EQ(world.getSimulatedTime(), 12.5);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getSimulatedTime(), 12.5 + world.getParam().timeStep, 1e-9);
}

TEST(World, StepAllocatesNothingAfterWarmUp) {
  for (PfxPipelineType pipeline : {kPfxPipelineSimple, kPfxPipelineStable}) {
    PfxWorld world;
    buildScene(world, pipeline);
    for (int i = 0; i < 120; ++i) ASSERT_EQ(world.step(), PFX_OK);
    const long before = pfx_test::pfxAllocationCount();
    for (int i = 0; i < 240; ++i) ASSERT_EQ(world.step(), PFX_OK);
    EXPECT_EQ(pfx_test::pfxAllocationCount() - before, 0) << "pipeline " << int(pipeline);
    EXPECT_GT(world.getStats().numContactPoints, 0u);
  }
}

TEST(World, ReservedBodiesStepAsGrownOnesAndRoomGrowsBeyond) {
  PfxWorld reserved, grown;
  ASSERT_EQ(reserved.initialize(PfxWorldParam()), PFX_OK);
  ASSERT_EQ(grown.initialize(PfxWorldParam()), PFX_OK);
  constexpr PfxUInt32 kBodies = 100;
  reserved.reserveRigidBodies(kBodies);
  reserved.reserveRigidBodies(kBodies / 2);  // less than there is room for: nothing changes
  for (PfxUInt32 i = 0; i < kBodies; ++i) {
    PfxBodyInit init;
    init.mass = i == 0 ? 0 : 1;
    init.position = PfxVector3(PfxFloat(i % 10) * 1.1f, PfxFloat(i / 10) * 1.1f, 0);
    ASSERT_EQ(pfxAddBody(reserved, pfxMakeShape(PfxSphere(0.5f)), init), PFX_OK);
    ASSERT_EQ(pfxAddBody(grown, pfxMakeShape(PfxSphere(0.5f)), init), PFX_OK);
  }
  const long afterAdding = pfx_test::pfxAllocationCount();
  ASSERT_EQ(pfxAddBody(reserved, pfxMakeShape(PfxSphere(0.5f)), PfxBodyInit()), PFX_OK);
  EXPECT_GT(pfx_test::pfxAllocationCount(), afterAdding) << "one body beyond the room grows it";
  ASSERT_EQ(pfxAddBody(grown, pfxMakeShape(PfxSphere(0.5f)), PfxBodyInit()), PFX_OK);
  for (int i = 0; i < 60; ++i) {
    ASSERT_EQ(reserved.step(), PFX_OK);
    ASSERT_EQ(grown.step(), PFX_OK);
  }
  EXPECT_EQ(snapshot(reserved), snapshot(grown));
}

TEST(World, ReservingBodiesAllocatesOnceForThemAll) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  world.reserveRigidBodies(64);
  const long before = pfx_test::pfxAllocationCount();
  for (PfxUInt32 i = 0; i < 64; ++i) {
    PfxBodyInit init;
    init.position = PfxVector3(PfxFloat(i) * 2, 0, 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5f)), init), PFX_OK);
  }
  EXPECT_EQ(pfx_test::pfxAllocationCount() - before, 0);
}

TEST(World, SameWorldSameStepsGiveIdenticalBits) {
  for (PfxPipelineType pipeline : {kPfxPipelineSimple, kPfxPipelineStable}) {
    PfxWorld a, b;
    buildScene(a, pipeline);
    buildScene(b, pipeline);
    for (int i = 0; i < 300; ++i) {
      ASSERT_EQ(a.step(), PFX_OK);
      ASSERT_EQ(b.step(), PFX_OK);
    }
    EXPECT_EQ(snapshot(a), snapshot(b)) << "pipeline " << int(pipeline);
    // And the scene did move: not identical because nothing happened.
    EXPECT_GT((a.getRigidState(15).getPosition() - PfxVector3(-3 + 5 * 1.2f, 7.5f, 2)).norm(), 1);
  }
}

TEST(World, ReportsStageTimesAndSkipsRefreshInSimplePipeline) {
  PfxWorld world;
  buildScene(world, kPfxPipelineSimple, true);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxWorldStats& stats = world.getStats();
  EXPECT_EQ(stats.stageSeconds[kPfxStageRefreshContacts], 0.0);
  EXPECT_GT(stats.stageSeconds[kPfxStageDetectCollision], 0.0);
  EXPECT_GT(stats.stepSeconds, 0.0);
  EXPECT_GT(stats.numPairs, 0u);
  EXPECT_GE(stats.numPairs + stats.numSleepingPairs, stats.numContactPairs);
  EXPECT_GE(stats.maxPenetration, 0);
}

// Unless the world measures its stages, their times stay zero and only the step is timed
// (the island groups of two threads: test_world_threads).
TEST(World, TimesItsStagesOnlyWhenAsked) {
  PfxWorld world;
  buildScene(world, kPfxPipelineStable);
  for (int i = 0; i < 30; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxWorldStats& stats = world.getStats();
    for (int s = 0; s < kPfxStageCount; ++s) {
      EXPECT_EQ(stats.stageSeconds[s], 0.0) << pfxStageName(PfxStage(s));
    }
    EXPECT_GT(stats.stepSeconds, 0.0);
  }
}

// A scene of spheres only skips the joint stages (zero time); the step reports the joints'
// gap and, when asked, how much energy and momentum it changed.
TEST(World, ReportsItsOwnErrorFigures) {
  PfxWorldParam param;
  param.gravity.setZero();
  param.measureConservation = true;
  param.measureStages = true;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit a;
  a.position = PfxVector3(-1, 0, 0);
  a.linearVelocity = PfxVector3(3, 0, 0);
  a.angularVelocity = PfxVector3(0, 4, 1);
  a.mass = 2;
  PfxBodyInit b = a;
  b.position = PfxVector3(1, 0.2f, 0);
  b.linearVelocity = PfxVector3(-1, 0, 0);
  b.mass = 1;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.3f)), a), PFX_OK);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.3f)), b), PFX_OK);
  const PfxConservedQuantities start = world.measureConservedQuantities();
  double energyLost = 0;
  for (int i = 0; i < 60; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxWorldStats& stats = world.getStats();
    EXPECT_EQ(stats.stageSeconds[kPfxStageSetupJointConstraints], 0.0);
    EXPECT_EQ(stats.stageSeconds[kPfxStageCorrectJointPositions], 0.0);
    EXPECT_EQ(stats.maxJointGap, 0);
    EXPECT_LT(stats.linearMomentumChange, 1e-4);
    EXPECT_LT(stats.angularMomentumChange, 1e-4);
    energyLost -= stats.energyChange;
  }
  // The spheres met (inelastic, e = 0): energy went, momentum stayed.
  const PfxConservedQuantities end = world.measureConservedQuantities();
  EXPECT_GT(energyLost, 0.1 * start.energy);
  EXPECT_NEAR(start.energy - end.energy, energyLost, 1e-4 * start.energy);
  EXPECT_LT((end.linearMomentum - start.linearMomentum).norm(), 1e-4f);

  // With a pendulum the joint stages run and the gap is reported.
  PfxWorld pendulum;
  PfxWorldParam timed;
  timed.measureStages = true;
  ASSERT_EQ(pendulum.initialize(timed), PFX_OK);
  PfxBodyInit pivot;
  pivot.mass = 0;
  PfxUInt32 pivotId = 0, bobId = 0;
  ASSERT_EQ(pfxAddBody(pendulum, pfxMakeShape(PfxSphere(0.05f)), pivot, &pivotId), PFX_OK);
  PfxBodyInit bob;
  bob.position = PfxVector3(1, 0, 0);
  ASSERT_EQ(pfxAddBody(pendulum, pfxMakeShape(PfxSphere(0.1f)), bob, &bobId), PFX_OK);
  PfxBallJointInitParam ball;
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeBallJoint(joint, pendulum.getRigidState(pivotId),
                                   pendulum.getRigidState(bobId), ball),
            PFX_OK);
  ASSERT_EQ(pendulum.addJoint(joint), PFX_OK);
  // Pull the bob 1 cm off its anchor: the step reports the gap it leaves (much less).
  PfxRigidState pulled = pendulum.getRigidState(bobId);
  pulled.setPosition(PfxVector3(1.01f, 0, 0));
  ASSERT_EQ(pendulum.setRigidState(bobId, pulled), PFX_OK);
  ASSERT_EQ(pendulum.step(), PFX_OK);
  EXPECT_GT(pendulum.getStats().stageSeconds[kPfxStageCorrectJointPositions], 0.0);
  EXPECT_LT(pendulum.getStats().maxJointGap, 1e-4f);
  EXPECT_NEAR((pendulum.getRigidState(bobId).getPosition() - PfxVector3::Zero()).norm(), 1,
              1e-3f);
}

// Each touching pair holds room for the points its shapes can give: a sphere on the ground
// one, a box four. A box that lands on a corner holds room for four from its first point,
// kept for it since its pair was found, so that touching with more of it (one point, then
// four) allocates nothing (test_world_threads' warm steps, where a pile lands).
TEST(World, ManifoldsHoldRoomForThePointsTheirShapesCanGive) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  PfxBodyInit sphere, box, tipped;
  sphere.position = PfxVector3(-3, 0.5f, 0);
  box.position = PfxVector3(0, 0.5f, 0);
  tipped.position = PfxVector3(3, 1.2f, 0);
  tipped.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.4f, PfxVector3(1, 0, 1).normalized()));
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5f)), sphere), PFX_OK);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), box), PFX_OK);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), tipped), PFX_OK);
  const auto manifoldOf = [&](PfxUInt32 id) -> const PfxContactManifold* {
    for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
      const PfxConstraintPair& pair = world.getContactPair(i);
      if (pfxGetObjectIdA(pair) == id || pfxGetObjectIdB(pair) == id) {
        return &world.getContactManifold(pair);
      }
    }
    return nullptr;
  };
  PfxUInt32 stepsOnOnePoint = 0, stepsOnMore = 0;
  long allocationsSinceLanding = 0;
  bool landed = false;
  for (int step = 0; step < 120; ++step) {
    const long before = pfx_test::pfxAllocationCount();
    ASSERT_EQ(world.step(), PFX_OK);
    if (landed) allocationsSinceLanding += pfx_test::pfxAllocationCount() - before;
    const PfxContactManifold* landing = manifoldOf(3);
    if (!landing || landing->getNumContacts() == 0) continue;
    landed = true;
    EXPECT_EQ(landing->getCapacity(), PFX_NUM_CONTACTS_PER_MANIFOLD) << "step " << step;
    (landing->getNumContacts() == 1 ? stepsOnOnePoint : stepsOnMore) += 1;
  }
  EXPECT_GT(stepsOnOnePoint, 0u) << "the corner lands alone first";
  EXPECT_GT(stepsOnMore, 0u);
  EXPECT_EQ(allocationsSinceLanding, 0);
  ASSERT_NE(manifoldOf(1), nullptr);
  EXPECT_EQ(manifoldOf(1)->getNumContacts(), 1u);
  EXPECT_EQ(manifoldOf(1)->getCapacity(), 1u);
  ASSERT_NE(manifoldOf(2), nullptr);
  EXPECT_EQ(manifoldOf(2)->getNumContacts(), 4u);
  EXPECT_EQ(manifoldOf(2)->getCapacity(), 4u);
  ASSERT_NE(manifoldOf(3), nullptr);
  EXPECT_EQ(manifoldOf(3)->getNumContacts(), 4u) << "the tipped box came to rest flat";
  EXPECT_LT(world.getRigidState(3).getLinearVelocity().norm(), 0.01f);
}
