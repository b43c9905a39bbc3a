// The solver and collision stages called directly: they reject bad parameters with an
// error code and leave every buffer as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/low_level/collision/pfx_detect_collision.h"
#include "pfx/low_level/collision/pfx_refresh_contacts.h"
#include "pfx/low_level/solver/pfx_setup_contact_constraints.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"
#include "pfx/low_level/solver/pfx_solve_constraints.h"
// The joint trees' direct solver is internal to the core (tests/core/CMakeLists.txt gives
// this suite the core's sources to include).
#include "low_level/solver/pfx_joint_tree_solver.h"

using namespace pfx;

namespace {

const PfxFloat kNaN = std::numeric_limits<PfxFloat>::quiet_NaN();

// Two boxes resting on each other, with one pair and one manifold set up by hand.
struct Scene {
  PfxRigidState states[2];
  PfxRigidBody bodies[2];
  PfxCollidable collidables[2];
  PfxSolverBody solverBodies[2];
  PfxConstraintPair pair;
  PfxContactManifold manifold;

  Scene() {
    for (int i = 0; i < 2; ++i) {
      states[i].reset();
      states[i].setPosition(PfxVector3(0, i * 0.99f, 0));
      states[i].setRigidBodyId(i);
      bodies[i].reset();
      collidables[i].reset();
      collidables[i].addShape(pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)));
      collidables[i].finish();
    }
    states[0].setMotionType(kPfxMotionTypeFixed);
    pfxInitializePair(pair, 0, kPfxMotionTypeFixed, 1, kPfxMotionTypeActive);
    manifold.reset(0, 1);
  }
};

// The scene's pair, bodies and `manifolds` as a detect or refresh stage takes them.
template <typename Param>
Param pairParam(Scene& s, PfxContactManifold* manifolds, PfxUInt32 numManifolds) {
  Param param;
  param.contactPairs = &s.pair;
  param.numContactPairs = 1;
  param.offsetContactManifolds = manifolds;
  param.numContactManifolds = numManifolds;
  param.offsetRigidStates = s.states;
  param.numRigidBodies = 2;
  return param;
}

PfxDetectCollisionParam detectParam(Scene& s, PfxContactManifold* manifolds,
                                    PfxUInt32 numManifolds) {
  auto detect = pairParam<PfxDetectCollisionParam>(s, manifolds, numManifolds);
  detect.offsetCollidables = s.collidables;
  return detect;
}

PfxRefreshContactsParam refreshParam(Scene& s, PfxContactManifold* manifolds,
                                     PfxUInt32 numManifolds) {
  return pairParam<PfxRefreshContactsParam>(s, manifolds, numManifolds);
}

template <typename T>
std::vector<unsigned char> bytes(const T& value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  return std::vector<unsigned char>(p, p + sizeof(T));
}

// What every setup of a joint row gives it, whatever the solve it is for.
void expectSameDirectionBoundsAndImpulse(const PfxConstraintRow& a, const PfxConstraintRow& b) {
  EXPECT_EQ(bytes(a.m_normal), bytes(b.m_normal));
  EXPECT_EQ(a.m_lowerLimit, b.m_lowerLimit);
  EXPECT_EQ(a.m_upperLimit, b.m_upperLimit);
  EXPECT_EQ(a.m_accumImpulse, b.m_accumImpulse);
}

// Every field a setup writes, bit for bit (bytes of whole structs would compare padding).
void expectSameSolverBody(const PfxSolverBody& a, const PfxSolverBody& b) {
  EXPECT_EQ(bytes(a.m_deltaLinearVelocity), bytes(b.m_deltaLinearVelocity));
  EXPECT_EQ(bytes(a.m_deltaAngularVelocity), bytes(b.m_deltaAngularVelocity));
  EXPECT_EQ(bytes(a.m_pushLinearVelocity), bytes(b.m_pushLinearVelocity));
  EXPECT_EQ(bytes(a.m_pushAngularVelocity), bytes(b.m_pushAngularVelocity));
  EXPECT_EQ(bytes(a.m_inertiaInv), bytes(b.m_inertiaInv));
  EXPECT_EQ(bytes(a.m_massInv), bytes(b.m_massInv));
  EXPECT_EQ(a.m_motionType, b.m_motionType);
  EXPECT_EQ(bytes(a.m_stiffnessInertia), bytes(b.m_stiffnessInertia));
}

void expectSameRow(const PfxConstraintRow& a, const PfxConstraintRow& b) {
  expectSameDirectionBoundsAndImpulse(a, b);
  EXPECT_EQ(bytes(a.m_rhs), bytes(b.m_rhs));
  EXPECT_EQ(bytes(a.m_jacDiagInv), bytes(b.m_jacDiagInv));
}

