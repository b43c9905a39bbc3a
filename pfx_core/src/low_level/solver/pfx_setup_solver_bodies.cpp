#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kBodiesPerTask = 512;

void setupSolverBody(const PfxRigidState& state, const PfxRigidBody& body,
                     PfxSolverBody& solverBody) {
  solverBody.m_deltaLinearVelocity.setZero();
  solverBody.m_deltaAngularVelocity.setZero();
  solverBody.m_pushLinearVelocity.setZero();
  solverBody.m_pushAngularVelocity.setZero();
  solverBody.m_motionType = state.getMotionType();
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
  if (param.numRigidBodies > 0 && (!param.states || !param.bodies || !param.solverBodies)) {
    return PFX_ERR_NULL_POINTER;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     setupSolverBody(param.states[i], param.bodies[i], param.solverBodies[i]);
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
