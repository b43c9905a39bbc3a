#include "pfx/low_level/solver/pfx_correct_joint_positions.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_joint_coupling_row.h"
#include "low_level/solver/pfx_joint_row.h"
#include "low_level/solver/pfx_joint_tree_solver.h"
#include "low_level/solver/pfx_tree_contact_rows.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

namespace pfx {

namespace {

// The work of the region the iterations still work on (CorrectionRegion): per body its
// group, a slot of the list of trees to solve, and a byte of flags; and per body a byte
// telling whether the last pass moved it.
std::size_t regionWorkBytes(PfxUInt32 numRigidBodies) {
  return PfxWorkCarver::bytesFor(alignof(PfxUInt32), sizeof(PfxUInt32) * 2 * numRigidBodies) +
         2 * PfxWorkCarver::bytesFor(1, numRigidBodies);
}

// The contact pairs with points (touchingPairs), copied once for every pass.
std::size_t touchingPairsWorkBytes(PfxUInt32 numContactPairs) {
  return PfxWorkCarver::bytesFor(alignof(PfxConstraintPair),
                                 sizeof(PfxConstraintPair) * numContactPairs);
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfCorrectJointPositions(PfxUInt32 numRigidBodies,
                                                 PfxUInt32 numJointPairs,
                                                 PfxUInt32 numContactPairs) {
  if (numJointPairs == 0) return 0;
  return static_cast<PfxUInt32>(PfxJointTreeSolver::getWorkBytes(numRigidBodies, numJointPairs) +
                                regionWorkBytes(numRigidBodies) +
                                touchingPairsWorkBytes(numContactPairs));
}

namespace {

constexpr PfxUInt32 kNewtonPasses = 2;

constexpr PfxUInt32 kCorrectedBodiesPerTask = 512;

// The contacts as one-sided rows on the push velocities: the correction may move two
// bodies apart at a contact point or along it, never closer. Without them the joints'
// correction, which runs after the contacts' split impulses, pulled a ragdoll's limbs back
// into each other and into the ground every step: at dt 1/30 a humanoid lay 4 cm deep in
// itself and crept for half a minute. Letting a point that had a gap after the step close
// it (the measured gap moved by the solved velocities) left that humanoid 4 cm deep again:
// the estimate is too rough to spend. The impulses start from zero: the solver's split
// impulses are spent by now, and the next setup starts them afresh.
void clearContactPushImpulses(const PfxConstraintPair* touchingPairs, PfxUInt32 numTouchingPairs,
                              PfxContactManifold* manifolds) {
  for (PfxUInt32 i = 0; i < numTouchingPairs; ++i) {
    PfxContactManifold& manifold = manifolds[pfxGetContactId(touchingPairs[i])];
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      manifold.getContactPoint(c).m_pushImpulse = 0;
    }
  }
}

// Copies the active contact pairs with points, in their order, into `touchingPairs`: most
// pairs of a pile have none (the bodies' boxes overlap, their shapes do not: three quarters
// or more of the piled ragdolls' 555 pairs at dt 1/60), and every iteration of every pass
// went through them twice.
PfxUInt32 gatherTouchingPairs(const PfxCorrectJointPositionsParam& param,
                              PfxConstraintPair* touchingPairs) {
  PfxUInt32 count = 0;
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (pfxGetActive(pair) &&
        param.offsetContactManifolds[pfxGetContactId(pair)].getNumContacts() > 0) {
      touchingPairs[count++] = pair;
    }
  }
  return count;
}

// How far the correction may move two bodies closer at a contact point, or an update of a
// joint's iterated row move its two bodies along the row, before they call for more
// iterations (m, or rad): far below the contact slop, and a standing robot, whose joints
// press its feet into the ground by micrometres every pass, then costs no iterations
// beyond the joints' own.
constexpr PfxFloat kNegligibleApproach = PfxFloat(1e-4);

// The largest move a pass may ask of a joint (m, or rad) and still be left undone: 0.3 µm,
// about the spacing of floats a few metres from the origin (0.24 µm from 2 to 4 m), where
// such a pass could not make the positions any more exact. It is scaled by the precision's
// epsilon, as kHeldLockedRowVelocity is. After the first pass, no joint of the robots of
// `pfx_bench --scene robots` (1 to 64 arms) asked for more than 1 µm in two steps of three,
// nor any joint of the arm of `--scene urdf` in any step; the later passes factored every
// tree and iterated for the rounding.
constexpr double kNegligibleCorrection =
    3e-7 * (double(std::numeric_limits<PfxFloat>::epsilon()) /
            double(std::numeric_limits<float>::epsilon()));

// Whether a row, as set up for the position correction, asks its bodies to move by more
// than kNegligibleCorrection along it: a locked axis's error, or how far a limit is passed,
// times the joint's bias. A move that is not a number asks.
bool asksToMove(PfxFloat pushRhs, const PfxConstraintRow& row, PfxFloat timeStep) {
  if (pushRhs == 0 || !(row.m_jacDiagInv > 0)) return false;
  return !(std::abs(double(pushRhs) / double(row.m_jacDiagInv)) * double(timeStep) <=
           kNegligibleCorrection);
}

// Whether a joint whose bodies the last pass moved may ask to move them again, measured at
// their poses now without setting the joint up: its lock rows as a setup would measure them
// (pfxCalcJointRowPositions, pfxLockRow), to the bit. It finds a joint asking wherever a
// setup would (asksToMove): the rows' effective masses, which the setup multiplies the push
// by and asksToMove divides it by again, are left out, and the bound is a thousandth lower
// for the rounding that leaves; so is the speed limit, which only shortens the push.
bool mayAskToMove(const PfxJoint& joint, const PfxRigidState& stateA,
                  const PfxRigidState& stateB, PfxFloat timeStep) {
  PfxFloat positions[6];
  pfxCalcJointRowPositions(joint, stateA, stateB, positions);
  for (PfxUInt32 axis = 0; axis < 6; ++axis) {
    const PfxFloat push =
        pfxLockRowPushVelocity(joint.m_constraints[axis], pfxLockRow(joint, axis, positions),
                               timeStep);
    if (push == 0) continue;
    // Not a number asks, as it does of asksToMove.
    if (!(std::abs(double(push)) * double(timeStep) <= 0.999 * kNegligibleCorrection)) {
      return true;
    }
  }
  return false;
}

// Whether a pass after the first may find a joint that asks to move its bodies, before it
// sets the joints up: the joints of the bodies the last pass moved are measured
// (mayAskToMove), the others' rows are as the last setup left them. Couplings are set up to
// be measured. Most passes after the first find nothing to move, and setting every joint up
// to learn it cost the chains of `pfx_bench --scene chain` 7 % of their step (792 of 949
// later passes of `--scene urdf` at dt 1/60 found nothing, 3,222 of 3,869 of the chains).
bool anyJointMayAskToMove(const PfxCorrectJointPositionsParam& param,
                          const PfxUInt8* movedBodies) {
  if (param.numJointCouplings > 0) return true;
  for (PfxUInt32 i = 0; i < param.numJointPairs; ++i) {
    const PfxConstraintPair& pair = param.jointPairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    const PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
    if (movedBodies[idA] != 0 || movedBodies[idB] != 0) {
      if (mayAskToMove(joint, param.offsetRigidStates[idA], param.offsetRigidStates[idB],
                       param.timeStep)) {
        return true;
      }
      continue;
    }
    for (const PfxJointConstraint& c : joint.m_constraints) {
      if (asksToMove(c.m_pushRhs, c.m_constraintRow, param.timeStep)) return true;
    }
  }
  return false;
}

// The part of the world that the correction's iterations still work on. The bodies fall
// into groups that the correction moves together: the bodies of one joint tree, whose
// locked axes are solved at once, and each body in no tree on its own. A group stays in
// the region while an iteration moves it by more than the negligible: a joint row's
// update, a contact short of its target, or a contact at which it still approaches. The
// rows and contacts of groups outside it are left as they are, and a tree that no impulse
// reached since its last solve keeps its locked axes held without one. Iterating the
// whole world while any contact in it still approached solved every ragdoll of a pile
// about 8.5 times a pass for the few that a contact kept moving.
class CorrectionRegion {
 public:
  // Each array holds numRigidBodies entries.
  struct Work {
    PfxUInt32* groups = nullptr;
    PfxUInt32* treesToSolve = nullptr;
    PfxUInt8* flags = nullptr;
  };

