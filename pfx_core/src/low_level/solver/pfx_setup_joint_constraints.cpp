#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_joint_coupling_row.h"
#include "low_level/solver/pfx_joint_row.h"

namespace pfx {

namespace {

constexpr PfxFloat kUnboundedImpulse = std::numeric_limits<PfxFloat>::max();
constexpr PfxUInt32 kJointsPerTask = 64;
// The geometric stiffness's chunks of bodies: each looks through every joint, so a few per
// thread, and a small world in one: two chunks, each looking through every joint, took
// longer on two threads than one chunk on one (the piled ragdolls).
constexpr PfxUInt32 kMinStiffenedBodiesPerChunk = 256;
constexpr PfxUInt32 kMaxStiffenedChunks = 16;

struct JointBodies {
  const PfxRigidState& stateA;
  const PfxRigidState& stateB;
  const PfxSolverBody& a;
  const PfxSolverBody& b;
  PfxFloat receivesA;
  PfxFloat receivesB;
};

// Velocity of the row from the bodies' current velocities.
PfxFloat rowVelocity(const PfxJointRowJacobian& j, const JointBodies& bodies) {
  return pfxJointRowVelocity(j, bodies.stateA.getLinearVelocity(),
                             bodies.stateA.getAngularVelocity(), bodies.stateB.getLinearVelocity(),
                             bodies.stateB.getAngularVelocity());
}

// What a setup computes: every row's direction, bounds and warm-started impulse, its
// effective mass and push where the position correction reads them, and, unless it sets
// up the position correction, the velocity each row aims for (m_rhs) and the drive rows'
// effective masses, which only the velocity solve reads.
struct SetupMode {
  PfxFloat timeStep;
  PfxFloat warmStartFactor;
  bool velocities;
};

// The row's direction, its impulse's bounds and its warm-started impulse.
void setRowBounds(PfxConstraintRow& row, const PfxVector3& direction, PfxFloat lower,
                  PfxFloat upper, PfxFloat warmStartFactor) {
  // A row that turned round (the other limit) starts afresh.
  if (row.m_normal.dot(direction) <= 0) row.m_accumImpulse = 0;
  row.m_normal = direction;
  row.m_lowerLimit = lower;
  row.m_upperLimit = upper;
  row.m_accumImpulse = std::clamp(row.m_accumImpulse * warmStartFactor, lower, upper);
}

// Sets `row` to move the coordinate at `targetVelocity` along `direction`, its impulse
// clamped to [lower, upper] and scaled by the axis weight.
void setRow(PfxConstraintRow& row, const PfxJoint& joint, PfxUInt32 axis,
            const PfxVector3& direction, PfxFloat targetVelocity, PfxFloat lower, PfxFloat upper,
            PfxFloat weight, const SetupMode& mode, const JointBodies& bodies) {
  setRowBounds(row, direction, lower, upper, mode.warmStartFactor);
  const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, direction);
  const PfxFloat jacDiagInv =
      pfxJointRowJacDiagInv(j, bodies.a, bodies.receivesA, bodies.b, bodies.receivesB);
  row.m_jacDiagInv = weight * jacDiagInv;
  if (mode.velocities) {
    row.m_rhs = weight * (targetVelocity - rowVelocity(j, bodies)) * jacDiagInv;
  }
}

// A velocity a row aims for along `axis`, cut to the speeds a body keeps (kPfxMaxLinearSpeed,
// kPfxMaxAngularSpeed): a position drive 1e18 m from its target with no force limit asked
// for 6e19 m/s, and the bodies it reached had velocities whose squares overflowed.
PfxFloat withinSpeedLimit(PfxUInt32 axis, PfxFloat velocity) {
  const PfxFloat limit = axis < 3 ? kPfxMaxLinearSpeed : kPfxMaxAngularSpeed;
  return std::clamp(velocity, -limit, limit);
}

void unsetRow(PfxConstraintRow& row) {
  row.m_jacDiagInv = 0;
  row.m_rhs = 0;
  row.m_lowerLimit = row.m_upperLimit = 0;
  row.m_accumImpulse = 0;
}

// The lock row of one axis, as pfxLockRow measures it: equality, the nearer limit, or
// nothing.
void setupLockRow(PfxJoint& joint, PfxUInt32 axis, const PfxVector3& direction,
                  const PfxLockRow& lock, const SetupMode& mode, const JointBodies& bodies) {
  const PfxFloat timeStep = mode.timeStep;
  PfxJointConstraint& c = joint.m_constraints[axis];
  c.m_pushRhs = 0;
  c.m_pushImpulse = 0;
  c.m_rowType = lock.type;
  if (lock.type == kPfxJointRowNone) {
    unsetRow(c.m_constraintRow);
    return;
  }
  if (lock.type == kPfxJointRowEquality) {
    setRow(c.m_constraintRow, joint, axis, direction, 0, -kUnboundedImpulse, kUnboundedImpulse,
           c.m_weight, mode, bodies);
  } else {
    // The nearer limit, as a one-sided row along +direction (lower) or -direction (upper).
    // Away from it, the gap may close within the step but no further, as for contacts.
    const PfxFloat gap = lock.error;
    setRow(c.m_constraintRow, joint, axis, lock.atLower ? direction : PfxVector3(-direction),
           gap > 0 ? -gap / timeStep : 0, 0, kUnboundedImpulse, c.m_weight, mode, bodies);
    if (!(gap < 0)) return;
  }
  c.m_pushRhs = withinSpeedLimit(axis, pfxLockRowPushVelocity(c, lock, timeStep)) *
                c.m_constraintRow.m_jacDiagInv;
}

// The velocities along an axis that keep it within its limits over the step (beyond a
// limit: that take it no further out). Only for an axis whose limit row measures the
// drive's own coordinate.
struct AllowedVelocities {
  PfxFloat lower = -kUnboundedImpulse;
  PfxFloat upper = kUnboundedImpulse;
};

AllowedVelocities allowedVelocities(const PfxJointConstraint& c, PfxFloat timeStep) {
  AllowedVelocities allowed;
  if (c.m_rowType == kPfxJointRowNone) return allowed;
  allowed.lower = std::min(PfxFloat(0), (c.m_movableLowerLimit - c.m_position) / timeStep);
  allowed.upper = std::max(PfxFloat(0), (c.m_movableUpperLimit - c.m_position) / timeStep);
  return allowed;
}

// The drive row: a drive toward its target, or friction and damping against the motion.
// A drive's target velocity stays within `allowed`: a drive asking to go past a limit and
// the limit row would both be met only by impulses growing without bound, and with no
// force limit the row solved last would win (a hinge driven 0.9 rad through its stop, its
// neighbours pulled open). Within the limits, both rows ask for the same velocity.
void setupDriveRow(PfxJoint& joint, PfxUInt32 axis, const PfxVector3& direction,
                   const AllowedVelocities& allowed, const SetupMode& mode,
                   const JointBodies& bodies) {
  const PfxFloat timeStep = mode.timeStep;
  PfxJointConstraint& c = joint.m_constraints[axis];
  const bool movable = c.m_lock != kPfxJointLockLocked;
  PfxFloat target = 0;
  PfxFloat bound = kUnboundedImpulse;
  if (movable && c.m_drive == kPfxJointDriveVelocity) {
    target = std::clamp(c.m_driveTarget, allowed.lower, allowed.upper);
    bound = c.m_driveMaxForce * timeStep;
  } else if (movable && c.m_drive == kPfxJointDrivePosition) {
    target = std::clamp((c.m_driveTarget - c.m_position) / timeStep, allowed.lower, allowed.upper);
    bound = c.m_driveMaxForce * timeStep;
  } else if (movable && c.m_friction == 0 && c.m_damping > 0 && !mode.velocities) {
    // Damping's target is a velocity, and its impulse unbounded: nothing to measure.
  } else if (movable && (c.m_damping > 0 || c.m_friction > 0)) {
    // Damping alone takes its fraction of the velocity away. Friction tries to stop the
    // axis outright, within its force, and damping then adds its share to that force.
    const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, direction);
    const PfxFloat velocity = rowVelocity(j, bodies);
    if (c.m_friction > 0) {
      const PfxFloat jacDiagInv =
          pfxJointRowJacDiagInv(j, bodies.a, bodies.receivesA, bodies.b, bodies.receivesB);
      target = 0;
      bound = c.m_friction * timeStep + c.m_damping * std::abs(velocity) * jacDiagInv;
    } else {
      target = (1 - c.m_damping) * velocity;
    }
  } else {
    c.m_driveRowUsed = 0;
    unsetRow(c.m_driveRow);
    return;
  }
  c.m_driveRowUsed = 1;
  if (!mode.velocities) {
    setRowBounds(c.m_driveRow, direction, -bound, bound, mode.warmStartFactor);
    return;
  }
  setRow(c.m_driveRow, joint, axis, direction, withinSpeedLimit(axis, target), -bound, bound,
         c.m_weight, mode, bodies);
}

