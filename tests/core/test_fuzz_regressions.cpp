// Defects the fuzz targets found (tests/fuzz/, README.md "Fuzzing"), each as the smallest
// sequence of calls that showed it, asserting the refusal or the behaviour that holds now.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "pfx/base_level/collision/pfx_contact_shapes.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_serialize_test_world.h"

using namespace pfx;
using namespace pfx_test;

namespace {

const PfxFloat kLargestFloat = std::numeric_limits<PfxFloat>::max();

PfxUInt32 addSphere(PfxWorld& world, const PfxVector3& position) {
  PfxBodyInit init;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.5))), init, &id), PFX_OK);
  return id;
}

bool sameState(const PfxRigidState& a, const PfxRigidState& b) {
  return a.getPosition() == b.getPosition() && a.getOrientation().coeffs() == b.getOrientation().coeffs() &&
         a.getLinearVelocity() == b.getLinearVelocity() &&
         a.getAngularVelocity() == b.getAngularVelocity();
}

}  // namespace

// fuzz_world_api: a body added with an angular velocity of 3.4e38 rad/s (finite, so it was
// accepted) turned NaN in its first step, and the integrator converted that NaN to an int
// (undefined behaviour). Velocities whose squared length overflows are refused now.
TEST(FuzzRegressions, VelocityWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));

  PfxBodyInit spinning;
  spinning.angularVelocity = PfxVector3(PfxFloat(3.14159), kLargestFloat, 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), spinning),
            PFX_ERR_INVALID_VALUE);
  PfxBodyInit fast;
  // A speed whose square overflows in either precision.
  fast.linearVelocity = PfxVector3(0, -2 * std::sqrt(kLargestFloat), 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), fast),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);

  const PfxRigidState before = world.getRigidState(kept);
  PfxRigidState state = before;
  state.setAngularVelocity(PfxVector3(0, kLargestFloat, 0));
  EXPECT_EQ(world.setRigidState(kept, state), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(kept), before));

  // The fastest spin still accepted steps to finite states.
  state = before;
  state.setAngularVelocity(PfxVector3(0, 1e18f, 0));
  ASSERT_EQ(world.setRigidState(kept, state), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(pfxIsFinite(world.getRigidState(kept).getPosition()));
  EXPECT_TRUE(pfxIsFinite(world.getRigidState(kept).getOrientation()));
}

// fuzz_world_api: a world initialized with a time step of 3.4e38 s (finite, so it was
// accepted) made its bodies' positions and velocities infinite in the first step. A time
// step and gravity whose one-step velocity has an overflowing square are refused now, by
// initialize and setStepParam alike.
TEST(FuzzRegressions, TimeStepThatMakesGravityInfiniteIsRefusedWithNothingChanged) {
  PfxWorld world;
  PfxWorldParam param;
  param.timeStep = kLargestFloat;
  EXPECT_EQ(world.initialize(param), PFX_ERR_INVALID_VALUE);
  param.gravity = PfxVector3::Zero();
  EXPECT_EQ(world.initialize(param), PFX_ERR_OUT_OF_RANGE);  // above PFX_MAX_TIME_STEP

  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 id = addSphere(world, PfxVector3(0, 2, 0));
  EXPECT_EQ(world.setStepParam(kLargestFloat, 1, 10, PfxVector3(0, PfxFloat(-9.8), 0)),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getParam().timeStep, PfxWorldParam().timeStep);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(world.getRigidState(id).isValid());
}

// fuzz_world_file: a saved world whose box had the principal moments 0.0017, 0.031 and
// 1.4e-38 kg m^2 (positive, so it was read) gave the solver an inverse inertia of 7e37 and
// every body it touched turned NaN in the first step. A moment below the largest times the
// precision's epsilon, lost in rounding once the tensor turns, is refused now, by
// addRigidBody, setRigidBody and the file reader (which apply the same check).
TEST(FuzzRegressions, InertiaWithAMomentLostInRoundingIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));

  PfxRigidBody body;
  body.reset();
  body.setMass(1);
  PfxMatrix3 inertia = PfxMatrix3::Zero();
  inertia.diagonal() = PfxVector3(0.00166667f, 0.0308333f, 1.41047e-38f);
  body.setInertia(inertia);
  EXPECT_FALSE(body.isValid());
  PfxRigidState state;
  state.reset();
  const PfxShape shape = pfxMakeShape(PfxBox(0.5f, 0.1f, 0.1f));
  EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);
  const PfxMatrix3 before = world.getRigidBody(kept).getInertia();
  EXPECT_EQ(world.setRigidBody(kept, body), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getRigidBody(kept).getInertia(), before);

  // A thin rod, its smallest moment a millionth of the largest, is still a body.
  inertia.diagonal() = PfxVector3(1e-6f, 1, 1);
  body.setInertia(inertia);
  EXPECT_TRUE(body.isValid());
  EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_OK);
}

// fuzz_world_file: a saved world whose shape sat at an offset of -3.4e38 m (finite, so it
// was read) had a bounding box that overflowed to infinity, and the loaded world's first
// step failed in the broad phase. A shape whose bounds are not finite is refused now by
// PfxShape::validate, which addRigidBody and the file reader apply.
TEST(FuzzRegressions, ShapeWhoseBoundsOverflowIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxShape shape = pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f));
  shape.setOffsetPosition(PfxVector3(-kLargestFloat, 0, 0));
  EXPECT_EQ(shape.validate(), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxAddBody(world, shape, PfxBodyInit()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 0u);

  shape.setOffsetPosition(PfxVector3(-1e6f, 0, 0));
  EXPECT_EQ(shape.validate(), PFX_OK);
}

namespace {

// A bar 0.8 m long on a hinge about Z at its end, on a fixed body; returns the bar.
PfxUInt32 addPendulum(PfxWorld& world, PfxUInt32* jointId) {
  PfxBodyInit fixed;
  fixed.position = PfxVector3(1, 2, 0);
  fixed.motionType = kPfxMotionTypeFixed;
  PfxUInt32 anchor = 0, bar = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.05))), fixed, &anchor), PFX_OK);
  PfxBodyInit swinging;
  swinging.position = PfxVector3(PfxFloat(1.4), 2, 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.4f, 0.05f, 0.05f)), swinging, &bar), PFX_OK);
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = fixed.position;
  PfxJoint joint;
  EXPECT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(anchor), world.getRigidState(bar),
                                    hinge),
            PFX_OK);
  EXPECT_EQ(world.addJoint(joint, jointId), PFX_OK);
  return bar;
}

// Saves `world`, writes `replacement` over the first real in the file (or from the start
// of `section`'s payload) equal to `value` (a value the test made unique there), reseals the
// checksum and loads the file into `loaded`.
PfxInt32 loadWithValueReplaced(const PfxWorld& world, PfxFloat value, PfxFloat replacement,
                               PfxWorld& loaded, std::string& error,
                               const char* section = nullptr) {
  Bytes bytes = saveWorld(world);
  const PfxUInt8* wanted = reinterpret_cast<const PfxUInt8*>(&value);
  const auto from = bytes.begin() + (section ? sectionPayload(bytes, section) : 0);
  const auto at = std::search(from, bytes.end(), wanted, wanted + sizeof value);
  if (at == bytes.end()) {
    ADD_FAILURE() << "the saved world holds no " << value;
    return PFX_OK;
  }
  std::memcpy(&*at, &replacement, sizeof replacement);
  resealChecksum(bytes);
  PfxSerializedMeshes meshes;
  return loadWorld(loaded, meshes, bytes, &error);
}