  CorrectionRegion(const Work& work, const PfxJointTreeSolver& tree,
                   const PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies)
      : m_tree(tree),
        m_solverBodies(solverBodies),
        m_numRigidBodies(numRigidBodies),
        m_groups(work.groups),
        m_treesToSolve(work.treesToSolve),
        m_flags(work.flags) {
    for (PfxUInt32 i = 0; i < numRigidBodies; ++i) {
      const PfxInt32 treeBody = tree.getTreeBody(i);
      m_groups[i] = treeBody >= 0 ? PfxUInt32(treeBody) : i;
      m_flags[i] = 0;
    }
  }

  // The first region: the groups of the joints and couplings whose rows ask to move their
  // bodies (asksToMove), their trees' locked axes to be solved. The other groups join as
  // the contacts and rows of the region push them. False when no row asks.
  bool takeGroupsAsked(const PfxCorrectJointPositionsParam& param) {
    bool any = false;
    const auto take = [&](PfxUInt32 idA, PfxUInt32 idB) {
      mark(idA, kInRegion | kChanged | kToSolve);
      mark(idB, kInRegion | kChanged | kToSolve);
      any = true;
    };
    for (PfxUInt32 i = 0; i < param.numJointPairs; ++i) {
      const PfxConstraintPair& pair = param.jointPairs[i];
      if (!pfxGetActive(pair)) continue;
      const PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
      for (const PfxJointConstraint& c : joint.m_constraints) {
        if (asksToMove(c.m_pushRhs, c.m_constraintRow, param.timeStep)) {
          take(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
          break;
        }
      }
    }
    for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
      const PfxJointCoupling& coupling = param.offsetJointCouplings[i];
      if (!asksToMove(coupling.m_pushRhs, coupling.m_row, param.timeStep)) continue;
      for (PfxUInt32 b = 0; b < coupling.m_numBodies; ++b) {
        const PfxUInt32 id = coupling.m_bodies[b].m_rigidBodyId;
        take(id, id);
      }
    }
    return any;
  }

