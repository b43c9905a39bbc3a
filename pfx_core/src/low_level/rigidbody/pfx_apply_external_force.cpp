#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"

#include "low_level/pfx_param_checks.h"
#include "low_level/rigidbody/pfx_speed_limit.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kForcedBodiesPerTask = 512;

bool movedByForces(const PfxRigidState& state) {
  return pfxMotionTypeIsDynamic(state.getMotionType()) && state.isAwake();
}

// Past the speed limits the sums are formed again in long double (pfxWithinSpeed).
void applyForce(PfxRigidState& state, const PfxRigidBody& body, const PfxVector3& force,
                const PfxVector3& torque, const PfxVector3& gravity, PfxFloat timeStep) {
  const PfxVector3& linear = state.getLinearVelocity();
  const PfxVector3 pushed = linear + (force * body.getMassInv() + gravity) * timeStep;
  state.setLinearVelocity(pfxWithinSpeed(pushed, kPfxMaxLinearSpeed, [&]() -> PfxWideVector {
    return pfxWide(linear) +
           (pfxWide(force) * (long double)body.getMassInv() + pfxWide(gravity)) *
               (long double)timeStep;
  }));
  const PfxMatrix3 rotation = state.getOrientation().toRotationMatrix();
  const PfxMatrix3 inertiaInvWorld = pfxRotateInertia(rotation, body.getInertiaInv());
  const PfxVector3& angular = state.getAngularVelocity();
  pfxTurnWithinSpeed(state, inertiaInvWorld * torque * timeStep, [&]() -> PfxWideVector {
    return pfxWide(angular) +
           inertiaInvWorld.cast<long double>() * pfxWide(torque) * (long double)timeStep;
  });
}

bool validStep(const PfxVector3& gravity, PfxFloat timeStep) {
  return pfxIsFinite(gravity) && timeStep > 0 && pfxIsFinite(timeStep);
}

}  // namespace

PfxInt32 pfxApplyExternalForce(PfxRigidState& state, const PfxRigidBody& body,
                               const PfxVector3& force, const PfxVector3& torque,
                               const PfxVector3& gravity, PfxFloat timeStep) {
  if (!validStep(gravity, timeStep) || !pfxIsFinite(force) || !pfxIsFinite(torque)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxApplyExternalForce: force, torque and gravity must be finite, "
                          "timeStep (%g) positive and finite",
                          double(timeStep));
  }
  if (movedByForces(state)) applyForce(state, body, force, torque, gravity, timeStep);
  return PFX_OK;
}

PfxInt32 pfxApplyExternalForce(const PfxApplyExternalForceParam& param,
                               PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxApplyExternalForce", "PfxApplyExternalForceParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at, {{param.states, "states"}, {param.bodies, "bodies"}},
                              "numRigidBodies", param.numRigidBodies)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK) {
    return err;
  }
  if (!pfxIsFinite(param.gravity)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxApplyExternalForce: PfxApplyExternalForceParam::gravity is not "
                          "finite");
  }
  for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
    if ((param.forces && !pfxIsFinite(param.forces[i])) ||
        (param.torques && !pfxIsFinite(param.torques[i]))) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxApplyExternalForce: PfxApplyExternalForceParam::%s[%u] is not "
                            "finite",
                            param.forces && !pfxIsFinite(param.forces[i]) ? "forces" : "torques",
                            i);
    }
  }
  const PfxVector3 zero = PfxVector3::Zero();
  pfxParallelFor(taskManager, param.numRigidBodies, kForcedBodiesPerTask,
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
