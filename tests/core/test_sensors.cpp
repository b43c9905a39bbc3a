// The core's sensor functions: the rays of a scan and the ranges their hits give
// (pfx_range_sensor.h), a depth camera's rays and depths (pfx_depth_camera.h), and what an
// IMU on a body reads (pfx_imu_reading.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pfx/high_level/pfx_depth_camera.h"
#include "pfx/high_level/pfx_imu_reading.h"
#include "pfx/high_level/pfx_range_sensor.h"

using namespace pfx;

namespace {

const PfxFloat kPi = PfxFloat(3.14159265358979);

PfxRangeSensorParam lidar() {
  PfxRangeSensorParam p;
  p.horizontalSamples = 4;
  p.horizontalMinAngle = -kPi / 2;
  p.horizontalMaxAngle = kPi;
  p.verticalSamples = 3;
  p.verticalMinAngle = -kPi / 4;
  p.verticalMaxAngle = kPi / 4;
  p.rangeMin = PfxFloat(0.5);
  p.rangeMax = 10;
  return p;
}

}  // namespace

TEST(RangeSensor, RaysSpanTheScanFromRangeMinToRangeMax) {
  const PfxRangeSensorParam p = lidar();
  ASSERT_EQ(pfxCheckRangeSensorParam(p), PFX_OK);
  ASSERT_EQ(pfxGetRangeSensorNumRays(p), 12u);
  // The sensor at (1, 2, 3), turned a quarter turn about Z: its +X is the world's +Y.
  const PfxTransform3 pose = pfxMakeTransform(
      PfxQuat(Eigen::AngleAxis<PfxFloat>(kPi / 2, PfxVector3::UnitZ())), PfxVector3(1, 2, 3));
  std::vector<PfxRayInput> rays(12);
  pfxMakeRangeSensorRays(p, pose, rays.data());
  for (PfxUInt32 v = 0; v < 3; ++v) {
    const PfxFloat pitch = -kPi / 4 + PfxFloat(v) * kPi / 4;
    for (PfxUInt32 h = 0; h < 4; ++h) {
      const PfxFloat yaw = -kPi / 2 + PfxFloat(h) * kPi / 2;
      const PfxVector3 local(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                             std::sin(pitch));
      const PfxVector3 beam = pose.linear() * local;
      const PfxRayInput& ray = rays[v * 4 + h];
      EXPECT_LT((ray.m_startPosition - (PfxVector3(1, 2, 3) + beam * PfxFloat(0.5))).norm(), 1e-5)
          << "ray " << v * 4 + h;
      EXPECT_LT((ray.m_direction - beam * PfxFloat(9.5)).norm(), 1e-4) << "ray " << v * 4 + h;
    }
  }
  // Horizontal sample 1 of the middle row looks along the sensor's +X, the world's +Y.
  EXPECT_LT((rays[5].m_direction.normalized() - PfxVector3(0, 1, 0)).norm(), 1e-6);
}

TEST(RangeSensor, RangesAreMeasuredFromTheOriginAndMissesAreInfinite) {
  PfxRangeSensorParam p;
  p.horizontalSamples = 2;
  p.horizontalMaxAngle = 1;
  p.rangeMin = 1;
  p.rangeMax = 5;
  PfxRayOutput hits[2];
  hits[0].m_contactFlag = true;
  hits[0].m_variable = PfxFloat(0.25);  // 1 m into the 4 m the ray covers
  hits[1].m_contactFlag = false;
  hits[1].m_variable = 1;
  PfxFloat ranges[2];
  pfxGetRangeSensorRanges(p, hits, ranges);
  EXPECT_FLOAT_EQ(ranges[0], 2);
  EXPECT_TRUE(std::isinf(ranges[1]) && ranges[1] > 0);
}

TEST(RangeSensor, BadParamsAreRefused) {
  const PfxRangeSensorParam good = lidar();
  auto refused = [&](auto change) {
    PfxRangeSensorParam p = good;
    change(p);
    return pfxCheckRangeSensorParam(p) == PFX_ERR_INVALID_VALUE;
  };
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.horizontalSamples = 0; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.verticalSamples = 0; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.rangeMin = -1; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.rangeMax = p.rangeMin; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.horizontalMinAngle = 4; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.verticalMaxAngle = -1; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.rangeMax = NAN; }));
  EXPECT_TRUE(refused([](PfxRangeSensorParam& p) { p.horizontalMaxAngle = INFINITY; }));
}

