// /diagnostics: how the simulation runs, summed up over the steps since the last report:
// step time (mean and largest), the real-time factor reached and asked for, the mean time
// of each pipeline stage, and the error figures of the steps (deepest overlap, largest
// joint gap, largest change of energy and momentum), with the current contact count: all
// the points the bodies' manifolds hold (speculative ones too) and those that get_contacts
// lists, and the bodies asleep and awake.
#pragma once

#include <ros/ros.h>

#include <string>
#include <vector>

#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeDiagnostics {
 public:
  PfxNodeDiagnostics(ros::NodeHandle& handle, double targetRealTimeFactor);

  // ~set_physics changed it: later reports compare with the new factor.
  void setTargetRealTimeFactor(double factor) { m_targetRealTimeFactor = factor; }
  // After each step.
  void addStep(const PfxWorldStats& stats);
  // Publishes the report on the steps since the last one and starts a new one.
  void publish(const PfxNodeSimulation& simulation, bool paused, const ros::Time& stamp);

 private:
  void clear();

  ros::Publisher m_publisher;
  double m_targetRealTimeFactor;
  ros::WallTime m_windowStart;
  double m_windowStartSimTime = 0;
  PfxUInt64 m_steps = 0;
  double m_stepSecondsSum = 0;
  double m_stepSecondsMax = 0;
  double m_stageSecondsSum[kPfxStageCount] = {};
  double m_maxPenetration = 0;
  double m_maxJointGap = 0;
  double m_maxEnergyChange = 0;
  double m_maxLinearMomentumChange = 0;
  double m_maxAngularMomentumChange = 0;
  std::vector<PfxNodeContact> m_contacts;  // kept between reports: no allocation once grown
};

}  // namespace pfx
