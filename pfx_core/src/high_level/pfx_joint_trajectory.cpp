#include "pfx/high_level/pfx_joint_trajectory.h"

#include <algorithm>
#include <cmath>

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

bool allFinite(const std::vector<double>& values) {
  for (const double x : values) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

// Empty when the waypoint holds one finite position per joint and no velocities or one
// finite velocity per joint; else what is wrong.
const char* checkPoint(const PfxJointTrajectoryPoint& point, std::size_t numJoints) {
  if (point.positions.size() != numJoints) return "positions are not one per joint";
  if (!point.velocities.empty() && point.velocities.size() != numJoints) {
    return "velocities are neither empty nor one per joint";
  }
  if (!allFinite(point.positions) || !allFinite(point.velocities)) {
    return "a position or velocity is NaN or infinite";
  }
  if (!std::isfinite(point.timeFromStart)) return "time_from_start is not finite";
  return nullptr;
}

// One joint between two waypoints, at s in [0, 1] of a segment `duration` long.
void interpolate(const PfxJointTrajectoryPoint& from, const PfxJointTrajectoryPoint& to,
                 std::size_t joint, double duration, double s, double& position,
                 double& velocity) {
  const double p0 = from.positions[joint], p1 = to.positions[joint];
  if (from.velocities.empty() || to.velocities.empty()) {
    position = p0 + s * (p1 - p0);
    velocity = (p1 - p0) / duration;
    return;
  }
  const double v0 = from.velocities[joint], v1 = to.velocities[joint];
  const double s2 = s * s, s3 = s2 * s;
  position = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * duration * v0 +
             (3 * s2 - 2 * s3) * p1 + (s3 - s2) * duration * v1;
  velocity = (6 * s2 - 6 * s) * (p0 - p1) / duration + (3 * s2 - 4 * s + 1) * v0 +
             (3 * s2 - 2 * s) * v1;
}

}  // namespace

PfxInt32 PfxJointTrajectory::set(double startTime, const std::vector<double>& startPositions,
                                 const std::vector<double>& startVelocities,
                                 const std::vector<PfxJointTrajectoryPoint>& points) {
  const std::size_t numJoints = startPositions.size();
  if (numJoints == 0 || points.empty()) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "PfxJointTrajectory::set: %s", numJoints == 0 ? "no joints" : "no points");
  }
  PfxJointTrajectoryPoint start;
  start.positions = startPositions;
  start.velocities = startVelocities;
  if (!std::isfinite(startTime) || startVelocities.size() != numJoints ||
      checkPoint(start, numJoints)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "PfxJointTrajectory::set: the start time or state is not finite or "
                          "not one value per joint");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (const char* why = checkPoint(points[i], numJoints)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE, "PfxJointTrajectory::set: point %zu: %s", i,
                            why);
    }
    const double previous = i == 0 ? 0 : points[i - 1].timeFromStart;
    const bool increasing = i == 0 ? points[i].timeFromStart >= 0
                                   : points[i].timeFromStart > previous;
    if (!increasing) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "PfxJointTrajectory::set: point %zu: time_from_start %g s is not "
                            "%s %g s",
                            i, points[i].timeFromStart, i == 0 ? "at least" : "after", previous);
    }
  }
  m_startTime = startTime;
  m_start = std::move(start);
  m_points = points;
  return PFX_OK;
}

double PfxJointTrajectory::getEndTime() const {
  return m_points.empty() ? m_startTime : m_startTime + m_points.back().timeFromStart;
}

void PfxJointTrajectory::sample(double time, std::vector<double>& positions,
                                std::vector<double>& velocities) const {
  const std::size_t numJoints = m_start.positions.size();
  positions.resize(numJoints);
  velocities.resize(numJoints);
  const double t = time - m_startTime;
  if (m_points.empty() || t <= 0) {
    positions = m_start.positions;
    velocities = m_start.velocities;
    return;
  }
  const PfxJointTrajectoryPoint* from = &m_start;
  for (const PfxJointTrajectoryPoint& to : m_points) {
    if (t < to.timeFromStart) {
      const double duration = to.timeFromStart - from->timeFromStart;
      const double s = (t - from->timeFromStart) / duration;
      for (std::size_t j = 0; j < numJoints; ++j) {
        interpolate(*from, to, j, duration, s, positions[j], velocities[j]);
      }
      return;
    }
    from = &to;
  }
  positions = m_points.back().positions;
  std::fill(velocities.begin(), velocities.end(), 0.0);
}

}  // namespace pfx