  bool takes(PfxUInt32 idA, PfxUInt32 idB) const {
    return ((m_flags[group(idA)] | m_flags[group(idB)]) & kInRegion) != 0;
  }
  // An impulse changed the velocities of both bodies (those that move); `moved` when by
  // more than the negligible, `solved` when their trees have been solved since.
  void impulseChanged(PfxUInt32 idA, PfxUInt32 idB, bool moved, bool solved) {
    const PfxUInt8 bits = kChanged | (moved ? kMoved : 0) | (solved ? 0 : kToSolve);
    mark(idA, bits);
    mark(idB, bits);
  }
  void mark(PfxUInt32 id, PfxUInt8 bits) {
    if (m_solverBodies[id].m_massInv > 0) m_flags[group(id)] |= bits;
  }
  // Whether either body's velocities changed in this iteration.
  bool changed(PfxUInt32 idA, PfxUInt32 idB) const {
    return ((m_flags[group(idA)] | m_flags[group(idB)]) & kChanged) != 0;
  }
  // Solves the locked axes of the trees that an impulse reached since their last solve.
  void solveTrees(PfxJointTreeSolver& tree, PfxTaskManager* taskManager) {
    PfxUInt32 count = 0;
    for (PfxUInt32 i = 0; i < m_numRigidBodies; ++i) {
      if ((m_flags[i] & kToSolve) != 0 && m_groups[i] == i && m_tree.getTreeBody(i) >= 0) {
        m_treesToSolve[count++] = i;
      }
    }
    pfxParallelFor(taskManager, count, kTreesSolvedPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
      for (PfxUInt32 k = begin; k < end; ++k) tree.solveTreeOf(m_treesToSolve[k], true);
    });
  }
  // The next iteration's region: the groups this one moved. False when it is empty.
  bool advance() {
    bool any = false;
    for (PfxUInt32 i = 0; i < m_numRigidBodies; ++i) {
      m_flags[i] = (m_flags[i] & kMoved) != 0 ? kInRegion : 0;
      any = any || m_flags[i] != 0;
    }
    return any;
  }