TEST(ImuReading, AtRestItReadsGravityUpwards) {
  PfxRigidState state;
  state.reset();
  // The IMU lies on its side (rolled a quarter turn): the world's up is its -Y.
  const PfxTransform3 pose = pfxMakeTransform(
      PfxQuat(Eigen::AngleAxis<PfxFloat>(kPi / 2, PfxVector3::UnitX())), PfxVector3(0, 0, 1));
  const PfxVector3 gravity(0, 0, PfxFloat(-9.80665));
  const PfxImuReading r = pfxGetImuReading(pose, state, PfxVector3::Zero(), PfxVector3::Zero(),
                                           PfxFloat(0.004), gravity);
  EXPECT_LT((r.linearAcceleration - PfxVector3(0, PfxFloat(9.80665), 0)).norm(), 1e-5);
  EXPECT_LT(r.angularVelocity.norm(), 1e-7);
  EXPECT_LT(r.orientation.angularDistance(PfxQuat(pose.linear())), 1e-6);
}

TEST(ImuReading, FallingFreelyItReadsNothingAndTurningItReadsTheRateInItsFrame) {
  PfxRigidState state;
  state.reset();
  state.setAngularVelocity(PfxVector3(0, 0, 2));
  const PfxVector3 gravity(0, 0, PfxFloat(-9.80665));
  const PfxFloat dt = PfxFloat(0.01);
  // Upside down (half a turn about X): the world's +Z turn is the IMU's -Z.
  const PfxTransform3 pose = pfxMakeTransform(
      PfxQuat(Eigen::AngleAxis<PfxFloat>(kPi, PfxVector3::UnitX())), PfxVector3::Zero());
  const PfxImuReading r =
      pfxGetImuReading(pose, state, gravity * dt, PfxVector3::Zero(), dt, gravity);
  EXPECT_LT(r.linearAcceleration.norm(), 1e-4);
  EXPECT_LT((r.angularVelocity - PfxVector3(0, 0, -2)).norm(), 1e-5);
}

TEST(ImuReading, PointVelocityAddsTheTurnAboutTheCentreOfMass) {
  PfxRigidState state;
  state.reset();
  state.setPosition(PfxVector3(1, 0, 0));
  state.setLinearVelocity(PfxVector3(0, 0, 1));
  state.setAngularVelocity(PfxVector3(0, 0, 3));
  // 2 m along +X from the centre: w x r = (0, 6, 0).
  EXPECT_LT((pfxGetPointVelocity(state, PfxVector3(3, 0, 0)) - PfxVector3(0, 6, 1)).norm(), 1e-6);
}

TEST(DepthCamera, PixelsLookThroughTheirCentresAndDepthIsAlongTheAxis) {
  PfxDepthCameraParam p;
  p.width = 4;
  p.height = 2;
  p.horizontalFov = kPi / 2;  // focal length 2 pixels
  p.nearClip = PfxFloat(0.5);
  p.farClip = 4;
  ASSERT_EQ(pfxCheckDepthCameraParam(p), PFX_OK);
  EXPECT_FLOAT_EQ(pfxGetDepthCameraFocalLength(p), 2);
  std::vector<PfxRayInput> rays(8);
  pfxMakeDepthCameraRays(p, PfxTransform3::Identity(), rays.data());
  // Top-left pixel (0, 0): 1.5 pixels left of and 0.5 above the centre.
  const PfxVector3 sight(1, PfxFloat(0.75), PfxFloat(0.25));
  EXPECT_LT((rays[0].m_startPosition - sight * PfxFloat(0.5)).norm(), 1e-6);
  EXPECT_LT((rays[0].m_direction - sight * PfxFloat(3.5)).norm(), 1e-5);
  // Bottom-right pixel (3, 1): right and below.
  EXPECT_LT((rays[7].m_direction.normalized() -
             PfxVector3(1, PfxFloat(-0.75), PfxFloat(-0.25)).normalized())
                .norm(),
            1e-6);
  PfxRayOutput hits[8];
  for (PfxRayOutput& hit : hits) {
    hit.m_contactFlag = false;
    hit.m_variable = 1;
  }
  hits[0].m_contactFlag = true;
  hits[0].m_variable = PfxFloat(0.5);
  PfxFloat depths[8];
  pfxGetDepthCameraDepths(p, hits, depths);
  EXPECT_FLOAT_EQ(depths[0], PfxFloat(2.25));  // 0.5 + 0.5 * 3.5
  EXPECT_TRUE(std::isinf(depths[1]));
  PfxDepthCameraParam bad = p;
  bad.horizontalFov = kPi;
  EXPECT_EQ(pfxCheckDepthCameraParam(bad), PFX_ERR_INVALID_VALUE);
  bad = p;
  bad.width = 0;
  EXPECT_EQ(pfxCheckDepthCameraParam(bad), PFX_ERR_INVALID_VALUE);
  bad = p;
  bad.farClip = bad.nearClip;
  EXPECT_EQ(pfxCheckDepthCameraParam(bad), PFX_ERR_INVALID_VALUE);
}