// Initializes `world` with a fixed ground box whose top is at y = 0; returns its id.
PfxUInt32 initializeWithGround(PfxWorld& world) {
  EXPECT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, PfxFloat(-0.5), 0);
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(2, 0.5f, 2)), ground, &id), PFX_OK);
  return id;
}

// A file of `world` with `value` replaced is refused by the reader with `code`, the error
// naming `detail`, and nothing is loaded.
void expectFileRefused(const PfxWorld& world, PfxFloat value, PfxFloat replacement,
                       const char* detail, const char* section = nullptr,
                       PfxInt32 code = PFX_ERR_INVALID_VALUE) {
  PfxWorld loaded;
  std::string error;
  EXPECT_EQ(loadWithValueReplaced(world, value, replacement, loaded, error, section), code);
  EXPECT_NE(error.find(detail), std::string::npos) << error;
  EXPECT_EQ(loaded.getNumRigidBodies(), 0u);
}

}  // namespace

// fuzz_world_file: a saved pendulum whose joint row carried an impulse of 2.3e15 N s (a
// velocity's square is still finite there) turned NaN in its first step: the joint's
// geometric stiffness added the impulse times the arm to the bar's inertia, and the joint
// tree solver's factors of that inertia overflowed. The extra inertia is bounded now, and a
// bar flung as fast steps to finite states (off its hinge: at 1e15 m/s the rounding of the
// velocities alone is metres per step).
TEST(FuzzRegressions, JointedBarFlungAtHugeSpeedStepsToFiniteStates) {
  for (const PfxFloat speed : {PfxFloat(2e15), PfxFloat(1e18)}) {
    PfxWorld world;
    ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    PfxUInt32 jointId = 0;
    const PfxUInt32 bar = addPendulum(world, &jointId);
    PfxRigidState state = world.getRigidState(bar);
    state.setLinearVelocity(PfxVector3(speed, speed, 0));
    ASSERT_EQ(world.setRigidState(bar, state), PFX_OK);
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(world.step(), PFX_OK);
      ASSERT_TRUE(world.getRigidState(bar).isValid()) << speed << " m/s, step " << i;
    }
  }
}

// fuzz_world_file: a saved joint row whose impulse was 1e200 N s (read into float as 3.4e38,
// finite, so it was accepted) made the pendulum's velocities infinite when the first step
// warm started with it. A row impulse whose square overflows, the rule of body velocities,
// is refused now: by the file reader for every saved row, and by pfxCheckJoint, which
// addJoint and setJoint apply (a joint passes its rows' impulses on).
TEST(FuzzRegressions, WarmStartImpulseWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxUInt32 jointId = 0;
  addPendulum(world, &jointId);
  ASSERT_EQ(world.step(), PFX_OK);
  const PfxJoint before = world.getJoint(jointId);
  PfxJoint flung = before;
  flung.m_constraints[kPfxJointAxisY].m_constraintRow.m_accumImpulse = kLargestFloat;
  EXPECT_EQ(pfxCheckJoint(flung), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setJoint(jointId, flung), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.addJoint(flung), PFX_ERR_INVALID_VALUE);
  flung = before;
  flung.m_constraints[kPfxJointAxisTwist].m_driveRow.m_accumImpulse = -kLargestFloat;
  EXPECT_EQ(world.setJoint(jointId, flung), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumJoints(), 1u);
  EXPECT_EQ(world.getJoint(jointId).m_constraints[kPfxJointAxisY].m_constraintRow.m_accumImpulse,
            before.m_constraints[kPfxJointAxisY].m_constraintRow.m_accumImpulse);

  // A file carrying such an impulse is refused by the reader, with the row named.
  PfxWorld saved;
  ASSERT_EQ(saved.initialize(PfxWorldParam()), PFX_OK);
  addPendulum(saved, &jointId);
  ASSERT_EQ(saved.step(), PFX_OK);
  // The impulse is the last real of the Y row's constraint row; found by its value.
  const PfxFloat impulse =
      saved.getJoint(jointId).m_constraints[kPfxJointAxisY].m_constraintRow.m_accumImpulse;
  ASSERT_NE(impulse, 0);
  expectFileRefused(saved, impulse, kLargestFloat, "constraintRow: has an impulse of");
}

// fuzz_world_file: a saved hinge whose anchor in its first body was 3.4e38 m away (finite,
// so it was accepted) turned the pendulum's position NaN in the first step, the position
// correction pulling the bar to that anchor. An anchor whose squared length overflows is
// refused now, by pfxCheckJoint (addJoint, setJoint and the file reader).
TEST(FuzzRegressions, JointAnchorWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxUInt32 jointId = 0;
  addPendulum(world, &jointId);
  const PfxJoint before = world.getJoint(jointId);
  PfxJoint faraway = before;
  faraway.m_anchorA.z() = -kLargestFloat;
  EXPECT_EQ(pfxCheckJoint(faraway), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setJoint(jointId, faraway), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.addJoint(faraway), PFX_ERR_INVALID_VALUE);
  faraway = before;
  faraway.m_anchorB.x() = kLargestFloat / 2;
  EXPECT_EQ(world.setJoint(jointId, faraway), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumJoints(), 1u);
  EXPECT_EQ(world.getJoint(jointId).m_anchorA, before.m_anchorA);
  EXPECT_EQ(world.getJoint(jointId).m_anchorB, before.m_anchorB);
  // An anchor far away but with a finite square is still taken, and the bar steps finitely.
  faraway = before;
  faraway.m_anchorA.z() = PfxFloat(-1e18);
  ASSERT_EQ(world.setJoint(jointId, faraway), PFX_OK);
  for (int step = 0; step < 10; ++step) ASSERT_EQ(world.step(), PFX_OK);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    EXPECT_TRUE(world.getRigidState(id).isValid()) << "body " << id;
  }

  // A file carrying such an anchor is refused by the reader.
  PfxWorld saved;
  ASSERT_EQ(saved.initialize(PfxWorldParam()), PFX_OK);
  addPendulum(saved, &jointId);
  PfxJoint marked = saved.getJoint(jointId);
  const PfxFloat mark = PfxFloat(123.25);  // a value the file holds nowhere else
  marked.m_anchorA.z() = mark;
  ASSERT_EQ(saved.setJoint(jointId, marked), PFX_OK);
  expectFileRefused(saved, mark, kLargestFloat, "joint 0");
}