  static constexpr PfxUInt8 kInRegion = 1;
  static constexpr PfxUInt8 kChanged = 2;  // its velocities changed in this iteration
  static constexpr PfxUInt8 kMoved = 4;    // by more than the negligible: in the next region
  static constexpr PfxUInt8 kToSolve = 8;  // its tree's locked axes may no longer hold

 private:
  // A tree's solve takes microseconds: the eight ragdolls of a pile solved on two threads
  // at four a task took half as long again as on one, for the fork and join.
  static constexpr PfxUInt32 kTreesSolvedPerTask = 8;
  PfxUInt32 group(PfxUInt32 id) const { return m_groups[id]; }

  const PfxJointTreeSolver& m_tree;
  const PfxSolverBody* m_solverBodies;
  PfxUInt32 m_numRigidBodies;
  PfxUInt32* m_groups;  // a body of its tree, or the body itself in no tree
  PfxUInt32* m_treesToSolve;
  PfxUInt8* m_flags;
};

// The work buffer, carved once for every pass: the joints' forest, the region, and the
// touching pairs (regionWorkBytes, touchingPairsWorkBytes).
struct CorrectionWork {
  void* tree = nullptr;
  PfxUInt32 treeBytes = 0;
  CorrectionRegion::Work region;
  PfxConstraintPair* touchingPairs = nullptr;
  PfxUInt32 numTouchingPairs = 0;
  PfxUInt8* movedBodies = nullptr;  // by the last pass: kMovedBody, kTurnedBody
};

constexpr PfxUInt8 kMovedBody = 1;
constexpr PfxUInt8 kTurnedBody = 2;  // by more than kLargestTurnOnKeptFactors

// The largest turn of a body in a pass (rad) after which its tree is factored again for
// the next: a Jacobian of that tree then changed by about as much, relative to itself, and
// so does the chord step's error against a Newton step's.
constexpr PfxFloat kLargestTurnOnKeptFactors = PfxFloat(1e-3);

// Marks both bodies of the contacts at which the push velocities move them closer by more
// than the negligible, among the pairs whose bodies' velocities changed in this iteration
// (the others are as they were when last looked at).
void markApproachingContacts(const PfxCorrectJointPositionsParam& param,
                             const PfxConstraintPair* touchingPairs, PfxUInt32 numTouchingPairs,
                             CorrectionRegion& region) {
  const PfxFloat negligible = kNegligibleApproach / param.timeStep;
  for (PfxUInt32 i = 0; i < numTouchingPairs; ++i) {
    const PfxConstraintPair& pair = touchingPairs[i];
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    if (!region.changed(idA, idB)) continue;
    const PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
    const PfxSolverBody& a = param.offsetSolverBodies[idA];
    const PfxSolverBody& b = param.offsetSolverBodies[idB];
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      const PfxContactPoint& cp = manifold.getContactPoint(c);
      if (cp.m_constraintRow[0].m_jacDiagInv <= 0) continue;
      if (pfxContactNormalVelocity(cp, a, b, &PfxSolverBody::m_pushLinearVelocity,
                                   &PfxSolverBody::m_pushAngularVelocity) < -negligible) {
        region.mark(idA, CorrectionRegion::kMoved);
        region.mark(idB, CorrectionRegion::kMoved);
        break;
      }
    }
  }
}

