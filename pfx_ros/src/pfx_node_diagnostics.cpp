#include "pfx_ros/pfx_node_diagnostics.h"

#include <diagnostic_msgs/DiagnosticArray.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pfx {

namespace {

// Beyond these the figures mean that the solve does not keep up with the scene: bodies
// sink visibly into each other or joints come apart.
constexpr double kWarnPenetration = 0.05;  // m
constexpr double kWarnJointGap = 0.01;     // m
// Below this fraction of the real-time factor asked for, the node says it falls behind.
constexpr double kWarnRealTimeShare = 0.8;

void addValue(diagnostic_msgs::DiagnosticStatus& status, const std::string& key, double value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  std::ostringstream text;
  text << value;
  kv.value = text.str();
  status.values.push_back(kv);
}

}  // namespace

PfxNodeDiagnostics::PfxNodeDiagnostics(ros::NodeHandle& handle, double targetRealTimeFactor)
    : m_targetRealTimeFactor(targetRealTimeFactor) {
  m_publisher = handle.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  m_windowStart = ros::WallTime::now();
}

void PfxNodeDiagnostics::clear() {
  m_steps = 0;
  m_stepSecondsSum = 0;
  m_stepSecondsMax = 0;
  std::fill(std::begin(m_stageSecondsSum), std::end(m_stageSecondsSum), 0.0);
  m_maxPenetration = 0;
  m_maxJointGap = 0;
  m_maxEnergyChange = 0;
  m_maxLinearMomentumChange = 0;
  m_maxAngularMomentumChange = 0;
}

void PfxNodeDiagnostics::addStep(const PfxWorldStats& stats) {
  ++m_steps;
  m_stepSecondsSum += stats.stepSeconds;
  m_stepSecondsMax = std::max(m_stepSecondsMax, stats.stepSeconds);
  for (int s = 0; s < kPfxStageCount; ++s) m_stageSecondsSum[s] += stats.stageSeconds[s];
  m_maxPenetration = std::max(m_maxPenetration, double(stats.maxPenetration));
  m_maxJointGap = std::max(m_maxJointGap, double(stats.maxJointGap));
  m_maxEnergyChange = std::max(m_maxEnergyChange, std::abs(stats.energyChange));
  m_maxLinearMomentumChange = std::max(m_maxLinearMomentumChange, stats.linearMomentumChange);
  m_maxAngularMomentumChange = std::max(m_maxAngularMomentumChange, stats.angularMomentumChange);
}

void PfxNodeDiagnostics::publish(const PfxNodeSimulation& simulation, bool paused,
                                 const ros::Time& stamp) {
  const ros::WallTime now = ros::WallTime::now();
  const double wallSeconds = (now - m_windowStart).toSec();
  const double simSeconds = simulation.getTime() - m_windowStartSimTime;
  const double realTimeFactor = wallSeconds > 0 ? simSeconds / wallSeconds : 0;
  const PfxWorldStats& last = simulation.getWorld().getStats();

  diagnostic_msgs::DiagnosticStatus status;
  status.name = "pfx_node: simulation";
  status.hardware_id = "pfx";
  status.level = diagnostic_msgs::DiagnosticStatus::OK;
  std::string message = paused ? "paused" : "running";
  if (!paused && m_targetRealTimeFactor > 0 &&
      realTimeFactor < kWarnRealTimeShare * m_targetRealTimeFactor) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    message += ", slower than the real-time factor asked for";
  }
  if (m_maxPenetration > kWarnPenetration) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    message += ", deep overlaps";
  }
  if (m_maxJointGap > kWarnJointGap) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    message += ", joints coming apart";
  }
  status.message = message;

  const double steps = m_steps > 0 ? double(m_steps) : 1.0;
  addValue(status, "simulated time (s)", simulation.getTime());
  addValue(status, "steps in this report", double(m_steps));
  addValue(status, "step time mean (ms)", 1e3 * m_stepSecondsSum / steps);
  addValue(status, "step time max (ms)", 1e3 * m_stepSecondsMax);
  addValue(status, "real-time factor", realTimeFactor);
  addValue(status, "real-time factor asked for (0: as fast as possible)", m_targetRealTimeFactor);
  for (int s = 0; s < kPfxStageCount; ++s) {
    addValue(status, std::string("stage ") + pfxStageName(PfxStage(s)) + " mean (ms)",
             1e3 * m_stageSecondsSum[s] / steps);
  }
  addValue(status, "max penetration (m)", m_maxPenetration);
  addValue(status, "max joint gap (m)", m_maxJointGap);
  addValue(status, "max energy change per step (J)", m_maxEnergyChange);
  addValue(status, "max linear momentum change per step (kg m/s)", m_maxLinearMomentumChange);
  addValue(status, "max angular momentum change per step (kg m^2/s)", m_maxAngularMomentumChange);
  // Sleeping bodies' contacts included, as get_contacts and the contact markers list them.
  // The points held include speculative ones, which get_contacts leaves out while they
  // neither touch nor push: a robot hanging just above the ground has the first and none of
  // the second.
  simulation.getContacts(m_contacts);
  addValue(status, "contact pairs", last.numContactPairs);
  addValue(status, "contact points", last.numContactPoints);
  addValue(status, "contact points touching or pushing (get_contacts)", double(m_contacts.size()));
  addValue(status, "bodies asleep", last.numSleepingBodies);
  addValue(status, "bodies awake", last.numAwakeBodies);
  const PfxWorld& world = simulation.getWorld();
  // Removed bodies and joints (a deleted agent's) leave slots that are not counted.
  addValue(status, "bodies", world.getNumRigidBodies() - world.getNumRemovedRigidBodies());
  addValue(status, "joints", world.getNumJoints() - world.getNumRemovedJoints());

  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stamp;
  array.status.push_back(status);
  m_publisher.publish(array);

  m_windowStart = now;
  m_windowStartSimTime = simulation.getTime();
  clear();
}

}  // namespace pfx