// fuzz_world_api: a body of 1.4e-45 kg (positive and finite, so it was accepted) had an
// infinite inverse mass, and gravity made it NaN in its first step. Masses and principal
// moments of inertia outside [kPfxMinMass, kPfxMaxMass] and [kPfxMinMoment, kPfxMaxMoment]
// are refused now, by PfxRigidBody::isValid (addRigidBody, setRigidBody, the file reader and
// the loaders).
TEST(FuzzRegressions, MassOrMomentOutOfRangeIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));
  const PfxRigidBody before = world.getRigidBody(kept);
  PfxRigidState state;
  state.reset();
  const PfxShape shape = pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f));

  const PfxFloat tooLight = std::numeric_limits<PfxFloat>::denorm_min();
  const PfxFloat badMasses[] = {tooLight, std::numeric_limits<PfxFloat>::min(),
                                kPfxMinMass / 2, kPfxMaxMass * 2, kLargestFloat};
  for (const PfxFloat mass : badMasses) {
    PfxRigidBody body = before;
    body.setMass(mass);
    EXPECT_FALSE(body.isValid()) << mass;
    EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_ERR_INVALID_VALUE) << mass;
    EXPECT_EQ(world.setRigidBody(kept, body), PFX_ERR_INVALID_VALUE) << mass;
  }
  for (const PfxFloat moment : {kPfxMinMoment / 2, kPfxMaxMoment * 2}) {
    PfxRigidBody body = before;
    body.setInertia(PfxMatrix3::Identity() * moment);
    EXPECT_FALSE(body.isValid()) << moment;
    EXPECT_EQ(world.setRigidBody(kept, body), PFX_ERR_INVALID_VALUE) << moment;
  }
  EXPECT_EQ(world.getNumRigidBodies(), 1u);
  EXPECT_EQ(world.getRigidBody(kept).getMass(), before.getMass());
  EXPECT_EQ(world.getRigidBody(kept).getInertia(), before.getInertia());

  // The ends of the ranges are bodies, and the lightest one falls under gravity finitely.
  for (const PfxFloat mass : {kPfxMinMass, kPfxMaxMass}) {
    PfxRigidBody body = before;
    body.setMass(mass);
    body.setInertia(PfxMatrix3::Identity() * (mass == kPfxMinMass ? kPfxMinMoment : kPfxMaxMoment));
    EXPECT_TRUE(body.isValid()) << mass;
    ASSERT_EQ(world.setRigidBody(kept, body), PFX_OK) << mass;
    ASSERT_EQ(world.step(), PFX_OK);
    EXPECT_TRUE(world.getRigidState(kept).isValid()) << mass;
  }
}

// fuzz_world_file: a saved world whose hinged bar carried a pending force of -1.7e38 N
// (finite, so it was read) turned two coupled pendulums NaN in the first step: the force
// gave the bar 2.8e36 m/s, and the joint solver squared that. Stage (1) cuts a body's speeds
// to kPfxMaxLinearSpeed and kPfxMaxAngularSpeed now (forming them in long double when float
// would overflow on the way), and applyForce refuses a call whose sum with the earlier ones
// overflows.
TEST(FuzzRegressions, HugeForceOnALightBodyIsCutToTheSpeedLimit) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxUInt32 jointId = 0;
  const PfxUInt32 bar = addPendulum(world, &jointId);
  const PfxUInt32 free = addSphere(world, PfxVector3(5, 2, 0));
  PfxRigidBody light = world.getRigidBody(free);
  light.setMass(kPfxMinMass);
  light.setInertia(PfxMatrix3::Identity() * kPfxMinMoment);
  ASSERT_EQ(world.setRigidBody(free, light), PFX_OK);

  const PfxVector3 huge(-kLargestFloat * PfxFloat(0.6), kLargestFloat * PfxFloat(0.6), 0);
  ASSERT_EQ(world.applyForce(bar, huge, huge), PFX_OK);
  ASSERT_EQ(world.applyForce(free, huge, huge), PFX_OK);
  // A second call would overflow the sum: refused, the first kept.
  EXPECT_EQ(world.applyForce(free, huge, PfxVector3::Zero()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.applyForce(free, PfxVector3::Zero(), huge), PFX_ERR_INVALID_VALUE);

  ASSERT_EQ(world.step(), PFX_OK);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    ASSERT_TRUE(world.getRigidState(id).isValid()) << "body " << id;
  }
  // The free body moved only by the force: cut to the limit, along the force.
  const PfxRigidState& flung = world.getRigidState(free);
  EXPECT_NEAR(flung.getLinearVelocity().norm(), kPfxMaxLinearSpeed, kPfxMaxLinearSpeed * 1e-3);
  EXPECT_NEAR(flung.getLinearVelocity().normalized().dot(huge.stableNormalized()), 1, 1e-3);
  EXPECT_NEAR(flung.getAngularVelocity().norm(), kPfxMaxAngularSpeed, kPfxMaxAngularSpeed * 1e-3);
  for (int step = 0; step < 30; ++step) {
    ASSERT_EQ(world.applyForce(free, huge, huge), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      ASSERT_TRUE(world.getRigidState(id).isValid()) << "body " << id << ", step " << step;
    }
  }
}

// fuzz_world_api: a fixed body given an inertia of -inf by setRigidBody was accepted (the
// mass properties of a body forces do not move were not checked), and the world could no
// longer be saved. Every body's mass and inertia must be finite now.
TEST(FuzzRegressions, FixedBodyWithInfiniteInertiaIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit fixed;
  fixed.motionType = kPfxMotionTypeFixed;
  PfxUInt32 id = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(1, 0.1f, 1)), fixed, &id), PFX_OK);
  const PfxRigidBody before = world.getRigidBody(id);
  PfxRigidBody body = before;
  PfxMatrix3 inertia = body.getInertia();
  inertia(1, 1) = -std::numeric_limits<PfxFloat>::infinity();
  body.setInertia(inertia);
  EXPECT_EQ(world.setRigidBody(id, body), PFX_ERR_INVALID_VALUE);
  body = before;
  body.setMass(std::numeric_limits<PfxFloat>::quiet_NaN());
  EXPECT_EQ(world.setRigidBody(id, body), PFX_ERR_INVALID_VALUE);
  PfxRigidState state;
  state.reset();
  state.setMotionType(kPfxMotionTypeFixed);
  const PfxShape shape = pfxMakeShape(PfxSphere(1));
  EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);
  EXPECT_EQ(world.getRigidBody(id).getInertia(), before.getInertia());
  EXPECT_FALSE(saveWorld(world).empty());
}

