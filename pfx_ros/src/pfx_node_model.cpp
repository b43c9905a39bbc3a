#include "pfx_ros/pfx_node_model.h"

namespace pfx {

PfxNodeModel::PfxNodeModel(PfxNodeSimulation& simulation, PfxUInt32 slot,
                           const std::string& robotNamespace, const std::string& fixedFrame,
                           bool useSimTime, PfxNodeRefusalLog& log)
    : m_simulation(simulation), m_slot(slot), m_handle(robotNamespace) {
  // /clock is the robot of robot_description's to publish, and the agents' frames too.
  m_state = std::make_unique<PfxNodeStatePublisher>(m_handle, fixedFrame, "", false, slot);
  m_sensors = std::make_unique<PfxNodeSensors>(m_handle, fixedFrame, slot);
  // Its namespace is its private one too: <ns>/joint_trajectory, <ns>/joint_interfaces.
  m_jointCommands =
      std::make_unique<PfxNodeJointCommands>(m_handle, m_handle, simulation, log, useSimTime,
                                                         slot);
}

bool PfxNodeModel::configure(std::string* message) {
  const PfxNodeModelSpec& spec = m_simulation.getModelSpec(m_slot);
  const std::string urdfName = spec.urdfPath.empty() ? "model '" + spec.name + "'" : spec.urdfPath;
  if (!m_sensors->configure(spec.urdfXml, urdfName, m_handle, m_simulation, message) ||
      !m_jointCommands->configure(message)) {
    return false;
  }
  m_state->bind(m_simulation);
  return true;
}

void PfxNodeModel::beforeStep() { m_jointCommands->update(); }

void PfxNodeModel::afterStep(const ros::Time& stamp) { m_sensors->update(m_simulation, stamp); }

void PfxNodeModel::publishState(const ros::Time& stamp) { m_state->publish(m_simulation, stamp); }

void PfxNodeModel::releaseFromTrajectories(const std::vector<PfxUInt32>& joints) {
  m_jointCommands->releaseFromTrajectories(joints);
}

void PfxNodeModel::rebind() {
  m_state->bind(m_simulation);
  m_sensors->restart();
}

}  // namespace pfx
