// What an IMU fixed to a rigid body reads: its orientation, its angular velocity and its
// specific force (the acceleration of its point minus gravity), the last two in the IMU's
// own frame. An IMU at rest on the ground thus reads +g along the world's up axis: the
// ground's push, not gravity's pull, is what an accelerometer feels.
#pragma once

#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

struct PfxImuReading {
  PfxQuat orientation = PfxQuat::Identity();           // of the IMU frame in the world
  PfxVector3 angularVelocity = PfxVector3::Zero();     // rad/s, IMU frame
  PfxVector3 linearAcceleration = PfxVector3::Zero();  // m/s^2, IMU frame, gravity included
};

// Velocity (world frame) of the material point of the body at `worldPoint`.
inline PfxVector3 pfxGetPointVelocity(const PfxRigidState& state, const PfxVector3& worldPoint) {
  return state.getLinearVelocity() +
         state.getAngularVelocity().cross(worldPoint - state.getPosition());
}

// The reading of an IMU at `imuPose` (world) on the body of `state`, whose point there moved
// at `previousPointVelocity` a time `dt` (> 0) ago and now at `pointVelocity`: the point's
// acceleration is their finite difference, which a solver that changes velocities in jumps
// (contacts, joints) gives exactly over the step.
PfxImuReading pfxGetImuReading(const PfxTransform3& imuPose, const PfxRigidState& state,
                               const PfxVector3& pointVelocity,
                               const PfxVector3& previousPointVelocity, PfxFloat dt,
                               const PfxVector3& gravity);

}  // namespace pfx
