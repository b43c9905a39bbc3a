#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

#include <cstring>
#include <limits>

namespace pfx {

namespace {

// Stage (1) cuts the speeds of the bodies forces move, but the solver takes the others'
// velocities as they are: a fixed ground saved moving at 5.8e17 m/s, or a fixed base turning
// at 1e19 rad/s (their squares finite), turned the bodies on it or jointed to it NaN in the
// first step.
bool withinSpeedLimits(const PfxVector3& linear, const PfxVector3& angular) {
  return linear.squaredNorm() <= kPfxMaxLinearSpeed * kPfxMaxLinearSpeed &&
         angular.squaredNorm() <= kPfxMaxAngularSpeed * kPfxMaxAngularSpeed;
}

}  // namespace

void PfxRigidState::reset() {
  // Zero the padding too, so that states compare and serialize byte for byte.
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_position.setZero();
  m_orientation.setIdentity();
  m_linearVelocity.setZero();
  m_angularVelocity.setZero();
  m_orientationCarry.coeffs().setZero();
  m_angularVelocityCarry.setZero();
  m_motionType = kPfxMotionTypeActive;
  m_contactFilterSelf = 0xffffffffu;
  m_contactFilterTarget = 0xffffffffu;
}

bool PfxRigidState::isValid() const {
  // A velocity whose squared length overflows (above about 1.8e19 in float) is finite but
  // unusable: the integrator, the solver and the energy square it, and a body given one
  // turned NaN in its first step. So is such a position: a fixed body saved at y = 3.4e38
  // pulled the body jointed to it to NaN.
  return pfxIsFinite(m_position.squaredNorm()) && pfxIsUnitQuat(m_orientation) &&
         pfxIsFinite(m_linearVelocity.squaredNorm()) &&
         pfxIsFinite(m_angularVelocity.squaredNorm()) &&
         // The orientation's carry is what rounding a unit quaternion leaves out: a larger
         // one (or NaN, which fails the comparison) is no carry.
         m_orientationCarry.coeffs().cwiseAbs().maxCoeff() <=
             std::numeric_limits<PfxFloat>::epsilon() &&
         pfxIsFinite(m_angularVelocityCarry.squaredNorm()) && m_motionType < kPfxMotionTypeCount &&
         (pfxMotionTypeIsDynamic(getMotionType()) ||
          withinSpeedLimits(m_linearVelocity, m_angularVelocity));
}

PfxInt32 pfxSetKeyframeTarget(PfxRigidState& state, const PfxVector3& targetPosition,
                              const PfxQuat& targetOrientation, PfxFloat timeStep) {
  if (!(timeStep > 0) || !pfxIsFinite(timeStep) || !pfxIsFinite(targetPosition) ||
      !pfxIsUnitQuat(targetOrientation)) {
    return PFX_ERR_INVALID_VALUE;
  }
  const PfxVector3 linear = (targetPosition - state.getPosition()) / timeStep;
  // The rotation that takes the current orientation to the target, as a rotation vector
  // over the step (shortest way round).
  PfxQuat delta = targetOrientation.normalized() * state.getOrientation().conjugate();
  if (delta.w() < 0) delta.coeffs() = -delta.coeffs();
  const Eigen::AngleAxis<PfxFloat> aa(delta);
  const PfxVector3 angular =
      aa.angle() == 0 ? PfxVector3::Zero() : PfxVector3(aa.axis() * (aa.angle() / timeStep));
  // A target 1e20 m away, or a turn over a step of 1e-40 s, is finite but no velocity the
  // solver can take from a body that impulses do not slow.
  if (!withinSpeedLimits(linear, angular)) return PFX_ERR_INVALID_VALUE;
  state.setLinearVelocity(linear);
  state.setAngularVelocity(angular);
  return PFX_OK;
}

}  // namespace pfx
