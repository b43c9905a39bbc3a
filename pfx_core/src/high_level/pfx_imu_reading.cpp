#include "pfx/high_level/pfx_imu_reading.h"

namespace pfx {

PfxImuReading pfxGetImuReading(const PfxTransform3& imuPose, const PfxRigidState& state,
                               const PfxVector3& pointVelocity,
                               const PfxVector3& previousPointVelocity, PfxFloat dt,
                               const PfxVector3& gravity) {
  const PfxMatrix3 toImu = imuPose.linear().transpose();
  PfxImuReading reading;
  reading.orientation = PfxQuat(imuPose.linear());
  reading.orientation.normalize();
  reading.angularVelocity = toImu * state.getAngularVelocity();
  reading.linearAcceleration = toImu * ((pointVelocity - previousPointVelocity) / dt - gravity);
  return reading;
}

}  // namespace pfx