void setupJoint(PfxJoint& joint, const JointBodies& bodies, const SetupMode& mode) {
  pfxCalcJointAxes(joint, bodies.stateA, bodies.stateB);
  PfxFloat positions[6];
  for (PfxUInt32 axis = 0; axis < 6; ++axis) positions[axis] = joint.m_constraints[axis].m_position;
  for (PfxUInt32 axis = 0; axis < 6; ++axis) {
    const PfxJointConstraint& c = joint.m_constraints[axis];
    const PfxLockRow lock = pfxLockRow(joint, axis, positions);
    PfxVector3 direction = joint.m_axes[axis];
    if (lock.cone) {
      // The cone's row turns about the axis the swing turns about.
      if (lock.position > PFX_EPSILON) {
        const PfxMatrix3 frameA =
            bodies.stateA.getOrientation().toRotationMatrix() * joint.m_frameA;
        direction = frameA * PfxVector3(0, positions[kPfxJointAxisSwing1],
                                        positions[kPfxJointAxisSwing2]) /
                    lock.position;
      }
      joint.m_axes[axis] = direction;
    }
    setupLockRow(joint, axis, direction, lock, mode, bodies);
    // The cone's limit row measures the swing angle, not the drive's coordinate.
    const AllowedVelocities allowed =
        lock.cone ? AllowedVelocities() : allowedVelocities(c, mode.timeStep);
    setupDriveRow(joint, axis, direction, allowed, mode, bodies);
  }
}