void expectSameJointRows(const PfxJoint& a, const PfxJoint& b) {
  EXPECT_EQ(bytes(a.m_armA), bytes(b.m_armA));
  EXPECT_EQ(bytes(a.m_armB), bytes(b.m_armB));
  for (int axis = 0; axis < 6; ++axis) {
    SCOPED_TRACE(testing::Message() << "axis " << axis);
    const PfxJointConstraint& ca = a.m_constraints[axis];
    const PfxJointConstraint& cb = b.m_constraints[axis];
    EXPECT_EQ(bytes(a.m_axes[axis]), bytes(b.m_axes[axis]));
    EXPECT_EQ(ca.m_rowType, cb.m_rowType);
    EXPECT_EQ(bytes(ca.m_position), bytes(cb.m_position));
    EXPECT_EQ(bytes(ca.m_pushRhs), bytes(cb.m_pushRhs));
    EXPECT_EQ(bytes(ca.m_pushImpulse), bytes(cb.m_pushImpulse));
    expectSameRow(ca.m_constraintRow, cb.m_constraintRow);
    EXPECT_EQ(ca.m_driveRowUsed, cb.m_driveRowUsed);
    expectSameRow(ca.m_driveRow, cb.m_driveRow);
  }
}

// The setup of every body of `states`.
PfxSetupSolverBodiesParam solverBodiesParam(const PfxRigidState* states, const PfxRigidBody* bodies,
                                            PfxSolverBody* solverBodies, PfxUInt32 numBodies) {
  PfxSetupSolverBodiesParam param;
  param.states = states;
  param.bodies = bodies;
  param.solverBodies = solverBodies;
  param.numRigidBodies = numBodies;
  return param;
}

// The velocity setup of joints 0 .. numJoints - 1, one pair each, at dt 1/60.
PfxSetupJointConstraintsParam jointSetupParam(PfxConstraintPair* pairs, PfxJoint* joints,
                                              PfxUInt32 numJoints, const PfxRigidState* states,
                                              const PfxRigidBody* bodies,
                                              PfxSolverBody* solverBodies, PfxUInt32 numBodies) {
  PfxSetupJointConstraintsParam param;
  param.jointPairs = pairs;
  param.numJointPairs = numJoints;
  param.offsetJoints = joints;
  param.numJoints = numJoints;
  param.offsetRigidStates = states;
  param.offsetRigidBodies = bodies;
  param.offsetSolverBodies = solverBodies;
  param.numRigidBodies = numBodies;
  param.timeStep = 1.0f / 60;
  return param;
}

}  // namespace

TEST(SolverStages, DetectSetupSolveRefreshRunOnAPair) {
  Scene s;
  PfxDetectCollisionParam detect = detectParam(s, &s.manifold, 1);
  detect.timeStep = 1.0f / 60;
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  // Face on face, 1 cm deep: four points.
  ASSERT_EQ(s.manifold.getNumContacts(), 4u);
  EXPECT_EQ(pfxGetNumConstraints(s.pair), 4u);
  EXPECT_NEAR(s.manifold.getPenetrationDepth(), 0.01f, 1e-5f);

  ASSERT_EQ(pfxSetupSolverBodies(solverBodiesParam(s.states, s.bodies, s.solverBodies, 2)), PFX_OK);
  EXPECT_EQ(s.solverBodies[0].m_massInv, 0);  // fixed
  EXPECT_EQ(s.solverBodies[1].m_massInv, 1);

  s.states[1].setLinearVelocity(PfxVector3(0, -1, 0));
  PfxSetupContactConstraintsParam setup;
  setup.contactPairs = &s.pair;
  setup.numContactPairs = 1;
  setup.offsetContactManifolds = &s.manifold;
  setup.numContactManifolds = 1;
  setup.offsetRigidStates = s.states;
  setup.offsetRigidBodies = s.bodies;
  setup.offsetSolverBodies = s.solverBodies;
  setup.numRigidBodies = 2;
  setup.timeStep = 1.0f / 60;
  ASSERT_EQ(pfxSetupContactConstraints(setup), PFX_OK);

  PfxSolveConstraintsParam solve;
  solve.contactPairs = &s.pair;
  solve.numContactPairs = 1;
  solve.offsetContactManifolds = &s.manifold;
  solve.numContactManifolds = 1;
  solve.offsetRigidStates = s.states;
  solve.offsetSolverBodies = s.solverBodies;
  solve.numRigidBodies = 2;
  solve.timeStep = 1.0f / 60;
  // The contacts' direct solve needs work memory; without it the call is refused. Its
  // scratch must hold the largest contact tree, here the face and the box (two nodes): a
  // byte less is refused too, and the call says how many nodes it needs.
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_OUT_OF_BUFFER);
  std::vector<unsigned char> work(pfxGetWorkBytesOfSolveConstraints(2, 1, 0, 1, 2));
  ASSERT_GT(work.size(), 0u);
  EXPECT_LT(work.size(), pfxGetWorkBytesOfSolveConstraints(2, 1));
  PfxUInt32 contactTreeNodes = 0;
  solve.outContactTreeNodes = &contactTreeNodes;
  solve.workBuff = work.data();
  solve.workBytes = static_cast<PfxUInt32>(work.size() - 1);
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_OUT_OF_BUFFER);
  EXPECT_EQ(contactTreeNodes, 2u);
  EXPECT_EQ(s.states[1].getLinearVelocity().y(), -1);  // the refused call changed nothing
  EXPECT_EQ(s.manifold.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 0);
  solve.workBytes = static_cast<PfxUInt32>(work.size());
  ASSERT_EQ(pfxSolveConstraints(solve), PFX_OK);
  // The downward velocity is stopped (the overlap is pushed out by position, not velocity).
  EXPECT_NEAR(s.states[1].getLinearVelocity().y(), 0, 1e-4f);
  EXPECT_GT(s.states[1].getPosition().y(), 0.99f);

  // Pull the box away: refreshing drops every point.
  s.states[1].setPosition(PfxVector3(0, 1.5f, 0));
  ASSERT_EQ(pfxRefreshContacts(refreshParam(s, &s.manifold, 1)), PFX_OK);
  EXPECT_EQ(s.manifold.getNumContacts(), 0u);
  EXPECT_EQ(pfxGetNumConstraints(s.pair), 0u);
}