// fuzz_world_api (the CI stage, seed 1): a keyframe body sent to a target whose move over the
// step was 6e21 m/s (finite, so it was taken) had a velocity whose square overflows, which
// PfxRigidState::isValid refuses everywhere else. pfxSetKeyframeTarget (and so
// PfxWorld::setKeyframeTarget) refuses such a move now, the state unchanged.
TEST(FuzzRegressions, KeyframeMoveWhoseSpeedSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit init;
  init.motionType = kPfxMotionTypeKeyframe;
  PfxUInt32 id = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.1f, 0.5f)), init, &id), PFX_OK);
  ASSERT_EQ(world.setKeyframeTarget(id, PfxVector3(0, 1, 0), PfxQuat::Identity()), PFX_OK);
  const PfxRigidState before = world.getRigidState(id);

  // Its speed over a step of 1/60 s is 60 times the square root of the largest number.
  const PfxVector3 farAway(-std::sqrt(kLargestFloat), 0, 0);
  EXPECT_EQ(world.setKeyframeTarget(id, farAway, PfxQuat::Identity()), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(id), before));
  PfxRigidState state = before;
  EXPECT_EQ(pfxSetKeyframeTarget(state, farAway, PfxQuat::Identity(), PfxFloat(1) / 60),
            PFX_ERR_INVALID_VALUE);
  // A quarter turn over a step so short that its rate's square overflows.
  const PfxQuat turned(Eigen::AngleAxis<PfxFloat>(PfxFloat(1.5707963), PfxVector3::UnitY()));
  EXPECT_EQ(pfxSetKeyframeTarget(state, before.getPosition(), turned,
                                 std::numeric_limits<PfxFloat>::min()),
            PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(state, before));

  // A move beyond the speed limit of a body forces do not move is refused too (issue 19's
  // fixed bodies); one at 6e4 m/s is taken and steps to finite states.
  EXPECT_EQ(world.setKeyframeTarget(id, PfxVector3(1e6f, 0, 0), turned), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(id), before));
  ASSERT_EQ(world.setKeyframeTarget(id, PfxVector3(1e3f, 0, 0), turned), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(world.getRigidState(id).isValid());
}

// fuzz_world_file: a saved contact whose normal was (3.4e38, 1, 0) (a double file's value
// beyond float read as the largest float) was read, and the refresh and the solver took it as
// it was: its bodies turned NaN in the first step. The reader now needs a contact normal of
// unit length and names the point.
TEST(FuzzRegressions, SavedContactNormalNotOfUnitLengthIsRefused) {
  PfxWorld saved;
  ASSERT_EQ(saved.initialize(PfxWorldParam()), PFX_OK);
  PfxBodyInit slope;
  slope.motionType = kPfxMotionTypeFixed;
  slope.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(PfxFloat(-0.3), PfxVector3::UnitZ()));
  ASSERT_EQ(pfxAddBody(saved, pfxMakeShape(PfxBox(2, 0.1f, 2)), slope), PFX_OK);
  const PfxVector3 up = slope.orientation * PfxVector3::UnitY();
  addSphere(saved, up * PfxFloat(0.59));
  ASSERT_EQ(saved.step(), PFX_OK);
  ASSERT_GT(saved.getNumContactPairs(), 0u);
  const PfxContactManifold& manifold = saved.getContactManifold(saved.getContactPair(0));
  ASSERT_GT(manifold.getNumContacts(), 0u);
  const PfxFloat normalX = manifold.getContactPoint(0).m_constraintRow[0].m_normal.x();
  ASSERT_GT(std::abs(normalX), PfxFloat(0.2));  // a value nothing saved before it holds

  expectFileRefused(saved, normalX, kLargestFloat, "the contact normal is not of unit length");
}

// fuzz_world_file: a fixed body saved at y = 3.4e38 m (finite, so read) pulled the body
// jointed to it to NaN in the first step. PfxRigidState::isValid (addRigidBody,
// setRigidState, the file reader) now needs the position's square finite too, the rule of
// body velocities.
TEST(FuzzRegressions, PositionWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));
  const PfxRigidState before = world.getRigidState(kept);
  PfxRigidState state = before;
  state.setPosition(PfxVector3(1, kLargestFloat, 0));
  EXPECT_FALSE(state.isValid());
  EXPECT_EQ(world.setRigidState(kept, state), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(kept), before));
  PfxBodyInit far;
  far.motionType = kPfxMotionTypeFixed;
  far.position = PfxVector3(1, kLargestFloat, 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(1)), far), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);
}

// A saved hinge whose limits or drive target were 3.4e38 (a double file's value beyond float
// read as the largest float; finite, so taken) formed errors and velocities from them that
// overflowed, and the pendulum turned NaN in the first step. pfxCheckJoint (addJoint,
// setJoint, the file reader) needs the limits and the drive target to have finite squares
// now, the rule of body velocities; the force limit may still be the largest float (none).
TEST(FuzzRegressions, JointLimitOrDriveTargetWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxUInt32 jointId = 0;
  addPendulum(world, &jointId);
  const PfxJoint before = world.getJoint(jointId);
  PfxJoint driven = before;
  PfxJointConstraint& twist = driven.m_constraints[kPfxJointAxisTwist];
  twist.m_drive = kPfxJointDriveVelocity;
  twist.m_driveTarget = kLargestFloat;
  twist.m_driveMaxForce = kLargestFloat;
  EXPECT_EQ(pfxCheckJoint(driven), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.setJoint(jointId, driven), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.addJoint(driven), PFX_ERR_INVALID_VALUE);
  PfxJoint limited = before;
  PfxJointConstraint& slide = limited.m_constraints[kPfxJointAxisX];
  slide.m_lock = kPfxJointLockLimit;
  slide.m_movableLowerLimit = -kLargestFloat;
  slide.m_movableUpperLimit = 1;
  EXPECT_EQ(world.setJoint(jointId, limited), PFX_ERR_INVALID_VALUE);
  slide.m_movableLowerLimit = slide.m_movableUpperLimit = kLargestFloat;
  EXPECT_EQ(world.setJoint(jointId, limited), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumJoints(), 1u);
  EXPECT_EQ(world.getJoint(jointId).m_constraints[kPfxJointAxisX].m_lock,
            before.m_constraints[kPfxJointAxisX].m_lock);
  EXPECT_EQ(world.getJoint(jointId).m_constraints[kPfxJointAxisTwist].m_drive,
            before.m_constraints[kPfxJointAxisTwist].m_drive);

  // A file carrying such a target is refused by the reader, with the joint named.
  const PfxFloat mark = PfxFloat(123.25);  // a value the file holds nowhere else
  twist.m_driveTarget = mark;
  ASSERT_EQ(world.setJoint(jointId, driven), PFX_OK);
  expectFileRefused(world, mark, kLargestFloat, "joint 0");
}

