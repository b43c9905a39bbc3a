#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kSetUpBodiesPerTask = 512;

void clearVelocityChanges(PfxSolverBody& solverBody) {
  solverBody.m_deltaLinearVelocity.setZero();
  solverBody.m_deltaAngularVelocity.setZero();
  solverBody.m_pushLinearVelocity.setZero();
  solverBody.m_pushAngularVelocity.setZero();
}

void setupSolverBody(const PfxRigidState& state, const PfxRigidBody& body,
                     PfxSolverBody& solverBody) {
  clearVelocityChanges(solverBody);
  solverBody.m_motionType = state.getMotionType();
  solverBody.m_stiffnessInertia = 0;
  if (pfxMotionTypeIsDynamic(state.getMotionType()) && state.isAwake()) {
    solverBody.m_massInv = body.getMassInv();
    solverBody.m_inertiaInv =
        pfxRotateInertia(state.getOrientation().toRotationMatrix(), body.getInertiaInv());
  } else {
    solverBody.m_massInv = 0;
    solverBody.m_inertiaInv.setZero();
  }
}

}  // namespace

PfxInt32 pfxSetupSolverBodies(const PfxSetupSolverBodiesParam& param,
                              PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxSetupSolverBodies", "PfxSetupSolverBodiesParam"};
  if (const PfxInt32 err = pfxCheckRequired(at,
                                            {{param.states, "states"},
                                             {param.bodies, "bodies"},
                                             {param.solverBodies, "solverBodies"}},
                                            "numRigidBodies", param.numRigidBodies);
      err != PFX_OK) {
    return err;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kSetUpBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     if (param.bodiesToSetUp && param.bodiesToSetUp[i] == 0) {
                       clearVelocityChanges(param.solverBodies[i]);
                     } else {
                       setupSolverBody(param.states[i], param.bodies[i], param.solverBodies[i]);
                     }
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