// Geometric stiffness, in the diagonal approximation of Andrews, Teichmann and Kry,
// "Geometric Stiffness for Real-time Constrained Multibody Dynamics" (2017). A joint that
// pulls with force F at an arm r resists turning its body with a stiffness of about F r
// (N m per radian). Light links under a heavy load make that stiffness so high that a step
// overshoots it, and the chain shakes itself apart; adding h^2 F r = h |impulse| r to the
// body's inertia in the solve, as an implicit step would, keeps it stable. The impulse is
// last step's, so a joint that starts to pull gets the extra inertia one step later.
// A body's joints add their stiffness up, and its inverse inertia is formed once from the
// sum (stiffenInertia): R I R^T + s 1 = R (I + s 1) R^T, one 3 x 3 inverse in the body's
// frame, where it took two a joint end in the world's, 3.7 % of the robots' step.
// `anchor` is the joint's anchor in the body's frame: the arm's length is its length, in any
// pose, so the arm is not turned into the world's frame.
void addGeometricStiffness(PfxSolverBody& body, PfxFloat impulse, const PfxVector3& anchor,
                           PfxFloat timeStep) {
  if (body.m_massInv == 0) return;
  const PfxFloat boost = timeStep * impulse * anchor.norm();
  if (boost > 0) body.m_stiffnessInertia += boost;
}