// Within that rule a joint may still ask for more than a body can take: a position drive
// 1e18 m or rad from its target with no force limit asked for 6e19 m/s, and an effort of
// 1e18 N on a bar of 1e-12 kg made 1.7e28 m/s; both turned the pendulum NaN. The velocity a
// joint row aims for, and what an effort adds to a velocity, are cut to kPfxMaxLinearSpeed
// and kPfxMaxAngularSpeed now, as stage (1) cuts a force's.
TEST(FuzzRegressions, JointDrivesAndLimitsFarAwayStepToFiniteStates) {
  const PfxFloat far = PfxFloat(1e18);
  for (const PfxUInt32 axis : {PfxUInt32(kPfxJointAxisX), PfxUInt32(kPfxJointAxisTwist)}) {
    for (const PfxUInt8 drive : {PfxUInt8(kPfxJointDriveVelocity),
                                 PfxUInt8(kPfxJointDrivePosition), PfxUInt8(kPfxJointDriveEffort),
                                 PfxUInt8(kPfxJointDriveNone)}) {
      PfxWorld world;
      ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
      PfxUInt32 jointId = 0;
      const PfxUInt32 bar = addPendulum(world, &jointId);
      PfxRigidBody light = world.getRigidBody(bar);
      light.setMass(kPfxMinMass);
      light.setInertia(PfxMatrix3::Identity() * kPfxMinMoment);
      ASSERT_EQ(world.setRigidBody(bar, light), PFX_OK);
      PfxJoint joint = world.getJoint(jointId);
      PfxJointConstraint& c = joint.m_constraints[axis];
      c.m_lock = kPfxJointLockFree;
      c.m_drive = drive;
      c.m_driveTarget = far;
      c.m_driveMaxForce = kLargestFloat;
      if (drive == kPfxJointDriveNone) {  // a limit far away, the axis held at it
        c.m_lock = kPfxJointLockLimit;
        c.m_movableLowerLimit = c.m_movableUpperLimit = far;
      }
      ASSERT_EQ(world.setJoint(jointId, joint), PFX_OK);
      for (int step = 0; step < 3; ++step) {
        ASSERT_EQ(world.step(), PFX_OK);
        ASSERT_TRUE(world.getRigidState(bar).isValid())
            << "axis " << axis << ", drive " << int(drive) << ", step " << step;
      }
    }
  }
}

namespace {

// The pair fuzz_world_api found EPA unable to settle: a cylinder 1,560 km long and as wide
// (half-length and radius 780,859.375 m, the fuzz target's decoded reals), turned 1.8e-4 rad
// about y, around shapes of a metre 69.5 m from its centre along its axis. The way out
// through the near cap is 65 m shorter than through the side, less than 0.01 % of the
// depth: on a difference this round EPA would need thousands of faces to tell them apart,
// and it stops at its budget (124 steps, 128 vertices) from both of its starts, for each
// triangle of a mesh. Each step tested every face and matched each removed edge against
// the horizon found so far; a query of 96 triangles ran past 10 s under
// AddressSanitizer on a loaded machine.
const PfxFloat kHugeCylinderSize = PfxFloat(780859.375);

PfxTransform3 hugeCylinderPose() {
  return pfxMakeTransform(PfxQuat(Eigen::AngleAxis<PfxFloat>(PfxFloat(-1.8e-4), PfxVector3::UnitY())),
                          PfxVector3::Zero());
}

// How far the shapes overlap along the unit normal n (from A to B), from their support
// points sampled on the surfaces the contact names: pushing B by this much along n
// separates them.
PfxFloat overlapAlong(const PfxVector3& n, const PfxVector3& boxCentre, const PfxVector3& half,
                      const PfxTransform3& cylinderPose) {
  const PfxFloat boxReach = n.dot(boxCentre) + half.dot(n.cwiseAbs());
  const PfxVector3 local = cylinderPose.linear().transpose() * n;
  const PfxFloat cylinderReach = -n.dot(cylinderPose.translation()) +
                                 kHugeCylinderSize * std::abs(local.x()) +
                                 kHugeCylinderSize * std::hypot(local.y(), local.z());
  return boxReach + cylinderReach;
}

}  // namespace

// The pair itself: a box of a metre where the mesh's triangles lay, against the cylinder.
// The contact must be sound: pushing the cylinder by the reported depth along the
// reported normal separates the shapes, and the depth is within 1 % of the push along the
// cap's normal (65 m less than the side's; EPA's budget ends 69 m above it, a face
// from early in its growth would be several per cent).
TEST(FuzzRegressions, BoxDeepInsideAHugeCylinderGetsASoundContact) {
  const PfxVector3 half = PfxVector3::Constant(PfxFloat(0.5));
  const PfxVector3 boxCentre(PfxFloat(-69.5), PfxFloat(0.3), PfxFloat(-0.7));
  const PfxTransform3 cylinderPose = hugeCylinderPose();
  PfxContactCandidate out[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 n = pfxContactConvexShapes(
      pfxMakeShape(PfxBox(half)), pfxMakeTransform(PfxQuat::Identity(), boxCentre),
      pfxMakeShape(PfxCylinder(kHugeCylinderSize, kHugeCylinderSize)), cylinderPose,
      PfxFloat(0.0063), out, PFX_MAX_CONTACT_CANDIDATES);
  ASSERT_GE(n, 1u);
  const PfxVector3 capNormal = cylinderPose.linear() * PfxVector3::UnitX();
  const PfxFloat capPush = overlapAlong(capNormal, boxCentre, half, cylinderPose);
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactCandidate& c = out[i];
    ASSERT_TRUE(pfxIsFinite(c.m_normal) && pfxIsFinite(c.m_pointA) && pfxIsFinite(c.m_pointB) &&
                std::isfinite(c.m_distance));
    EXPECT_NEAR(c.m_normal.norm(), 1, 1e-5);
    // Float rounding at 780 km is 0.06 m; the tolerances below are a few of those.
    EXPECT_LE(overlapAlong(c.m_normal, boxCentre, half, cylinderPose), -c.m_distance + 1)
        << "contact " << i << " does not separate the shapes";
    EXPECT_LE(-c.m_distance, capPush * PfxFloat(1.01)) << "contact " << i;
  }
}

// The query as fuzz_world_api made it: the cylinder against a static mesh like the fuzz
// target's ground (4 x 4 cells of a metre, heights up to 0.4 m; the input had it three
// times over on one body) turned a third of a turn about (1, 1, 1). Every contact is
// finite with a unit normal and overlaps, by no more than the cylinder's whole length.
TEST(FuzzRegressions, QueryOfAHugeCylinderAroundAMeshGivesSoundContacts) {
  const pfx_test::MeshSource grid =
      pfx_test::makeHeightField(4, 4, 1, [](PfxFloat x, PfxFloat z) {
        return PfxFloat(int(x * 7 + z * 3 + 20) % 5) * PfxFloat(0.1);
      });
  pfx_test::MeshOwner ground;
  ASSERT_EQ(pfxCreateLargeTriMesh(ground.mesh,
                                  grid.param(PFX_MESH_FLAG_USE_BVH, PfxFloat(0.002))),
            PFX_OK);

  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxShape meshShape;
  meshShape.reset();
  meshShape.setLargeTriMesh(&ground.mesh);
  PfxBodyInit init;
  init.motionType = kPfxMotionTypeFixed;
  init.mass = 0;
  init.position = PfxVector3(PfxFloat(-69.5), 0, 0);
  init.orientation = PfxQuat(PfxFloat(0.5), PfxFloat(0.5), PfxFloat(0.5), PfxFloat(0.5));
  ASSERT_EQ(pfxAddBody(world, meshShape, init), PFX_OK);

  PfxCollidable cylinder;
  cylinder.reset();
  ASSERT_EQ(cylinder.addShape(pfxMakeShape(PfxCylinder(kHugeCylinderSize, kHugeCylinderSize))),
            PFX_OK);
  ASSERT_EQ(cylinder.finish(), PFX_OK);
  PfxContactQueryInput query;
  query.collidable = &cylinder;
  query.transform = hugeCylinderPose();
  query.contactThreshold = PfxFloat(0.0063);
  PfxQueryContact out[8];
  PfxQueryContactsResult result;
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  ASSERT_GE(result.numContacts, 1u);
  ASSERT_LE(result.numContacts, 8u);
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    const PfxContactCandidate& c = out[i].m_contact;
    ASSERT_TRUE(pfxIsFinite(c.m_normal) && pfxIsFinite(c.m_pointA) && pfxIsFinite(c.m_pointB) &&
                std::isfinite(c.m_distance));
    EXPECT_NEAR(c.m_normal.norm(), 1, 1e-5);
    EXPECT_LT(c.m_distance, 0) << "contact " << i;
    EXPECT_GT(c.m_distance, -2 * kHugeCylinderSize) << "contact " << i;
  }
}

