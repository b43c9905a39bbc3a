#include "pfx/low_level/rigidbody/pfx_apply_joint_efforts.h"

#include <algorithm>

#include "low_level/pfx_param_checks.h"
#include "low_level/rigidbody/pfx_speed_limit.h"
#include "low_level/solver/pfx_joint_row.h"

namespace pfx {

namespace {

bool movedByEfforts(const PfxRigidState& state) {
  return pfxMotionTypeIsDynamic(state.getMotionType()) && state.isAwake();
}

bool pushes(const PfxJointConstraint& c) {
  return c.m_drive == kPfxJointDriveEffort && c.m_lock != kPfxJointLockLocked;
}

// v += m^-1 J^T impulse for one side of the row, each speed then cut to the limits of stage
// (1), as a force's: an effort of 1e18 N on a body of 1e-12 kg made 1.7e28 m/s, whose square
// overflows.
void applyImpulse(PfxRigidState& state, const PfxRigidBody& body, const PfxVector3& linear,
                  const PfxVector3& angular, PfxFloat impulse) {
  if (!movedByEfforts(state)) return;
  const PfxMatrix3 inertiaInv =
      pfxRotateInertia(state.getOrientation().toRotationMatrix(), body.getInertiaInv());
  const PfxVector3& linearVelocity = state.getLinearVelocity();
  const PfxVector3 pushed = linearVelocity + (body.getMassInv() * impulse) * linear;
  state.setLinearVelocity(pfxWithinSpeed(pushed, kPfxMaxLinearSpeed, [&]() -> PfxWideVector {
    return pfxWide(linearVelocity) +
           (long double)body.getMassInv() * (long double)impulse * pfxWide(linear);
  }));
  const PfxVector3& angularVelocity = state.getAngularVelocity();
  pfxTurnWithinSpeed(state, impulse * (inertiaInv * angular), [&]() -> PfxWideVector {
    return pfxWide(angularVelocity) +
           (long double)impulse * (inertiaInv.cast<long double>() * pfxWide(angular));
  });
}

}  // namespace

PfxInt32 pfxApplyJointEfforts(const PfxApplyJointEffortsParam& param) {
  const PfxParamNames at{"pfxApplyJointEfforts", "PfxApplyJointEffortsParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.joints, "joints"},
                               {param.states, "states"},
                               {param.bodies, "bodies"}},
                              "numJoints", param.numJoints)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < param.numJoints; ++i) {
    const PfxJoint& joint = param.joints[i];
    if (!joint.m_active) continue;
    for (PfxUInt32 axis = 0; axis < 6; ++axis) {
      const PfxJointConstraint& c = joint.m_constraints[axis];
      if (c.m_drive != kPfxJointDriveEffort) continue;
      if (joint.m_rigidBodyIdA >= param.numRigidBodies ||
          joint.m_rigidBodyIdB >= param.numRigidBodies) {
        return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                              "pfxApplyJointEfforts: PfxApplyJointEffortsParam::joints[%u] joins "
                              "bodies %u and %u, but numRigidBodies is %u",
                              i, joint.m_rigidBodyIdA, joint.m_rigidBodyIdB,
                              param.numRigidBodies);
      }
      if (!pfxIsFinite(c.m_driveTarget) || !pfxIsFinite(c.m_driveMaxForce) ||
          c.m_driveMaxForce < 0) {
        return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                              "pfxApplyJointEfforts: PfxApplyJointEffortsParam::joints[%u] axis "
                              "%u: effort %g and force limit %g must be finite, the limit >= 0",
                              i, axis, double(c.m_driveTarget), double(c.m_driveMaxForce));
      }
    }
  }
  for (PfxUInt32 i = 0; i < param.numJoints; ++i) {
    PfxJoint& joint = param.joints[i];
    if (!joint.m_active ||
        std::none_of(std::begin(joint.m_constraints), std::end(joint.m_constraints), pushes)) {
      continue;
    }
    PfxRigidState& stateA = param.states[joint.m_rigidBodyIdA];
    PfxRigidState& stateB = param.states[joint.m_rigidBodyIdB];
    pfxCalcJointAxes(joint, stateA, stateB);
    for (PfxUInt32 axis = 0; axis < 6; ++axis) {
      const PfxJointConstraint& c = joint.m_constraints[axis];
      if (!pushes(c)) continue;
      const PfxFloat effort = std::clamp(c.m_driveTarget, -c.m_driveMaxForce, c.m_driveMaxForce);
      if (effort == 0) continue;
      const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, joint.m_axes[axis]);
      const PfxFloat impulse = effort * param.timeStep;
      applyImpulse(stateA, param.bodies[joint.m_rigidBodyIdA], j.linearA, j.angularA, impulse);
      applyImpulse(stateB, param.bodies[joint.m_rigidBodyIdB], j.linearB, j.angularB, impulse);
    }
  }
  return PFX_OK;
}

}  // namespace pfx
