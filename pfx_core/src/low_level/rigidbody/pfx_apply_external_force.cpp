#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kBodiesPerTask = 512;

bool movedByForces(const PfxRigidState& state) {
  return pfxMotionTypeIsDynamic(state.getMotionType()) && state.isAwake();
}

void applyForce(PfxRigidState& state, const PfxRigidBody& body, const PfxVector3& force,
                const PfxVector3& torque, const PfxVector3& gravity, PfxFloat timeStep) {
  state.setLinearVelocity(state.getLinearVelocity() +
                          (force * body.getMassInv() + gravity) * timeStep);
  const PfxMatrix3 rotation = state.getOrientation().toRotationMatrix();
  const PfxMatrix3 inertiaInvWorld = pfxRotateInertia(rotation, body.getInertiaInv());
  state.setAngularVelocity(state.getAngularVelocity() + inertiaInvWorld * torque * timeStep);
}

bool validStep(const PfxVector3& gravity, PfxFloat timeStep) {
  return pfxIsFinite(gravity) && timeStep > 0 && pfxIsFinite(timeStep);
}

}  // namespace

PfxInt32 pfxApplyExternalForce(PfxRigidState& state, const PfxRigidBody& body,
                               const PfxVector3& force, const PfxVector3& torque,
                               const PfxVector3& gravity, PfxFloat timeStep) {
  if (!validStep(gravity, timeStep) || !pfxIsFinite(force) || !pfxIsFinite(torque)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (movedByForces(state)) applyForce(state, body, force, torque, gravity, timeStep);
  return PFX_OK;
}

PfxInt32 pfxApplyExternalForce(const PfxApplyExternalForceParam& param,
                               PfxTaskManager* taskManager) {
  if (param.numRigidBodies > 0 && (!param.states || !param.bodies)) return PFX_ERR_NULL_POINTER;
  if (!validStep(param.gravity, param.timeStep)) return PFX_ERR_INVALID_VALUE;
  for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
    if ((param.forces && !pfxIsFinite(param.forces[i])) ||
        (param.torques && !pfxIsFinite(param.torques[i]))) {
      return PFX_ERR_INVALID_VALUE;
    }
  }
  const PfxVector3 zero = PfxVector3::Zero();
  pfxParallelFor(taskManager, param.numRigidBodies, kBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     PfxRigidState& state = param.states[i];
                     if (!movedByForces(state)) continue;
                     applyForce(state, param.bodies[i], param.forces ? param.forces[i] : zero,
                                param.torques ? param.torques[i] : zero, param.gravity,
                                param.timeStep);
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