// fuzz_world_file: a saved world whose resting sphere's radius was 3.5e12 m (finite, so it
// was read) overlapped every body near it by as much, and three bodies turned NaN in the
// first step: in float, the lever arms of such contacts round by hundreds of kilometres,
// and the split impulses that pushed along them overflowed. A shape whose bounds reach
// beyond kPfxMaxShapeReach from its body's origin is refused now by PfxShape::validate,
// which addRigidBody and the file reader apply; one that reaches that far steps to finite
// states with bodies buried deep inside it.
TEST(FuzzRegressions, ShapeReachingTooFarIsRefusedWithNothingChanged) {
  PfxWorld world;
  initializeWithGround(world);
  const PfxFloat radius = PfxFloat(0.2345);  // unique in the saved file
  PfxBodyInit resting;  // dropped, so that its height is not the radius
  resting.position = PfxVector3(-1, PfxFloat(0.3), 1);
  PfxUInt32 sphere = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(radius)), resting, &sphere), PFX_OK);
  PfxUInt32 jointId = 0;
  addPendulum(world, &jointId);
  for (int step = 0; step < 30; ++step) ASSERT_EQ(world.step(), PFX_OK);

  const PfxFloat fuzzedRadius = PfxFloat(3.5e12);
  EXPECT_EQ(pfxMakeShape(PfxSphere(fuzzedRadius)).validate(), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(fuzzedRadius)), PfxBodyInit()),
            PFX_ERR_INVALID_VALUE);
  PfxShape reachingOut = pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f));
  reachingOut.setOffsetPosition(PfxVector3(0, 0, PfxFloat(1.5) * kPfxMaxShapeReach));
  EXPECT_EQ(reachingOut.validate(), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 4u);  // the ground, the sphere, the pendulum's two

  expectFileRefused(world, radius, fuzzedRadius, "PfxShape::validate");

  // A sphere reaching exactly that far, around the ground, the pendulum and its own centre.
  PfxWorld largest;
  std::string error;
  ASSERT_EQ(loadWithValueReplaced(world, radius, kPfxMaxShapeReach, largest, error), PFX_OK)
      << error;
  for (int step = 0; step < 5; ++step) {
    ASSERT_EQ(largest.step(), PFX_OK);
    for (PfxUInt32 id = 0; id < largest.getNumRigidBodies(); ++id) {
      ASSERT_TRUE(largest.getRigidState(id).isValid()) << "body " << id << ", step " << step;
    }
  }
}

// fuzz_world_file: a saved world whose resting box's contact point with the ground lay
// 6.3e29 m from the ground's origin (finite, so it was read), and whose hinge had been
// moved onto that box, turned the box and both coupled pendulums NaN in the first step: the
// point's lever arm had an overflowing square in the contact's effective mass. The reader
// now refuses a contact point farther than kPfxMaxShapeReach from its body, as no shape
// reaches.
TEST(FuzzRegressions, SavedContactPointBeyondAnyShapeIsRefused) {
  PfxWorld world;
  const PfxUInt32 groundId = initializeWithGround(world);
  PfxBodyInit resting;
  resting.position = PfxVector3(-1, PfxFloat(0.2), 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f)), resting), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  ASSERT_EQ(world.getNumContactPairs(), 1u);
  const PfxConstraintPair& pair = world.getContactPair(0);
  ASSERT_GT(world.getContactManifold(pair).getNumContacts(), 0u);
  const PfxContactPoint& point = world.getContactManifold(pair).getContactPoint(0);
  const bool groundIsA = pfxGetObjectIdA(pair) == groundId;
  const PfxFloat onGroundX = (groundIsA ? point.m_localPointA : point.m_localPointB).x();
  expectFileRefused(world, onGroundX, PfxFloat(6.3e29),
                    groundIsA ? "localPointA" : "localPointB", "CONT", PFX_ERR_OUT_OF_RANGE);
}

namespace {

// Steps `world` `steps` times; every body must stay valid.
void expectStepsFinite(PfxWorld& world, int steps) {
  for (int step = 0; step < steps; ++step) {
    ASSERT_EQ(world.step(), PFX_OK);
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      ASSERT_TRUE(world.getRigidState(id).isValid()) << "body " << id << ", step " << step;
    }
  }
}

}  // namespace

// fuzz_world_file (issue 19's search of a saved world): the fixed ground saved moving at
// 5.8e17 m/s, or a hinged bar's fixed base turning at 1e19 rad/s (their squares finite, so
// read), turned the bodies on it or jointed to it NaN in the first step: stage (1) cuts the
// speeds of the bodies forces move, but the solver took the others' as they were. A body
// forces do not move must now be given speeds within kPfxMaxLinearSpeed and
// kPfxMaxAngularSpeed (PfxRigidState::isValid: addRigidBody, setRigidState, the file
// reader; pfxSetKeyframeTarget), and at those speeds the world steps to finite states.
TEST(FuzzRegressions, FixedBodyBeyondTheSpeedLimitIsRefusedWithNothingChanged) {
  PfxWorld world;
  const PfxUInt32 ground = initializeWithGround(world);
  PfxUInt32 jointId = 0;
  const PfxUInt32 bar = addPendulum(world, &jointId);
  const PfxUInt32 base = world.getJoint(jointId).m_rigidBodyIdA;

  PfxRigidState fuzzed = world.getRigidState(ground);
  fuzzed.setLinearVelocity(PfxVector3(0, PfxFloat(5.8e17), 0));
  EXPECT_FALSE(fuzzed.isValid());
  const PfxRigidState groundBefore = world.getRigidState(ground);
  EXPECT_EQ(world.setRigidState(ground, fuzzed), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(ground), groundBefore));
  fuzzed = world.getRigidState(base);
  fuzzed.setAngularVelocity(PfxVector3(PfxFloat(1e19), 0, 0));
  const PfxRigidState baseBefore = world.getRigidState(base);
  EXPECT_EQ(world.setRigidState(base, fuzzed), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(base), baseBefore));
  PfxBodyInit spinningFixed;
  spinningFixed.motionType = kPfxMotionTypeFixed;
  spinningFixed.angularVelocity = PfxVector3(0, PfxFloat(1e19), 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.1))), spinningFixed),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 3u);
  // A keyframe move that fast is refused too.
  PfxRigidState keyframe = world.getRigidState(base);
  keyframe.setMotionType(kPfxMotionTypeKeyframe);
  EXPECT_EQ(pfxSetKeyframeTarget(keyframe, PfxVector3(1e5f, 0, 0), keyframe.getOrientation(),
                                 PfxFloat(1) / 60),
            PFX_ERR_INVALID_VALUE);

  // The saved ground moving at 5.8e17 m/s is refused by the reader.
  const PfxFloat groundSpeed = PfxFloat(0.4375);  // unique in the saved file
  PfxRigidState moving = groundBefore;
  moving.setLinearVelocity(PfxVector3(0, groundSpeed, 0));
  ASSERT_EQ(world.setRigidState(ground, moving), PFX_OK);
  expectFileRefused(world, groundSpeed, PfxFloat(5.8e17), "kPfxMaxLinearSpeed");

  // At the limits, the bar on its turning base and a box on the moving ground stay finite.
  PfxBodyInit box;
  box.position = PfxVector3(-1, PfxFloat(0.1), 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), box), PFX_OK);
  moving.setLinearVelocity(PfxVector3(0, kPfxMaxLinearSpeed, 0));
  ASSERT_EQ(world.setRigidState(ground, moving), PFX_OK);
  PfxRigidState turning = baseBefore;
  turning.setAngularVelocity(PfxVector3(kPfxMaxAngularSpeed, 0, 0));
  ASSERT_EQ(world.setRigidState(base, turning), PFX_OK);
  expectStepsFinite(world, 20);
  EXPECT_TRUE(world.getRigidState(bar).isValid());
}

