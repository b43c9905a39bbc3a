#include "pfx/base_level/joint/pfx_joint_coupling.h"

#include <cstring>

namespace pfx {

void PfxJointCoupling::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_active = 1;
  m_multiplier = 1;
  m_bias = 1;
  m_row.m_normal.setZero();
  for (PfxJointCouplingBody& body : m_bodies) {
    body.m_linear.setZero();
    body.m_angular.setZero();
  }
}

PfxInt32 pfxCheckJointCoupling(const PfxJointCoupling& coupling, const PfxJoint* joints,
                               PfxUInt32 numJoints) {
  if (!joints || coupling.m_leaderJointId >= numJoints ||
      coupling.m_followerJointId >= numJoints || coupling.m_leaderAxis > 5 ||
      coupling.m_followerAxis > 5) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  if (coupling.m_leaderJointId == coupling.m_followerJointId &&
      coupling.m_leaderAxis == coupling.m_followerAxis) {
    return PFX_ERR_INVALID_VALUE;
  }
  const PfxJoint& leader = joints[coupling.m_leaderJointId];
  const PfxJoint& follower = joints[coupling.m_followerJointId];
  if (leader.m_constraints[coupling.m_leaderAxis].m_lock == kPfxJointLockLocked ||
      follower.m_constraints[coupling.m_followerAxis].m_lock == kPfxJointLockLocked) {
    return PFX_ERR_INVALID_VALUE;
  }
  // The rule of body velocities: a value whose square overflows is finite but unusable. An
  // offset of 3.4e38 read from a file made the coupling's error, divided by the step, infinite.
  const auto usable = [](PfxFloat value) { return pfxIsFinite(value * value); };
  const PfxFloat error = coupling.m_followerPosition -
                         coupling.m_multiplier * coupling.m_leaderPosition - coupling.m_offset;
  if (!usable(coupling.m_multiplier) || !usable(coupling.m_offset) ||
      !usable(coupling.m_leaderPosition) || !usable(coupling.m_followerPosition) ||
      !usable(error) || !pfxIsFinite(coupling.m_maxImpulseForce) ||
      !(coupling.m_bias >= 0 && coupling.m_bias <= 1)) {
    return PFX_ERR_INVALID_VALUE;
  }
  return PFX_OK;
}

}  // namespace pfx