TEST(SolverStages, PairsNamingTheSharedEmptyManifoldAreTestedWithoutWritingIt) {
  Scene s;
  PfxDetectCollisionParam detect = detectParam(s, &s.manifold, 1);
  detect.sharedEmptyContactId = 0;
  const std::vector<unsigned char> before = bytes(s.manifold);
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  // The boxes touch: the pair says how many points it found, its id still names the shared
  // manifold, and that stays as it was.
  EXPECT_EQ(pfxGetNumConstraints(s.pair), 4u);
  EXPECT_EQ(pfxGetContactId(s.pair), 0u);
  EXPECT_EQ(bytes(s.manifold), before);

  // Given a manifold of its own, the pair finds the same points there.
  PfxContactManifold own[2];
  own[0].reset(0, 0);
  own[1].reset(0, 1);
  pfxSetContactId(s.pair, 1);
  detect.offsetContactManifolds = own;
  detect.numContactManifolds = 2;
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  EXPECT_EQ(own[1].getNumContacts(), 4u);
  EXPECT_EQ(own[0].getNumContacts(), 0u);

  // Apart, it finds none, and refreshing a pair that names the empty manifold reads it only.
  s.states[1].setPosition(PfxVector3(0, 1.5f, 0));
  pfxSetContactId(s.pair, 0);
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  EXPECT_EQ(pfxGetNumConstraints(s.pair), 0u);
  const std::vector<unsigned char> empty = bytes(own[0]);
  ASSERT_EQ(pfxRefreshContacts(refreshParam(s, own, 2)), PFX_OK);
  EXPECT_EQ(bytes(own[0]), empty);
}