// The extra inertia is held to a million times the body's own: a joint holding a heavy robot
// by a light link adds a few hundred times, and one whose impulse came from a body flung at
// 1e15 m/s made the inertia so large that the joint tree solver's factors overflowed to NaN.
// Held once for the sum, it is what holding each joint's share in turn gave.
constexpr PfxFloat kMaxStiffnessBoost = PfxFloat(1e6);
void stiffenInertia(PfxSolverBody& body, const PfxRigidBody& rigidBody,
                    const PfxRigidState& state) {
  if (!(body.m_stiffnessInertia > 0)) return;
  body.m_stiffnessInertia = std::min(
      body.m_stiffnessInertia, kMaxStiffnessBoost * rigidBody.getInertia().diagonal().maxCoeff());
  const PfxMatrix3 stiffened =
      rigidBody.getInertia() + body.m_stiffnessInertia * PfxMatrix3::Identity();
  body.m_inertiaInv =
      pfxRotateInertia(state.getOrientation().toRotationMatrix(), pfxInverseDefinite(stiffened));
}

}  // namespace

PfxInt32 pfxSetupJointConstraints(const PfxSetupJointConstraintsParam& param,
                                  PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxSetupJointConstraints", "PfxSetupJointConstraintsParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.offsetJointCouplings, "offsetJointCouplings"},
                               {param.offsetJoints, "offsetJoints"},
                               {param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numJointCouplings", param.numJointCouplings)) != PFX_OK ||
      (err = pfxCheckRequired(at,
                              {{param.jointPairs, "jointPairs"},
                               {param.offsetJoints, "offsetJoints"},
                               {param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetRigidBodies, "offsetRigidBodies"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numJointPairs", param.numJointPairs)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(at, "warmStartFactor", param.warmStartFactor,
                           param.warmStartFactor >= 0 && param.warmStartFactor <= 1,
                           "within [0, 1]")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "jointPairs", param.jointPairs, param.numJointPairs,
                                  param.numRigidBodies, "numJoints", param.numJoints)) != PFX_OK) {
    return err;
  }
  // A coupling names joints by id, which only the count of joints can vouch for.
  for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
    const PfxJointCoupling& coupling = param.offsetJointCouplings[i];
    if (coupling.m_leaderJointId >= param.numJoints ||
        coupling.m_followerJointId >= param.numJoints) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxSetupJointConstraints: PfxSetupJointConstraintsParam::"
                            "offsetJointCouplings[%u] names joints %u and %u, but numJoints is %u",
                            i, coupling.m_leaderJointId, coupling.m_followerJointId,
                            param.numJoints);
    }
    if (coupling.m_leaderAxis > 5 || coupling.m_followerAxis > 5) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxSetupJointConstraints: PfxSetupJointConstraintsParam::"
                            "offsetJointCouplings[%u] names axes %u and %u; an axis is 0 to 5",
                            i, PfxUInt32(coupling.m_leaderAxis),
                            PfxUInt32(coupling.m_followerAxis));
    }
    for (const PfxUInt32 jointId : {coupling.m_leaderJointId, coupling.m_followerJointId}) {
      const PfxJoint& joint = param.offsetJoints[jointId];
      if (joint.m_rigidBodyIdA >= param.numRigidBodies ||
          joint.m_rigidBodyIdB >= param.numRigidBodies) {
        return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                              "pfxSetupJointConstraints: PfxSetupJointConstraintsParam::"
                              "offsetJoints[%u] joins bodies %u and %u, but numRigidBodies is %u",
                              jointId, joint.m_rigidBodyIdA, joint.m_rigidBodyIdB,
                              param.numRigidBodies);
      }
    }
  }
  // A body sums the stiffness of its joints in joint order, which fixes its bits; the
  // bodies are split into chunks that each look through every joint for their own bodies,
  // so that the chunks, and the threads, share no body.
  const PfxUInt32 numChunks =
      param.numJointPairs == 0 ? 0
                               : pfxNumChunks(taskManager, param.numRigidBodies,
                                              kMinStiffenedBodiesPerChunk, kMaxStiffenedChunks);
  pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 firstChunk, PfxUInt32 lastChunk) {
    const PfxUInt32 begin = pfxChunkBegin(param.numRigidBodies, numChunks, firstChunk);
    const PfxUInt32 end = pfxChunkBegin(param.numRigidBodies, numChunks, lastChunk);
    // The chunk's bodies that this setup sets up.
    auto stiffensHere = [&](PfxUInt32 id) {
      return id >= begin && id < end && (!param.bodiesToSetUp || param.bodiesToSetUp[id] != 0);
    };
    for (PfxUInt32 i = 0; i < param.numJointPairs; ++i) {
      const PfxConstraintPair& pair = param.jointPairs[i];
      if (!pfxGetActive(pair)) continue;
      const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
      const bool stiffensA = pfxGetReceivesA(pair) && stiffensHere(idA);
      const bool stiffensB = pfxGetReceivesB(pair) && stiffensHere(idB);
      if (!stiffensA && !stiffensB) continue;
      const PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
      PfxVector3 linearImpulse;
      for (int k = 0; k < 3; ++k) {
        linearImpulse[k] = joint.m_constraints[k].m_constraintRow.m_accumImpulse;
      }
      const PfxFloat impulse = linearImpulse.norm();
      if (stiffensA) {
        addGeometricStiffness(param.offsetSolverBodies[idA], impulse, joint.m_anchorA,
                              param.timeStep);
      }
      if (stiffensB) {
        addGeometricStiffness(param.offsetSolverBodies[idB], impulse, joint.m_anchorB,
                              param.timeStep);
      }
    }
    for (PfxUInt32 id = begin; id < end; ++id) {
      if (!stiffensHere(id)) continue;
      stiffenInertia(param.offsetSolverBodies[id], param.offsetRigidBodies[id],
                     param.offsetRigidStates[id]);
    }
  });
  const SetupMode mode{param.timeStep, param.warmStartFactor, !param.forPositionCorrection};
  pfxParallelFor(taskManager, param.numJointPairs, kJointsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 i = begin; i < end; ++i) {
      const PfxConstraintPair& pair = param.jointPairs[i];
      if (!pfxGetActive(pair)) continue;
      const PfxUInt32 idA = pfxGetObjectIdA(pair);
      const PfxUInt32 idB = pfxGetObjectIdB(pair);
      PfxJoint& joint = param.offsetJoints[pfxGetConstraintId(pair)];
      if (param.bodiesToSetUp && param.bodiesToSetUp[idA] == 0 &&
          param.bodiesToSetUp[idB] == 0) {
        for (PfxJointConstraint& c : joint.m_constraints) c.m_pushImpulse = 0;
        continue;
      }
      const JointBodies bodies{param.offsetRigidStates[idA], param.offsetRigidStates[idB],
                               param.offsetSolverBodies[idA], param.offsetSolverBodies[idB],
                               pfxGetReceivesA(pair) ? PfxFloat(1) : PfxFloat(0),
                               pfxGetReceivesB(pair) ? PfxFloat(1) : PfxFloat(0)};
      setupJoint(joint, bodies, mode);
    }
  });
  for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
    PfxJointCoupling& coupling = param.offsetJointCouplings[i];
    if (!coupling.m_active || !param.offsetJoints[coupling.m_leaderJointId].m_active ||
        !param.offsetJoints[coupling.m_followerJointId].m_active) {
      coupling.m_numBodies = 0;
      coupling.m_pushRhs = coupling.m_pushImpulse = 0;
      unsetRow(coupling.m_row);
      continue;
    }
    pfxSetupJointCouplingRow(coupling, param.offsetJoints, param.offsetRigidStates,
                             param.offsetSolverBodies, param.timeStep, param.warmStartFactor);
  }
  return PFX_OK;
}

}  // namespace pfx