// fuzz_world_file (issue 19): a hinged bar whose saved principal moments were 7.0e3, 0.031
// and 0.031 or 0.0017, 0.031 and 7.3e-9 kg m^2 was read. Neither is a rigid body's (each
// moment is a sum of m (y^2 + z^2) and the like, so the largest is at most the sum of the
// others), and the second turned the bars NaN in the first step; so did a thin bar of
// 7.4e-9 about its length beside 0.0308 across (2 epsilon of it in float), a body, but one
// whose small moment is lost in rounding once its tensor turns. Both are refused now (PfxRigidBody::isValid, so
// addRigidBody, setRigidBody, the file reader and the loaders, which name the rule).
TEST(FuzzRegressions, InertiaOfNoRigidBodyOrLostInRoundingIsRefusedWithNothingChanged) {
  PfxWorld world;
  initializeWithGround(world);
  PfxUInt32 jointId = 0;
  const PfxUInt32 bar = addPendulum(world, &jointId);
  const PfxRigidBody before = world.getRigidBody(bar);
  const auto withMoments = [&](PfxFloat x, PfxFloat y, PfxFloat z) {
    PfxRigidBody body = before;
    PfxMatrix3 inertia = PfxMatrix3::Zero();
    inertia.diagonal() = PfxVector3(x, y, z);
    body.setInertia(inertia);
    return body;
  };
  const PfxRigidBody heavyAcross =
      withMoments(PfxFloat(7.0e3), PfxFloat(0.031), PfxFloat(0.031));
  const PfxRigidBody tiny = withMoments(PfxFloat(0.0017), PfxFloat(0.031), PfxFloat(7.3e-9));
  // 7.3e-9 kg m^2 beside 0.0308 in float: 2 epsilon of it.
  const PfxFloat across = PfxFloat(0.0308);
  const PfxFloat lostInRounding = 2 * std::numeric_limits<PfxFloat>::epsilon() * across;
  const PfxRigidBody thin = withMoments(lostInRounding, across, across);
  for (const PfxRigidBody* body : {&heavyAcross, &tiny}) {
    ASSERT_NE(body->problem(), nullptr);
    EXPECT_NE(std::string(body->problem()).find("of no rigid body"), std::string::npos)
        << body->problem();
  }
  ASSERT_NE(thin.problem(), nullptr);
  EXPECT_NE(std::string(thin.problem()).find("kPfxMinMomentRatio"), std::string::npos)
      << thin.problem();
  for (const PfxRigidBody* body : {&heavyAcross, &tiny, &thin}) {
    EXPECT_EQ(world.setRigidBody(bar, *body), PFX_ERR_INVALID_VALUE);
    EXPECT_EQ(world.getRigidBody(bar).getInertia(), before.getInertia());
    EXPECT_EQ(world.addRigidBody(world.getRigidState(bar), *body,
                                 &world.getCollidable(bar).getShape(0), 1),
              PFX_ERR_INVALID_VALUE);
  }
  EXPECT_EQ(world.getNumRigidBodies(), 3u);

  // A flat disc has the largest moment equal to the sum; moments written to three
  // significant digits may exceed it by up to 1e-2 of it: both bodies.
  EXPECT_TRUE(withMoments(PfxFloat(0.25), PfxFloat(0.25), PfxFloat(0.5)).isValid());
  EXPECT_TRUE(withMoments(PfxFloat(0.125), PfxFloat(0.125), PfxFloat(0.2525)).isValid());
  // The thinnest bar taken steps to finite states.
  ASSERT_EQ(world.setRigidBody(bar, withMoments(kPfxMinMomentRatio * across, across, across)),
            PFX_OK);
  expectStepsFinite(world, 20);

  // The saved bar made thin, then heavy across one axis.
  const PfxFloat along = PfxFloat(0.0123);  // unique in the saved file, as is `across`
  ASSERT_EQ(world.setRigidBody(bar, withMoments(along, across, across)), PFX_OK);
  expectFileRefused(world, along, lostInRounding, "kPfxMinMomentRatio");
  expectFileRefused(world, across, PfxFloat(7.0e3), "of no rigid body");
}

// fuzz_world_file (issue 19): a saved time step of 1.6e17 s (gravity over it finite, so it
// was read) turned the hinged bars NaN in their first step at two sub-steps; 1e10 s did at
// four. PfxWorldParam::timeStep is now at most PFX_MAX_TIME_STEP (100 s), refused above
// with PFX_ERR_OUT_OF_RANGE by initialize, setStepParam and the file reader, which names it.
TEST(FuzzRegressions, TimeStepAboveTheBoundIsRefusedWithNothingChanged) {
  PfxWorld world;
  PfxWorldParam param;
  param.timeStep = PfxFloat(1.6e17);
  param.subStep = 2;
  EXPECT_EQ(world.initialize(param), PFX_ERR_OUT_OF_RANGE);
  initializeWithGround(world);
  PfxUInt32 jointId = 0;
  const PfxUInt32 bar = addPendulum(world, &jointId);
  EXPECT_EQ(world.setStepParam(PfxFloat(1e10), 4, 10, PfxVector3(0, PfxFloat(-9.8), 0)),
            PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.getParam().timeStep, PfxWorldParam().timeStep);
  EXPECT_EQ(world.getParam().subStep, PfxWorldParam().subStep);

  // The longest step taken, at every sub-step count the fuzzed files asked for.
  for (const PfxUInt32 subSteps : {1u, 2u, 4u, PFX_MAX_SUB_STEPS}) {
    PfxWorld longest;
    initializeWithGround(longest);
    addPendulum(longest, &jointId);
    ASSERT_EQ(longest.setStepParam(PFX_MAX_TIME_STEP, subSteps, 10,
                                   PfxVector3(0, PfxFloat(-9.8), 0)),
              PFX_OK);
    expectStepsFinite(longest, 5);
  }

  EXPECT_TRUE(world.getRigidState(bar).isValid());
  expectFileRefused(world, PfxWorldParam().timeStep, PfxFloat(1.6e17), "timeStep", nullptr,
                    PFX_ERR_OUT_OF_RANGE);
}