TEST(SolverStages, RejectBadInputAndChangeNothing) {
  Scene s;
  const auto statesBefore = bytes(s.states);
  const auto manifoldBefore = bytes(s.manifold);
  const auto pairBefore = bytes(s.pair);
  auto unchanged = [&](const char* what) {
    EXPECT_EQ(bytes(s.states), statesBefore) << what;
    EXPECT_EQ(bytes(s.manifold), manifoldBefore) << what;
    EXPECT_EQ(bytes(s.pair), pairBefore) << what;
  };

  PfxDetectCollisionParam detect = detectParam(s, &s.manifold, 1);
  detect.timeStep = 1.0f / 60;
  PfxDetectCollisionParam bad = detect;
  bad.offsetCollidables = nullptr;
  EXPECT_EQ(pfxDetectCollision(bad), PFX_ERR_NULL_POINTER);
  bad = detect;
  bad.contactMargin = kNaN;
  EXPECT_EQ(pfxDetectCollision(bad), PFX_ERR_INVALID_VALUE);
  bad = detect;
  bad.numRigidBodies = 1;  // the pair names body 1
  EXPECT_EQ(pfxDetectCollision(bad), PFX_ERR_OUT_OF_RANGE);
  // A pair naming a manifold beyond the count given; without a count (0) ids go unchecked.
  PfxConstraintPair farPair = s.pair;
  pfxSetContactId(farPair, 1);
  bad = detect;
  bad.contactPairs = &farPair;
  EXPECT_EQ(pfxDetectCollision(bad), PFX_ERR_OUT_OF_RANGE);
  unchanged("detect");

  PfxRefreshContactsParam refresh = refreshParam(s, &s.manifold, 1);
  refresh.breakDistance = -1;
  EXPECT_EQ(pfxRefreshContacts(refresh), PFX_ERR_INVALID_VALUE);
  refresh.breakDistance = 0.02f;
  refresh.offsetRigidStates = nullptr;
  EXPECT_EQ(pfxRefreshContacts(refresh), PFX_ERR_NULL_POINTER);
  unchanged("refresh");

  PfxSetupSolverBodiesParam bodies;
  bodies.states = s.states;
  bodies.bodies = s.bodies;
  bodies.numRigidBodies = 2;
  EXPECT_EQ(pfxSetupSolverBodies(bodies), PFX_ERR_NULL_POINTER);

  PfxSetupContactConstraintsParam setup;
  setup.contactPairs = &s.pair;
  setup.numContactPairs = 1;
  setup.offsetContactManifolds = &s.manifold;
  setup.numContactManifolds = 1;
  setup.offsetRigidStates = s.states;
  setup.offsetRigidBodies = s.bodies;
  setup.offsetSolverBodies = s.solverBodies;
  setup.numRigidBodies = 2;
  setup.timeStep = 0;
  EXPECT_EQ(pfxSetupContactConstraints(setup), PFX_ERR_INVALID_VALUE);
  setup.timeStep = 1.0f / 60;
  setup.separateBias = kNaN;
  EXPECT_EQ(pfxSetupContactConstraints(setup), PFX_ERR_INVALID_VALUE);
  setup.separateBias = 0.2f;
  setup.numRigidBodies = 1;
  EXPECT_EQ(pfxSetupContactConstraints(setup), PFX_ERR_OUT_OF_RANGE);
  setup.numRigidBodies = 2;
  setup.offsetRigidBodies = nullptr;
  EXPECT_EQ(pfxSetupContactConstraints(setup), PFX_ERR_NULL_POINTER);
  unchanged("setup");

  PfxSolveConstraintsParam solve;
  solve.contactPairs = &s.pair;
  solve.numContactPairs = 1;
  solve.offsetContactManifolds = &s.manifold;
  solve.numContactManifolds = 1;
  solve.offsetRigidStates = s.states;
  solve.offsetSolverBodies = s.solverBodies;
  solve.numRigidBodies = 2;
  solve.timeStep = kNaN;
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_INVALID_VALUE);
  solve.timeStep = 1.0f / 60;
  solve.restitutionThreshold = -1;
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_INVALID_VALUE);
  solve.restitutionThreshold = 0.2f;
  solve.gravity = PfxVector3(0, kNaN, 0);
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_INVALID_VALUE);
  solve.gravity = PfxVector3(0, -9.8f, 0);
  solve.contactPairs = &farPair;
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_OUT_OF_RANGE);
  solve.contactPairs = &s.pair;
  solve.offsetSolverBodies = nullptr;
  EXPECT_EQ(pfxSolveConstraints(solve), PFX_ERR_NULL_POINTER);
  unchanged("solve");
}

