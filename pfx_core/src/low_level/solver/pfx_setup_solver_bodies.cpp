#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

namespace pfx {

PfxInt32 pfxSetupSolverBodies(const PfxSetupSolverBodiesParam& param) {
  if (param.numRigidBodies > 0 && (!param.states || !param.bodies || !param.solverBodies)) {
    return PFX_ERR_NULL_POINTER;
  }
  for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
    const PfxRigidState& state = param.states[i];
    PfxSolverBody& solverBody = param.solverBodies[i];
    solverBody.m_deltaLinearVelocity.setZero();
    solverBody.m_deltaAngularVelocity.setZero();
    solverBody.m_pushLinearVelocity.setZero();
    solverBody.m_pushAngularVelocity.setZero();
    solverBody.m_motionType = state.getMotionType();
    if (pfxMotionTypeIsDynamic(state.getMotionType()) && state.isAwake()) {
      const PfxRigidBody& body = param.bodies[i];
      solverBody.m_massInv = body.getMassInv();
      solverBody.m_inertiaInv =
          pfxRotateInertia(state.getOrientation().toRotationMatrix(), body.getInertiaInv());
    } else {
      solverBody.m_massInv = 0;
      solverBody.m_inertiaInv.setZero();
    }
  }
  return PFX_OK;
}

}  // namespace pfx
