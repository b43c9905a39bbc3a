#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"

#include <Eigen/Eigenvalues>

namespace pfx {

namespace {

// Rotation by the rotation vector `v` (exact exponential map).
PfxQuat rotationFromVector(const PfxVector3& v) {
  const PfxFloat angle = v.norm();
  if (angle < PfxFloat(1e-12)) {
    return PfxQuat(PfxFloat(1), v[0] * PfxFloat(0.5), v[1] * PfxFloat(0.5), v[2] * PfxFloat(0.5))
        .normalized();
  }
  return PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, v / angle));
}

PfxQuat rotationAboutAxis(int axis, PfxFloat angle) {
  const PfxFloat half = angle * PfxFloat(0.5);
  PfxQuat q(std::cos(half), 0, 0, 0);
  q.vec()[axis] = std::sin(half);
  return q;
}

bool isDiagonal(const PfxMatrix3& m) {
  return m(0, 1) == 0 && m(0, 2) == 0 && m(1, 2) == 0 && m(1, 0) == 0 && m(2, 0) == 0 &&
         m(2, 1) == 0;
}

// The free rigid body in its principal frame: orientation `q` of that frame and body
// momentum `momentum` advance by h, split into exact rotations about the principal axes,
// 0 (h/2), 1 (h/2), 2 (h), 1 (h/2), 0 (h/2). Each sub-flow keeps |momentum| and the world
// momentum exactly; the symmetric composition is second order and time-reversible.
void advanceFreeRotation(PfxQuat& q, PfxVector3& momentum, const PfxVector3& principalInertia,
                         PfxFloat h) {
  static constexpr int kAxes[5] = {0, 1, 2, 1, 0};
  static constexpr PfxFloat kFractions[5] = {0.5f, 0.5f, 1.0f, 0.5f, 0.5f};
  for (int s = 0; s < 5; ++s) {
    const int axis = kAxes[s];
    const PfxFloat angle = h * kFractions[s] * momentum[axis] / principalInertia[axis];
    const PfxQuat step = rotationAboutAxis(axis, angle);
    q = q * step;
    momentum = step.conjugate() * momentum;
  }
  q.normalize();
}

}  // namespace

void pfxIntegrate(PfxRigidState& state, const PfxRigidBody& body, PfxFloat timeStep) {
  const PfxMotionType type = state.getMotionType();
  if (state.isAsleep() || type == kPfxMotionTypeFixed || type == kPfxMotionTypeTrigger) return;

  state.setPosition(state.getPosition() + state.getLinearVelocity() * timeStep);

  const PfxVector3& omega = state.getAngularVelocity();
  if (type == kPfxMotionTypeKeyframe) {
    state.setOrientation((rotationFromVector(omega * timeStep) * state.getOrientation()).normalized());
    return;
  }

  // Principal frame of the inertia: body = principal * axes. Shape inertias are usually
  // diagonal already, which saves the eigen-decomposition.
  const PfxMatrix3& inertia = body.getInertia();
  PfxVector3 principalInertia;
  PfxQuat axes = PfxQuat::Identity();
  if (isDiagonal(inertia)) {
    principalInertia = inertia.diagonal();
  } else {
    const Eigen::SelfAdjointEigenSolver<PfxMatrix3> eig(inertia);
    PfxMatrix3 vectors = eig.eigenvectors();
    if (vectors.determinant() < 0) vectors.col(2) = -vectors.col(2);
    principalInertia = eig.eigenvalues();
    axes = PfxQuat(vectors);
  }

  PfxQuat frame = state.getOrientation() * axes;
  PfxVector3 momentum = principalInertia.cwiseProduct(frame.conjugate() * omega);
  advanceFreeRotation(frame, momentum, principalInertia, timeStep);

  state.setOrientation((frame * axes.conjugate()).normalized());
  state.setAngularVelocity(frame * momentum.cwiseQuotient(principalInertia));
}

PfxInt32 pfxUpdateRigidStates(const PfxUpdateRigidStatesParam& param) {
  if (param.numRigidBodies > 0 && (!param.states || !param.bodies)) return PFX_ERR_NULL_POINTER;
  if (!(param.timeStep > 0) || !pfxIsFinite(param.timeStep)) return PFX_ERR_INVALID_VALUE;
  for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
    pfxIntegrate(param.states[i], param.bodies[i], param.timeStep);
  }
  return PFX_OK;
}

}  // namespace pfx