// The position correction's setup gives every row the direction, bounds, warm-started
// impulse, effective mass (lock rows) and push that a full setup gives, and leaves what
// only the velocity solve reads, the rows' aimed-for velocities and the drive rows'
// effective masses, as they were. A hinge past its limit with a velocity drive, and a
// damped swing-twist joint, between a fixed and two moving bodies.
TEST(SolverStages, JointSetupForThePositionCorrectionSetsWhatItReads) {
  PfxRigidState states[3];
  PfxRigidBody bodies[3];
  PfxSolverBody solverBodies[3];
  for (int i = 0; i < 3; ++i) {
    states[i].reset();
    states[i].setPosition(PfxVector3(i * 1.0f, 0, 0));
    states[i].setRigidBodyId(i);
    bodies[i].reset();
  }
  states[0].setMotionType(kPfxMotionTypeFixed);
  PfxJoint joints[2];
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = PfxVector3(0.5f, 0, 0);
  hinge.lowerAngle = -0.2f;
  hinge.upperAngle = 0.2f;
  ASSERT_EQ(pfxInitializeHingeJoint(joints[0], states[0], states[1], hinge), PFX_OK);
  joints[0].m_constraints[kPfxJointAxisTwist].m_drive = kPfxJointDriveVelocity;
  joints[0].m_constraints[kPfxJointAxisTwist].m_driveTarget = 2;
  joints[0].m_constraints[kPfxJointAxisTwist].m_driveMaxForce = 30;
  PfxSwingTwistJointInitParam swingTwist;
  swingTwist.anchorPoint = PfxVector3(1.5f, 0, 0);
  swingTwist.damping = 0.3f;
  ASSERT_EQ(pfxInitializeSwingTwistJoint(joints[1], states[1], states[2], swingTwist), PFX_OK);
  // Turned past the hinge's upper limit, moving, with impulses to warm start from.
  states[1].setOrientation(PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f, PfxVector3::UnitZ())));
  states[1].setLinearVelocity(PfxVector3(0.1f, -0.4f, 0.2f));
  states[1].setAngularVelocity(PfxVector3(0.3f, 0.1f, 1.5f));
  states[2].setAngularVelocity(PfxVector3(-0.5f, 0.8f, 0.2f));
  constexpr PfxFloat kUnset = 12345;
  for (PfxJoint& joint : joints) {
    for (PfxJointConstraint& c : joint.m_constraints) {
      c.m_constraintRow.m_accumImpulse = 0.7f;
      c.m_driveRow.m_accumImpulse = 0.9f;
      c.m_constraintRow.m_rhs = c.m_driveRow.m_rhs = kUnset;
      c.m_driveRow.m_jacDiagInv = kUnset;
    }
  }
  PfxConstraintPair pairs[2];
  for (PfxUInt32 i = 0; i < 2; ++i) {
    pfxUpdateJointPairs(pairs[i], i, joints[i], states[joints[i].m_rigidBodyIdA],
                        states[joints[i].m_rigidBodyIdB]);
  }
  ASSERT_EQ(pfxSetupSolverBodies(solverBodiesParam(states, bodies, solverBodies, 3)), PFX_OK);

  PfxJoint full[2] = {joints[0], joints[1]};
  PfxJoint corrected[2] = {joints[0], joints[1]};
  PfxSolverBody fullBodies[3] = {solverBodies[0], solverBodies[1], solverBodies[2]};
  PfxSolverBody correctedBodies[3] = {solverBodies[0], solverBodies[1], solverBodies[2]};
  PfxSetupJointConstraintsParam setup =
      jointSetupParam(pairs, full, 2, states, bodies, fullBodies, 3);
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);
  setup.forPositionCorrection = true;
  setup.offsetJoints = corrected;
  setup.offsetSolverBodies = correctedBodies;
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);

  int limitRows = 0, driveRows = 0;
  for (int j = 0; j < 2; ++j) {
    for (int axis = 0; axis < 6; ++axis) {
      SCOPED_TRACE(testing::Message() << "joint " << j << " axis " << axis);
      const PfxJointConstraint& a = full[j].m_constraints[axis];
      const PfxJointConstraint& b = corrected[j].m_constraints[axis];
      EXPECT_EQ(a.m_rowType, b.m_rowType);
      EXPECT_EQ(a.m_position, b.m_position);
      expectSameDirectionBoundsAndImpulse(a.m_constraintRow, b.m_constraintRow);
      EXPECT_EQ(a.m_constraintRow.m_jacDiagInv, b.m_constraintRow.m_jacDiagInv);
      EXPECT_EQ(a.m_pushRhs, b.m_pushRhs);
      EXPECT_EQ(a.m_driveRowUsed, b.m_driveRowUsed);
      expectSameDirectionBoundsAndImpulse(a.m_driveRow, b.m_driveRow);
      if (a.m_rowType != kPfxJointRowNone) {
        EXPECT_NE(a.m_constraintRow.m_rhs, kUnset);
        EXPECT_EQ(b.m_constraintRow.m_rhs, kUnset);
      }
      if (a.m_driveRowUsed) {
        ++driveRows;
        EXPECT_NE(a.m_driveRow.m_jacDiagInv, kUnset);
        EXPECT_EQ(b.m_driveRow.m_jacDiagInv, kUnset);
        EXPECT_EQ(b.m_driveRow.m_rhs, kUnset);
      }
      limitRows += a.m_rowType == kPfxJointRowLimit ? 1 : 0;
    }
  }
  // The hinge's limit holds a push, its drive and the swing-twist's damping use their rows.
  EXPECT_NE(full[0].m_constraints[kPfxJointAxisTwist].m_pushRhs, 0);
  EXPECT_GE(limitRows, 2);
  EXPECT_GE(driveRows, 4);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(bytes(fullBodies[i].m_inertiaInv), bytes(correctedBodies[i].m_inertiaInv));
  }
}

