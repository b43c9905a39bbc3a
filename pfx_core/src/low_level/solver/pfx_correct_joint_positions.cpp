#include "pfx/low_level/solver/pfx_correct_joint_positions.h"

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_joint_coupling_row.h"
#include "low_level/solver/pfx_joint_row.h"
#include "low_level/solver/pfx_joint_tree_solver.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

namespace pfx {

PfxUInt32 pfxGetWorkBytesOfCorrectJointPositions(PfxUInt32 numRigidBodies,
                                                 PfxUInt32 numJointPairs) {
  return numJointPairs > 0 ? PfxJointTreeSolver::getWorkBytes(numRigidBodies, numJointPairs) : 0;
}

namespace {

constexpr PfxUInt32 kNewtonPasses = 2;

constexpr PfxUInt32 kBodiesPerTask = 512;

PfxInt32 correctOnce(const PfxCorrectJointPositionsParam& param, PfxTaskManager* taskManager) {
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
    tree.solvePush(taskManager);
    if (!iterated) break;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kBodiesPerTask,
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
      (err = pfxCheckValue(at, "timeStep", param.timeStep,
                           param.timeStep > 0 && pfxIsFinite(param.timeStep),
                           "positive and finite")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "jointPairs", param.jointPairs, param.numJointPairs,
                                  param.numRigidBodies, "numJoints", param.numJoints)) != PFX_OK) {
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
  for (PfxUInt32 pass = 0; pass < kNewtonPasses; ++pass) {
    if ((err = correctOnce(param, taskManager)) != PFX_OK) return err;
  }
  return PFX_OK;
}

}  // namespace pfx