// The contacts take part when the work has touching pairs. `moved` tells whether the pass
// moved the bodies: not when the joints ask for no more than kNegligibleCorrection, since
// the contacts' rows only keep the joints' pushes from closing them. After the first pass,
// only the bodies the last one moved, and their joints, are set up again: the others'
// masses and rows are what a setup would give again, bit for bit, unless the last setup
// turned a translation row round (a limit left for the other), which cleared the impulse
// that the geometric stiffness of its unmoved body still counts. The second pass of the 64
// robots of `pfx_bench --scene robots` moves half of the bodies, the third a quarter.
PfxInt32 correctOnce(const PfxCorrectJointPositionsParam& param, const CorrectionWork& work,
                     PfxJointTreeSolver& tree, bool firstPass, bool lastPass, bool& moved,
                     PfxTaskManager* taskManager) {
  moved = false;
  if (!firstPass && !anyJointMayAskToMove(param, work.movedBodies)) return PFX_OK;
  const PfxConstraintPair* const touchingPairs = work.touchingPairs;
  const PfxUInt32 numTouchingPairs = work.numTouchingPairs;
  const bool seeContacts = numTouchingPairs > 0;
  // Masses at the current orientations, and the joints measured at the current poses.
  // Last step's impulses stay as they are (warm start factor 1): they seed the next
  // velocity solve.
  PfxSetupSolverBodiesParam bodies;
  bodies.states = param.offsetRigidStates;
  bodies.bodies = param.offsetRigidBodies;
  bodies.solverBodies = param.offsetSolverBodies;
  bodies.numRigidBodies = param.numRigidBodies;
  bodies.bodiesToSetUp = firstPass ? nullptr : work.movedBodies;
  pfxSetupSolverBodies(bodies, taskManager);
  PfxSetupJointConstraintsParam setup;
  setup.jointPairs = param.jointPairs;
  setup.numJointPairs = param.numJointPairs;
  setup.offsetJoints = param.offsetJoints;
  setup.numJoints = param.numJoints;
  setup.offsetJointCouplings = param.offsetJointCouplings;
  setup.numJointCouplings = param.numJointCouplings;
  setup.offsetRigidStates = param.offsetRigidStates;
  setup.offsetRigidBodies = param.offsetRigidBodies;
  setup.offsetSolverBodies = param.offsetSolverBodies;
  setup.numRigidBodies = param.numRigidBodies;
  setup.timeStep = param.timeStep;
  setup.warmStartFactor = 1;
  setup.forPositionCorrection = true;
  setup.bodiesToSetUp = bodies.bodiesToSetUp;
  if (const PfxInt32 err = pfxSetupJointConstraints(setup, taskManager); err != PFX_OK) {
    return err;
  }

  // The trees are factored as the region reaches them: once most joints hold, a pass works
  // on a few robots of many. A tree keeps the factors of its first solve for the later
  // passes, which measure the joints anew but solve with the masses and Jacobians of that
  // solve: a chord step instead of a Newton step, whose error is the last pass's, already
  // small, times how far the tree's Jacobians turned since; a tree with a body the last
  // pass turned by more than kLargestTurnOnKeptFactors is factored again.
  if (firstPass) {
    tree.build(work.tree, work.treeBytes, param.jointPairs, param.numJointPairs,
               param.offsetJoints, param.offsetSolverBodies, param.numRigidBodies, taskManager,
               PfxJointTreeSolver::Factoring::kOnFirstSolve);
  } else {
    for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
      if ((work.movedBodies[i] & kTurnedBody) != 0) tree.refactorTreeOf(i);
    }
  }
  CorrectionRegion region(work.region, tree, param.offsetSolverBodies, param.numRigidBodies);
  if (!region.takeGroupsAsked(param)) return PFX_OK;
  moved = true;
  clearContactPushImpulses(touchingPairs, numTouchingPairs, param.offsetContactManifolds);
  // The negligible velocity of a contact's approach, and of a joint row's update as its two
  // bodies alone answer it (rad/s for a rotation).
  const PfxFloat negligible = kNegligibleApproach / param.timeStep;
  // The direct solve is exact: alternating with it pays only while iterated rows act.
  for (PfxUInt32 iteration = 0; iteration < param.iteration; ++iteration) {
    for (PfxUInt32 i = 0; i < param.numJointPairs; ++i) {
      const PfxConstraintPair& pair = param.jointPairs[i];
      if (!pfxGetActive(pair)) continue;
      const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
      if (!region.takes(idA, idB)) continue;
      PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
      PfxSolverBody& a = param.offsetSolverBodies[idA];
      PfxSolverBody& b = param.offsetSolverBodies[idB];
      const PfxFloat receivesA = pfxGetReceivesA(pair) ? 1 : 0;
      const PfxFloat receivesB = pfxGetReceivesB(pair) ? 1 : 0;
      const bool direct = tree.contains(i);
      for (PfxUInt32 axis = 0; axis < 6; ++axis) {
        PfxJointConstraint& c = joint.m_constraints[axis];
        const bool lockedDirectly =
            direct && c.m_rowType == kPfxJointRowEquality && c.m_weight == 1;
        if (c.m_rowType == kPfxJointRowNone || lockedDirectly) continue;
        if (c.m_pushRhs == 0 && c.m_pushImpulse == 0) continue;
        const PfxFloat previous = c.m_pushImpulse;
        pfxSolveJointPushRow(c, joint, axis, a, receivesA, b, receivesB);
        const PfxFloat change = std::abs(c.m_pushImpulse - previous);
        if (change == 0) continue;
        region.impulseChanged(idA, idB, change > negligible * c.m_constraintRow.m_jacDiagInv,
                              false);
      }
    }
    for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
      PfxJointCoupling& coupling = param.offsetJointCouplings[i];
      if (coupling.m_pushRhs == 0 && coupling.m_pushImpulse == 0) continue;
      const PfxJoint& leader = param.offsetJoints[coupling.m_leaderJointId];
      const PfxJoint& follower = param.offsetJoints[coupling.m_followerJointId];
      if (!region.takes(leader.m_rigidBodyIdA, leader.m_rigidBodyIdB) &&
          !region.takes(follower.m_rigidBodyIdA, follower.m_rigidBodyIdB)) {
        continue;
      }
      pfxSolveJointCouplingBlock(coupling, param.offsetJoints, param.offsetSolverBodies, true);
      region.impulseChanged(leader.m_rigidBodyIdA, leader.m_rigidBodyIdB, true, false);
      region.impulseChanged(follower.m_rigidBodyIdA, follower.m_rigidBodyIdB, true, false);
    }
    if (seeContacts) {
      pfxSweepTreeContacts(touchingPairs, numTouchingPairs, param.offsetContactManifolds,
                           param.offsetSolverBodies, tree,
                           PfxTreeContactVelocities::kPush,
                           lastPass ? PfxTreeContactPairs::kOnTrees : PfxTreeContactPairs::kAll,
                           negligible, region);
    }
    region.solveTrees(tree, taskManager);
    if (seeContacts) markApproachingContacts(param, touchingPairs, numTouchingPairs, region);
    if (!region.advance()) break;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kCorrectedBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     const PfxSolverBody& body = param.offsetSolverBodies[i];
                     work.movedBodies[i] = 0;
                     if (body.m_massInv == 0 ||
                         !pfxApplyPush(param.offsetRigidStates[i], body, param.timeStep)) {
                       continue;
                     }
                     const bool turned = body.m_pushAngularVelocity.norm() * param.timeStep >
                                         kLargestTurnOnKeptFactors;
                     work.movedBodies[i] = kMovedBody | (turned ? kTurnedBody : 0);
                   }
                 });
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxCorrectJointPositions(const PfxCorrectJointPositionsParam& param,
                                  PfxTaskManager* taskManager) {
  if (param.numJointPairs == 0) return PFX_OK;
  const PfxParamNames at{"pfxCorrectJointPositions", "PfxCorrectJointPositionsParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.jointPairs, "jointPairs"},
                               {param.offsetJoints, "offsetJoints"},
                               {param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetRigidBodies, "offsetRigidBodies"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numJointPairs", param.numJointPairs)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "jointPairs", param.jointPairs, param.numJointPairs,
                                  param.numRigidBodies, "numJoints", param.numJoints)) != PFX_OK ||
      (err = pfxCheckRequired(at,
                              {{param.contactPairs, "contactPairs"},
                               {param.offsetContactManifolds, "offsetContactManifolds"}},
                              "numContactPairs", param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "numContactManifolds",
                                  param.numContactManifolds)) != PFX_OK) {
    return err;
  }
  const PfxUInt32 workBytes = pfxGetWorkBytesOfCorrectJointPositions(
      param.numRigidBodies, param.numJointPairs, param.numContactPairs);
  if (!param.workBuff || param.workBytes < workBytes) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "pfxCorrectJointPositions: PfxCorrectJointPositionsParam::workBuff "
                          "holds %u bytes; pfxGetWorkBytesOfCorrectJointPositions asks %u",
                          param.workBuff ? param.workBytes : 0, workBytes);
  }

  // Each pass measures the joints at the current poses and moves the bodies to cancel the
  // errors, linearised there: a Newton step (a chord step for a tree the last pass barely
  // turned, see correctOnce). One pass leaves tens of micrometres on a fast 100-link chain
  // at 1/60 s, two leave a few.
  // With contact points, three passes: the contacts take part in the first two, and in the
  // third only those between a tree and what does not move, so that it leaves the joints
  // closed where a tree's contacts with itself contradict them (a chain folded onto
  // itself); a third pass of the joints alone closed an ankle opened on landing by pressing
  // the foot back into the ground (10 cm at dt 1/30). Without, two passes do (the third
  // cost a hanging chain a quarter of its step). The choice follows the contacts there
  // are, not whether they acted in this step: going from two passes to three and back from
  // step to step kept the seed's ragdoll creeping at 4 cm/s for 20 s.
  CorrectionWork work;
  PfxWorkCarver carver(param.workBuff, workBytes);
  work.treeBytes = PfxJointTreeSolver::getWorkBytes(param.numRigidBodies, param.numJointPairs);
  work.tree = carver.take<unsigned char>(work.treeBytes);
  work.region.groups = carver.take<PfxUInt32>(param.numRigidBodies);
  work.region.treesToSolve = carver.take<PfxUInt32>(param.numRigidBodies);
  work.region.flags = carver.take<PfxUInt8>(param.numRigidBodies);
  work.movedBodies = carver.take<PfxUInt8>(param.numRigidBodies);
  work.touchingPairs = carver.take<PfxConstraintPair>(param.numContactPairs);
  work.numTouchingPairs = gatherTouchingPairs(param, work.touchingPairs);
  const PfxUInt32 passes =
      work.numTouchingPairs > 0 || param.contactPassAnyway ? kNewtonPasses + 1 : kNewtonPasses;
  // A pass that leaves the bodies where they are would measure the same joints again.
  bool moved = true;
  PfxJointTreeSolver tree;
  for (PfxUInt32 pass = 0; pass < passes && moved; ++pass) {
    const bool last = pass + 1 == passes;
    if ((err = correctOnce(param, work, tree, pass == 0, last, moved, taskManager)) != PFX_OK) {
      return err;
    }
  }
  return PFX_OK;
}

}  // namespace pfx