// A setup of the bodies flagged (bodiesToSetUp) leaves every solver body and joint as a
// full setup at the same poses would, bit for bit, when only the flagged bodies moved since
// the last full one: the position correction's later passes rely on it. Two hinge chains,
// each from a fixed body with a heavy link under load (its geometric stiffness); the second
// link of the first chain moves, the second chain does not.
TEST(SolverStages, SetupOfTheBodiesToSetUpMatchesAFullSetup) {
  constexpr int kBodies = 6;
  PfxRigidState states[kBodies];
  PfxRigidBody bodies[kBodies];
  for (int i = 0; i < kBodies; ++i) {
    states[i].reset();
    states[i].setPosition(PfxVector3((i % 3) * 1.0f, (i / 3) * 2.0f, 0));
    states[i].setRigidBodyId(i);
    bodies[i].reset();
    bodies[i].setMass(i % 3 == 2 ? 50.0f : 1.0f);
    bodies[i].setInertia(PfxVector3(0.2f, 0.3f, 0.4f).asDiagonal());
  }
  states[0].setMotionType(kPfxMotionTypeFixed);
  states[3].setMotionType(kPfxMotionTypeFixed);
  PfxJoint joints[4];
  const int ends[4][2] = {{0, 1}, {1, 2}, {3, 4}, {4, 5}};
  for (int j = 0; j < 4; ++j) {
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = states[ends[j][0]].getPosition() + PfxVector3(0.5f, 0, 0);
    hinge.lowerAngle = -0.2f;
    hinge.upperAngle = 0.2f;
    ASSERT_EQ(pfxInitializeHingeJoint(joints[j], states[ends[j][0]], states[ends[j][1]], hinge),
              PFX_OK);
  }
  PfxConstraintPair pairs[4];
  for (PfxUInt32 j = 0; j < 4; ++j) {
    pfxUpdateJointPairs(pairs[j], j, joints[j], states[joints[j].m_rigidBodyIdA],
                        states[joints[j].m_rigidBodyIdB]);
  }
  PfxSolverBody solverBodies[kBodies];
  PfxSetupSolverBodiesParam solverParam = solverBodiesParam(states, bodies, solverBodies, kBodies);
  PfxSetupJointConstraintsParam setup =
      jointSetupParam(pairs, joints, 4, states, bodies, solverBodies, kBodies);
  // A velocity setup gives the rows their directions, a solve their impulses (which the
  // geometric stiffness reads), then the position correction's first pass sets up all.
  ASSERT_EQ(pfxSetupSolverBodies(solverParam), PFX_OK);
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);
  for (PfxJoint& joint : joints) {
    for (PfxJointConstraint& c : joint.m_constraints) c.m_constraintRow.m_accumImpulse = 3;
  }
  setup.forPositionCorrection = true;
  ASSERT_EQ(pfxSetupSolverBodies(solverParam), PFX_OK);
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);

  // What a pass leaves: push impulses on the rows, velocity changes on the bodies; then
  // body 2 moved (turned past the hinge's limit and shifted off its anchor).
  for (PfxJoint& joint : joints) {
    for (PfxJointConstraint& c : joint.m_constraints) c.m_pushImpulse = 0.25f;
  }
  solverBodies[2].m_pushLinearVelocity = PfxVector3(0.1f, 0, 0);
  solverBodies[4].m_deltaAngularVelocity = PfxVector3(0, 0.2f, 0);
  states[2].setPosition(states[2].getPosition() + PfxVector3(0.01f, 0.02f, 0));
  states[2].setOrientation(PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f, PfxVector3::UnitZ())));
  const PfxUInt8 moved[kBodies] = {0, 0, 1, 0, 0, 0};

  PfxJoint fullJoints[4] = {joints[0], joints[1], joints[2], joints[3]};
  PfxSolverBody fullBodies[kBodies];
  std::copy(solverBodies, solverBodies + kBodies, fullBodies);
  solverParam.bodiesToSetUp = setup.bodiesToSetUp = moved;
  ASSERT_EQ(pfxSetupSolverBodies(solverParam), PFX_OK);
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);
  solverParam.bodiesToSetUp = setup.bodiesToSetUp = nullptr;
  solverParam.solverBodies = setup.offsetSolverBodies = fullBodies;
  setup.offsetJoints = fullJoints;
  ASSERT_EQ(pfxSetupSolverBodies(solverParam), PFX_OK);
  ASSERT_EQ(pfxSetupJointConstraints(setup), PFX_OK);

  for (int i = 0; i < kBodies; ++i) {
    SCOPED_TRACE(testing::Message() << "body " << i);
    expectSameSolverBody(solverBodies[i], fullBodies[i]);
  }
  for (int j = 0; j < 4; ++j) {
    SCOPED_TRACE(testing::Message() << "joint " << j);
    expectSameJointRows(joints[j], fullJoints[j]);
  }
  // The heavy link took stiffness from its joint, and the moved one changed its rows.
  EXPECT_GT(fullBodies[2].m_stiffnessInertia, 0);
  EXPECT_GT(fullBodies[5].m_stiffnessInertia, 0);
  EXPECT_NE(joints[1].m_constraints[kPfxJointAxisTwist].m_pushRhs, 0);
}