// fuzz_scene: a body of two boxes in one place (4 x 5.1 x 1 and 4 x 6.1 x 1 m), placed
// through the whole height of a fixed box, turned NaN in its first step. Each of its boxes
// met the fixed one with the same depth up and down, one pushed up, the other down; the
// contact tree solver took the pair's four points for one face, and the face's first
// moment across them was no push at all, a zero row it divided by. Points whose normals
// disagree are no face now; the iterations solve them, and the body comes out.
TEST(FuzzRegressions, CompoundThroughAWallWithOpposedContactNormalsStepsToFiniteStates) {
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit wallInit;
  wallInit.mass = 0;
  wallInit.position = PfxVector3(0, 2, PfxFloat(0.5));
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(2, PfxFloat(2.55), PfxFloat(0.5))), wallInit),
            PFX_OK);
  const PfxShape shapes[2] = {pfxMakeShape(PfxBox(2, PfxFloat(2.55), PfxFloat(0.5))),
                              pfxMakeShape(PfxBox(2, PfxFloat(3.05), PfxFloat(0.5)))};
  PfxBodyInit bodyInit;
  bodyInit.mass = PfxFloat(4.5);
  bodyInit.position = PfxVector3(PfxFloat(-1.5), PfxFloat(-1.5), PfxFloat(0.5));
  PfxUInt32 body = 0;
  ASSERT_EQ(pfxAddBody(world, shapes, 2, bodyInit, &body), PFX_OK);
  bool opposed = false;
  for (int i = 0; i < 240; ++i) {
    ASSERT_EQ(world.step(), PFX_OK) << "step " << i;
    ASSERT_TRUE(world.getRigidState(body).isValid()) << "step " << i;
    for (PfxUInt32 c = 0; c < world.getNumContactPairs(); ++c) {
      const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(c));
      for (PfxUInt32 p = 1; p < manifold.getNumContacts(); ++p) {
        opposed |= manifold.getContactPoint(p).getNormal().dot(
                       manifold.getContactPoint(0).getNormal()) < 0;
      }
    }
  }
  EXPECT_TRUE(opposed) << "the pose no longer gives the pair opposed normals";
  // Pushed out: no point left overlapping the wall after the 4 s.
  for (PfxUInt32 c = 0; c < world.getNumContactPairs(); ++c) {
    const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(c));
    for (PfxUInt32 p = 0; p < manifold.getNumContacts(); ++p) {
      EXPECT_GE(manifold.getContactPoint(p).m_distance, PfxFloat(-0.01));
    }
  }
}

// fuzz_world_api: a capsule 2e7 m long (the longest shape accepted), welded to a fixed
// sphere, turned its angular velocity NaN in its first step. Its moments of 8e13 kg m^2 gave
// a world inverse inertia whose determinant (2e-42) was denormal, and the joints' geometric
// stiffness, which inverts that matrix back into an inertia, divided by it. The inverse is
// scaled first now (pfxInverseDefinite), and the weld holds the capsule where it was.
TEST(FuzzRegressions, LongestCapsuleWeldedToAFixedBodyStepsToFiniteStates) {
  PfxWorldParam param;
  param.subStep = 2;
  param.pipeline = kPfxPipelineStable;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit fixedInit;
  fixedInit.mass = 0;
  fixedInit.position = PfxVector3(0, 2, 0);
  PfxUInt32 fixedId = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.2))), fixedInit, &fixedId),
            PFX_OK);
  // The moments the fuzzed body had in float (pfxAddBody gives a capsule that thin other
  // moments in double), so that the test is the same in both precisions.
  const PfxVector3 start(1, 2, 0);
  PfxRigidState capsuleState;
  capsuleState.reset();
  capsuleState.setPosition(start);
  PfxRigidBody capsuleBody;
  capsuleBody.reset();
  capsuleBody.setMass(2);
  capsuleBody.setInertia(PfxMatrix3::Identity() * PfxFloat(8e13));
  // Its reach, half length and radius, within kPfxMaxShapeReach in either precision.
  const PfxShape capsule = pfxMakeShape(PfxCapsule(PfxFloat(0.4), kPfxMaxShapeReach - 1));
  PfxUInt32 capsuleId = 0;
  ASSERT_EQ(world.addRigidBody(capsuleState, capsuleBody, &capsule, 1, &capsuleId), PFX_OK);
  PfxFixedJointInitParam weld;
  weld.anchorPoint = PfxVector3(0, 1, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeFixedJoint(joint, world.getRigidState(fixedId),
                                    world.getRigidState(capsuleId), weld),
            PFX_OK);
  joint.m_rigidBodyIdA = fixedId;
  joint.m_rigidBodyIdB = capsuleId;
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  for (int i = 0; i < 60; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    ASSERT_TRUE(world.getRigidState(capsuleId).isValid()) << "step " << i;
  }
  const PfxRigidState& held = world.getRigidState(capsuleId);
  EXPECT_LT((held.getPosition() - start).norm(), PfxFloat(1e-4));
  EXPECT_LT(held.getAngularVelocity().norm(), PfxFloat(1e-6));
}

// The scaled inverse gives the plain inverse's bits where that one stays in float's range,
// and a finite inverse at both ends of the moments accepted (1e-18 and 1e18 kg m^2), where
// the plain one overflows or divides by a denormal.
TEST(FuzzRegressions, InverseOfDefiniteMatrixStaysFiniteOverTheMomentsAccepted) {
  const PfxMatrix3 turn = PfxQuat(PfxFloat(0.9), PfxFloat(0.3), PfxFloat(-0.2), PfxFloat(0.25))
                              .normalized()
                              .toRotationMatrix();
  const PfxMatrix3 moments = PfxVector3(PfxFloat(0.7), PfxFloat(1.3), PfxFloat(1.9)).asDiagonal();
  const PfxMatrix3 inertia = pfxRotateInertia(turn, moments);
  EXPECT_EQ(pfxInverseDefinite(inertia), inertia.inverse());
  for (const PfxFloat scale : {kPfxMinMoment, kPfxMaxMoment}) {
    const PfxMatrix3 scaled = inertia * scale;
    const PfxMatrix3 inverse = pfxInverseDefinite(scaled);
    ASSERT_TRUE(inverse.allFinite()) << "moments scaled by " << scale;
    EXPECT_TRUE((inverse * scaled).isApprox(PfxMatrix3::Identity(), PfxFloat(1e-4)))
        << "moments scaled by " << scale;
    EXPECT_TRUE(pfxInverseDefinite(inverse).isApprox(scaled, PfxFloat(1e-4)))
        << "moments scaled by " << scale;
  }
}
