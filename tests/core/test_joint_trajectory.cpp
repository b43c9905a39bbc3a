// Joint trajectories: straight lines between waypoints without velocities, cubics that
// meet positions and velocities at both ends with them, the start state before the start,
// the last waypoint held after the end; malformed trajectories refused with nothing changed.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_joint_trajectory.h"
#include "pfx/low_level/pfx_error_detail.h"

using namespace pfx;

namespace {

PfxJointTrajectoryPoint point(double time, std::vector<double> positions,
                              std::vector<double> velocities = {}) {
  PfxJointTrajectoryPoint p;
  p.timeFromStart = time;
  p.positions = std::move(positions);
  p.velocities = std::move(velocities);
  return p;
}

}  // namespace

TEST(JointTrajectory, StraightLinesWithoutVelocitiesThenHoldsTheLastPoint) {
  PfxJointTrajectory trajectory;
  ASSERT_EQ(trajectory.set(10, {0, 1}, {0, 0}, {point(1, {1, 3}), point(3, {-1, 3})}), PFX_OK);
  EXPECT_DOUBLE_EQ(trajectory.getEndTime(), 13);
  std::vector<double> q, v;
  trajectory.sample(9, q, v);  // before the start: where the joints were
  EXPECT_EQ(q, (std::vector<double>{0, 1}));
  trajectory.sample(10.25, q, v);
  EXPECT_DOUBLE_EQ(q[0], 0.25);
  EXPECT_DOUBLE_EQ(q[1], 1.5);
  EXPECT_DOUBLE_EQ(v[0], 1);
  EXPECT_DOUBLE_EQ(v[1], 2);
  trajectory.sample(12, q, v);
  EXPECT_DOUBLE_EQ(q[0], 0);
  EXPECT_DOUBLE_EQ(v[0], -1);
  trajectory.sample(20, q, v);
  EXPECT_EQ(q, (std::vector<double>{-1, 3}));
  EXPECT_EQ(v, (std::vector<double>{0, 0}));
}

TEST(JointTrajectory, CubicsMeetPositionAndVelocityAtBothEnds) {
  PfxJointTrajectory trajectory;
  ASSERT_EQ(trajectory.set(0, {0}, {0}, {point(2, {1}, {0.5}), point(4, {0}, {0})}), PFX_OK);
  std::vector<double> q, v;
  // A cubic from (0, 0) at rest to (1, 0.5) over 2 s: p(t) = a t^2 + b t^3 with
  // 4a + 8b = 1 and 4a + 12b = 0.5: a = 0.5, b = -0.125.
  for (const double t : {0.5, 1.0, 1.5}) {
    trajectory.sample(t, q, v);
    EXPECT_NEAR(q[0], 0.5 * t * t - 0.125 * t * t * t, 1e-12) << t;
    EXPECT_NEAR(v[0], t - 0.375 * t * t, 1e-12) << t;
  }
  trajectory.sample(2 - 1e-9, q, v);
  EXPECT_NEAR(q[0], 1, 1e-8);
  EXPECT_NEAR(v[0], 0.5, 1e-8);
  trajectory.sample(2, q, v);
  EXPECT_NEAR(q[0], 1, 1e-12);
  EXPECT_NEAR(v[0], 0.5, 1e-12);
}

TEST(JointTrajectory, MalformedTrajectoriesAreRefusedWithNothingChanged) {
  PfxJointTrajectory trajectory;
  ASSERT_EQ(trajectory.set(1, {0}, {0}, {point(1, {2})}), PFX_OK);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* what;
    std::vector<PfxJointTrajectoryPoint> points;
    const char* detail;
  };
  const Case cases[] = {
      {"no points", {}, "no points"},
      {"wrong size", {point(1, {1, 2})}, "point 0: positions are not one per joint"},
      {"wrong velocity size", {point(1, {1}, {1, 2})}, "velocities are neither"},
      {"NaN position", {point(1, {nan})}, "NaN or infinite"},
      {"infinite velocity", {point(1, {1}, {inf})}, "NaN or infinite"},
      {"NaN time", {point(nan, {1})}, "not finite"},
      {"negative time", {point(-1, {1})}, "is not at least 0"},
      {"times going back", {point(1, {1}), point(0.5, {2})}, "point 1: time_from_start 0.5 s"},
      {"a repeated time", {point(1, {1}), point(1, {2})}, "is not after 1 s"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_EQ(trajectory.set(5, {0}, {0}, c.points), PFX_ERR_INVALID_VALUE);
    EXPECT_NE(std::string(pfxGetLastErrorDetail()).find(c.detail), std::string::npos)
        << pfxGetLastErrorDetail();
  }
  EXPECT_EQ(trajectory.set(5, {}, {}, {point(1, {})}), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(trajectory.set(nan, {0}, {0}, {point(1, {1})}), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(trajectory.set(5, {0}, {}, {point(1, {1})}), PFX_ERR_INVALID_VALUE);
  // The first trajectory stands.
  EXPECT_DOUBLE_EQ(trajectory.getStartTime(), 1);
  EXPECT_DOUBLE_EQ(trajectory.getEndTime(), 2);
  std::vector<double> q, v;
  trajectory.sample(3, q, v);
  EXPECT_EQ(q, std::vector<double>{2});
}