// pfxCheckContactBodies passes a body whose pose is a rigid transform and whose shapes meet
// the narrow phase; a pair of two passed bodies skips those checks in the detection and
// finds the points it finds without them, and a body that fails them is checked, and
// refused, at its pairs as before.
TEST(SolverStages, DetectionOfCheckedBodiesFindsWhatTheCheckedCallsFind) {
  Scene s;
  PfxUInt8 checked[2] = {7, 7};
  pfxCheckContactBodies(s.states, s.collidables, 2, checked);
  EXPECT_EQ(checked[0], 1);
  EXPECT_EQ(checked[1], 1);
  PfxDetectCollisionParam detect = detectParam(s, &s.manifold, 1);
  detect.timeStep = 1.0f / 60;
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  ASSERT_EQ(s.manifold.getNumContacts(), 4u);
  PfxContactManifold unchecked;
  unchecked.reset(0, 1);
  detect.offsetContactManifolds = &unchecked;
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  PfxContactManifold fromChecked;
  fromChecked.reset(0, 1);
  detect.offsetContactManifolds = &fromChecked;
  detect.checkedBodies = checked;
  ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
  ASSERT_EQ(fromChecked.getNumContacts(), unchecked.getNumContacts());
  for (PfxUInt32 c = 0; c < unchecked.getNumContacts(); ++c) {
    const PfxContactPoint& a = unchecked.getContactPoint(c);
    const PfxContactPoint& b = fromChecked.getContactPoint(c);
    EXPECT_EQ(bytes(a.m_localPointA), bytes(b.m_localPointA));
    EXPECT_EQ(bytes(a.m_localPointB), bytes(b.m_localPointB));
    EXPECT_EQ(bytes(a.m_constraintRow[0].m_normal), bytes(b.m_constraintRow[0].m_normal));
    EXPECT_EQ(bytes(a.m_distance), bytes(b.m_distance));
  }

  // A pose that is no rotation (a quaternion of length 1.4) or not finite fails the check,
  // and the pair, checked at the call, finds nothing, flags or not.
  for (const PfxVector3& position : {PfxVector3(0, 0.99f, 0), PfxVector3(0, kNaN, 0)}) {
    SCOPED_TRACE(testing::Message() << "position " << position.transpose());
    const bool finite = pfxIsFinite(position);
    s.states[1].setPosition(position);
    s.states[1].setOrientation(finite ? PfxQuat(1, 1, 0, 0) : PfxQuat(PfxQuat::Identity()));
    pfxCheckContactBodies(s.states, s.collidables, 2, checked);
    EXPECT_EQ(checked[0], 1);
    EXPECT_EQ(checked[1], 0);
    fromChecked.reset(0, 1);
    ASSERT_EQ(pfxDetectCollision(detect), PFX_OK);
    EXPECT_EQ(fromChecked.getNumContacts(), 0u);
  }
}

