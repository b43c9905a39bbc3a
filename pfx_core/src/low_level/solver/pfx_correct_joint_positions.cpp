#include "pfx/low_level/solver/pfx_correct_joint_positions.h"

#include <algorithm>

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_joint_coupling_row.h"
#include "low_level/solver/pfx_joint_row.h"
#include "low_level/solver/pfx_joint_tree_solver.h"
#include "low_level/solver/pfx_tree_contact_rows.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

namespace pfx {

PfxUInt32 pfxGetWorkBytesOfCorrectJointPositions(PfxUInt32 numRigidBodies,
                                                 PfxUInt32 numJointPairs) {
  return numJointPairs > 0 ? PfxJointTreeSolver::getWorkBytes(numRigidBodies, numJointPairs) : 0;
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
void clearContactPushImpulses(const PfxCorrectJointPositionsParam& param) {
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (!pfxGetActive(pair)) continue;
    PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      manifold.getContactPoint(c).m_pushImpulse = 0;
    }
  }
}

bool anyContactPoint(const PfxCorrectJointPositionsParam& param) {
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (pfxGetActive(pair) &&
        param.offsetContactManifolds[pfxGetContactId(pair)].getNumContacts() > 0) {
      return true;
    }
  }
  return false;
}

// How far the correction may move two bodies closer at a contact point before the
// contacts call for more iterations (m): far below the contact slop, and a standing robot,
// whose joints press its feet into the ground by micrometres every pass, then costs no
// iterations beyond the joints' own.
constexpr PfxFloat kNegligibleApproach = PfxFloat(1e-4);

// Whether the push velocities move two bodies closer at any contact point by more than
// that: while they do not, the correction needs no iteration for the contacts.
bool anyContactApproached(const PfxCorrectJointPositionsParam& param) {
  const PfxFloat negligible = kNegligibleApproach / param.timeStep;
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
    const PfxSolverBody& a = param.offsetSolverBodies[pfxGetObjectIdA(pair)];
    const PfxSolverBody& b = param.offsetSolverBodies[pfxGetObjectIdB(pair)];
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      const PfxContactPoint& cp = manifold.getContactPoint(c);
      if (cp.m_constraintRow[0].m_jacDiagInv <= 0) continue;
      if (pfxContactNormalVelocity(cp, a, b, &PfxSolverBody::m_pushLinearVelocity,
                                   &PfxSolverBody::m_pushAngularVelocity) < -negligible) {
        return true;
      }
    }
  }
  return false;
}

PfxInt32 correctOnce(const PfxCorrectJointPositionsParam& param, bool seeContacts, bool lastPass,
                     PfxTaskManager* taskManager) {
  // Masses at the current orientations, and the joints measured at the current poses.
  // Last step's impulses stay as they are (warm start factor 1): they seed the next
  // velocity solve.
  PfxSetupSolverBodiesParam bodies;
  bodies.states = param.offsetRigidStates;
  bodies.bodies = param.offsetRigidBodies;
  bodies.solverBodies = param.offsetSolverBodies;
  bodies.numRigidBodies = param.numRigidBodies;
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
  if (const PfxInt32 err = pfxSetupJointConstraints(setup, taskManager); err != PFX_OK) {
    return err;
  }

  PfxJointTreeSolver tree;
  tree.build(param.workBuff, param.workBytes, param.jointPairs, param.numJointPairs,
             param.offsetJoints, param.offsetSolverBodies, param.numRigidBodies, taskManager);
  if (seeContacts) clearContactPushImpulses(param);
  // The direct solve is exact: alternating with it pays only while iterated rows act.
  for (PfxUInt32 iteration = 0; iteration < param.iteration; ++iteration) {
    bool iterated = false;
    for (PfxUInt32 i = 0; i < param.numJointPairs; ++i) {
      const PfxConstraintPair& pair = param.jointPairs[i];
      if (!pfxGetActive(pair)) continue;
      PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
      PfxSolverBody& a = param.offsetSolverBodies[pfxGetObjectIdA(pair)];
      PfxSolverBody& b = param.offsetSolverBodies[pfxGetObjectIdB(pair)];
      const PfxFloat receivesA = pfxGetReceivesA(pair) ? 1 : 0;
      const PfxFloat receivesB = pfxGetReceivesB(pair) ? 1 : 0;
      const bool direct = tree.contains(i);
      for (PfxUInt32 axis = 0; axis < 6; ++axis) {
        PfxJointConstraint& c = joint.m_constraints[axis];
        const bool lockedDirectly =
            direct && c.m_rowType == kPfxJointRowEquality && c.m_weight == 1;
        if (c.m_rowType == kPfxJointRowNone || lockedDirectly) continue;
        if (c.m_pushRhs == 0 && c.m_pushImpulse == 0) continue;
        pfxSolveJointPushRow(c, joint, axis, a, receivesA, b, receivesB);
        iterated = true;
      }
    }
    for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
      PfxJointCoupling& coupling = param.offsetJointCouplings[i];
      if (coupling.m_pushRhs == 0 && coupling.m_pushImpulse == 0) continue;
      pfxSolveJointCouplingBlock(coupling, param.offsetJoints, param.offsetSolverBodies, true);
      iterated = true;
    }
    if (seeContacts &&
        pfxSweepTreeContacts(param.contactPairs, param.numContactPairs,
                             param.offsetContactManifolds, param.offsetSolverBodies, tree,
                             PfxTreeContactVelocities::kPush,
                             lastPass ? PfxTreeContactPairs::kOnTrees : PfxTreeContactPairs::kAll,
                             kNegligibleApproach / param.timeStep)) {
      iterated = true;
    }
    tree.solvePush(taskManager);
    if (!iterated && !(seeContacts && anyContactApproached(param))) break;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kCorrectedBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     if (param.offsetSolverBodies[i].m_massInv == 0) continue;
                     pfxApplyPush(param.offsetRigidStates[i], param.offsetSolverBodies[i],
                                  param.timeStep);
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
  const PfxUInt32 workBytes =
      pfxGetWorkBytesOfCorrectJointPositions(param.numRigidBodies, param.numJointPairs);
  if (!param.workBuff || param.workBytes < workBytes) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "pfxCorrectJointPositions: PfxCorrectJointPositionsParam::workBuff "
                          "holds %u bytes; pfxGetWorkBytesOfCorrectJointPositions asks %u",
                          param.workBuff ? param.workBytes : 0, workBytes);
  }

  // Each pass measures the joints at the current poses and moves the bodies to cancel the
  // errors, linearised there: a Newton step. One pass leaves tens of micrometres on a fast
  // 100-link chain at 1/60 s, two leave a few.
  // With contact points, three passes: the contacts take part in the first two, and in the
  // third only those between a tree and what does not move, so that it leaves the joints
  // closed where a tree's contacts with itself contradict them (a chain folded onto
  // itself); a third pass of the joints alone closed an ankle opened on landing by pressing
  // the foot back into the ground (10 cm at dt 1/30). Without, two passes do (the third
  // cost a hanging chain a quarter of its step). The choice follows the contacts there
  // are, not whether they acted in this step: going from two passes to three and back from
  // step to step kept the seed's ragdoll creeping at 4 cm/s for 20 s.
  const bool withContacts = anyContactPoint(param);
  const PfxUInt32 passes = withContacts ? kNewtonPasses + 1 : kNewtonPasses;
  for (PfxUInt32 pass = 0; pass < passes; ++pass) {
    const bool last = pass + 1 == passes;
    if ((err = correctOnce(param, withContacts, last, taskManager)) != PFX_OK) return err;
  }
  return PFX_OK;
}

}  // namespace pfx
