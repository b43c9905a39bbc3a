// The speed limits of stage (1) (kPfxMaxLinearSpeed, kPfxMaxAngularSpeed) for what pushes
// a body before the solver: external forces and joint efforts.
#pragma once

#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

using PfxWideVector = Eigen::Matrix<long double, 3, 1>;

inline PfxWideVector pfxWide(const PfxVector3& v) { return v.cast<long double>(); }

// `velocity` cut to `maxSpeed`, direction kept. Taken in long double because a push past the
// limits may overflow float on its way to a velocity (1e19 N on a body of 1e-12 kg), and a
// cut of infinity has no direction.
inline PfxVector3 pfxCutToSpeed(const PfxWideVector& velocity, PfxFloat maxSpeed) {
  const long double speed = velocity.norm();
  return (speed > maxSpeed ? PfxWideVector(velocity * (maxSpeed / speed)) : velocity)
      .cast<PfxFloat>();
}

// `pushed`, a velocity summed in float, when it keeps to `maxSpeed`; else `wideSum()`, the
// same sum in long double, cut to it.
template <typename WideSum>
PfxVector3 pfxWithinSpeed(const PfxVector3& pushed, PfxFloat maxSpeed, WideSum wideSum) {
  return pushed.squaredNorm() <= maxSpeed * maxSpeed ? pushed
                                                     : pfxCutToSpeed(wideSum(), maxSpeed);
}

// The body's angular velocity turned by `change`, as pfxWithinSpeed bounds it (`wideSum`
// the sum in long double): a sum that keeps to the limit is a change, and the integrator's
// carry (PfxRigidState::getAngularVelocityCarry) still applies; a cut one is a new velocity.
template <typename WideSum>
void pfxTurnWithinSpeed(PfxRigidState& state, const PfxVector3& change, WideSum wideSum) {
  const PfxVector3 turned = state.getAngularVelocity() + change;
  if (turned.squaredNorm() <= kPfxMaxAngularSpeed * kPfxMaxAngularSpeed) {
    state.addAngularVelocity(change);
  } else {
    state.setAngularVelocity(pfxCutToSpeed(wideSum(), kPfxMaxAngularSpeed));
  }
}

}  // namespace pfx