// An impulse on one body of a tree whose locked axes hold moves the tree as giving the body
// the impulse and solving the tree does: the same velocity changes of every body and the
// same locked rows' impulses, to rounding. The contacts on a ragdoll's feet rely on it
// (pfx_tree_contact_rows.h): only a tree's first update in a sweep solves it whole. A
// root with two children, one of them with a child of its own, none fixed, all moving.
TEST(SolverStages, ImpulseThroughAHeldTreeMatchesAnImpulseAndATreeSolve) {
  constexpr int kBodies = 4;
  PfxRigidState states[kBodies];
  PfxRigidBody bodies[kBodies];
  const PfxVector3 positions[kBodies] = {{0, 1, 0}, {0.5f, 1, 0}, {-0.5f, 1, 0}, {1, 1, 0}};
  for (int i = 0; i < kBodies; ++i) {
    states[i].reset();
    states[i].setPosition(positions[i]);
    states[i].setRigidBodyId(i);
    states[i].setLinearVelocity(PfxVector3(0.1f * i, -0.3f, 0.2f));
    states[i].setAngularVelocity(PfxVector3(0.4f, 0.1f * i, -0.2f));
    bodies[i].reset();
    bodies[i].setMass(i == 0 ? 20.0f : 1.0f + i);
    bodies[i].setInertia(PfxVector3(0.2f, 0.3f + 0.1f * i, 0.4f).asDiagonal());
  }
  PfxJoint joints[3];
  const int ends[3][2] = {{0, 1}, {0, 2}, {1, 3}};
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(0.25f, 1, 0);
  ASSERT_EQ(pfxInitializeBallJoint(joints[0], states[0], states[1], ball), PFX_OK);
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = PfxVector3(-0.25f, 1, 0);
  ASSERT_EQ(pfxInitializeHingeJoint(joints[1], states[0], states[2], hinge), PFX_OK);
  hinge.anchorPoint = PfxVector3(0.75f, 1, 0);
  hinge.axis = PfxVector3::UnitY();
  ASSERT_EQ(pfxInitializeHingeJoint(joints[2], states[1], states[3], hinge), PFX_OK);
  PfxConstraintPair pairs[3];
  for (PfxUInt32 j = 0; j < 3; ++j) {
    pfxUpdateJointPairs(pairs[j], j, joints[j], states[ends[j][0]], states[ends[j][1]]);
  }
  PfxSolverBody solverBodies[kBodies];
  ASSERT_EQ(pfxSetupSolverBodies(solverBodiesParam(states, bodies, solverBodies, kBodies)), PFX_OK);
  ASSERT_EQ(pfxSetupJointConstraints(
                jointSetupParam(pairs, joints, 3, states, bodies, solverBodies, kBodies)),
            PFX_OK);

  std::vector<unsigned char> work(PfxJointTreeSolver::getWorkBytes(kBodies, 3));
  PfxJointTreeSolver tree;
  ASSERT_TRUE(
      tree.build(work.data(), PfxUInt32(work.size()), pairs, 3, joints, solverBodies, kBodies));
  for (PfxUInt32 j = 0; j < 3; ++j) ASSERT_TRUE(tree.contains(j));
  EXPECT_FALSE(tree.holdsTreeOf(3));
  tree.solveTreeOf(0, false);
  EXPECT_TRUE(tree.holdsTreeOf(3));
  tree.forgetHeldTreeOf(2);
  EXPECT_FALSE(tree.holdsTreeOf(3));
  tree.solveTreeOf(3, false);
  ASSERT_TRUE(tree.holdsTreeOf(0));

  PfxSolverBody heldBodies[kBodies];
  std::copy(solverBodies, solverBodies + kBodies, heldBodies);
  const PfxJoint heldJoints[3] = {joints[0], joints[1], joints[2]};
  const PfxVector3 linear(0.3f, -1.2f, 0.5f);
  const PfxVector3 angular = PfxVector3(0.1f, 0.2f, -0.05f).cross(linear);

  // Given to the body, then the tree solved.
  PfxSolverBody& loaded = solverBodies[3];
  loaded.m_deltaLinearVelocity += loaded.m_massInv * linear;
  loaded.m_deltaAngularVelocity += loaded.m_inertiaInv * angular;
  tree.solveTreeOf(3, false);
  PfxSolverBody solvedBodies[kBodies];
  std::copy(solverBodies, solverBodies + kBodies, solvedBodies);
  const PfxJoint solvedJoints[3] = {joints[0], joints[1], joints[2]};

  // Through the held tree.
  std::copy(heldBodies, heldBodies + kBodies, solverBodies);
  std::copy(heldJoints, heldJoints + 3, joints);
  tree.applyImpulseThroughTree(3, linear, angular, false);

  PfxFloat largestChange = 0;
  for (int i = 0; i < kBodies; ++i) {
    SCOPED_TRACE(testing::Message() << "body " << i);
    const PfxVector3 change =
        solvedBodies[i].m_deltaLinearVelocity - heldBodies[i].m_deltaLinearVelocity;
    const PfxVector3 turn =
        solvedBodies[i].m_deltaAngularVelocity - heldBodies[i].m_deltaAngularVelocity;
    largestChange = std::max({largestChange, change.norm(), turn.norm()});
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(solverBodies[i].m_deltaLinearVelocity[k],
                  solvedBodies[i].m_deltaLinearVelocity[k], 1e-5f);
      EXPECT_NEAR(solverBodies[i].m_deltaAngularVelocity[k],
                  solvedBodies[i].m_deltaAngularVelocity[k], 1e-5f);
    }
  }
  // The impulse reached the root through both joints: the comparison is not of zeros.
  EXPECT_GT(largestChange, 0.05f);
  EXPECT_GT((solvedBodies[0].m_deltaLinearVelocity - heldBodies[0].m_deltaLinearVelocity).norm(),
            0.01f);
  for (int j = 0; j < 3; ++j) {
    for (int axis = 0; axis < 6; ++axis) {
      SCOPED_TRACE(testing::Message() << "joint " << j << " axis " << axis);
      EXPECT_NEAR(joints[j].m_constraints[axis].m_constraintRow.m_accumImpulse,
                  solvedJoints[j].m_constraints[axis].m_constraintRow.m_accumImpulse, 1e-5f);
    }
  }
}
