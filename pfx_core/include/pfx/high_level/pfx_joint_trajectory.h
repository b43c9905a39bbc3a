// A joint trajectory followed in simulated time, as a trajectory controller follows one:
// waypoints of positions (and optionally velocities) for a set of joints at times from its
// start, reached from the joints' state at the start. Between two waypoints the reference
// is a cubic (Hermite) when both carry velocities, so that position and velocity are
// continuous, and a straight line otherwise; after the last waypoint it holds there at
// rest. Units are the joints' (rad or m); times are seconds of simulated time.
#pragma once

#include <vector>

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

struct PfxJointTrajectoryPoint {
  double timeFromStart = 0;      // s, after the trajectory's start
  std::vector<double> positions;   // one per joint
  std::vector<double> velocities;  // one per joint, or empty: straight lines to and from it
};

class PfxJointTrajectory {
 public:
  // Takes the waypoints, to be followed from `startTime`, where the joints are at
  // `startPositions` moving at `startVelocities` (one per joint each). Rejects, with the
  // detail in pfxGetLastErrorDetail() naming the waypoint and what is wrong, and nothing
  // changed: no joints or no waypoints (PFX_ERR_INVALID_VALUE), a waypoint or start state
  // whose sizes are not one per joint (PFX_ERR_INVALID_VALUE), a NaN or infinite value or
  // time, a negative first time, and times that do not increase from waypoint to waypoint.
  PfxInt32 set(double startTime, const std::vector<double>& startPositions,
               const std::vector<double>& startVelocities,
               const std::vector<PfxJointTrajectoryPoint>& points);

  bool isEmpty() const { return m_points.empty(); }
  PfxUInt32 getNumJoints() const { return static_cast<PfxUInt32>(m_start.positions.size()); }
  double getStartTime() const { return m_startTime; }
  // When the last waypoint is reached.
  double getEndTime() const;

  // The reference at `time`: the start state before the start, then the curves, then the
  // last waypoint at rest. `positions` and `velocities` get one value per joint.
  void sample(double time, std::vector<double>& positions, std::vector<double>& velocities) const;

 private:
  double m_startTime = 0;
  PfxJointTrajectoryPoint m_start;  // the joints' state at the start, at time 0
  std::vector<PfxJointTrajectoryPoint> m_points;
};

}  // namespace pfx
