// One robot added to the node's world while it runs (README, "Models"), as ROS sees it: the
// TF of its links under its frame prefix (<prefix>/<link>, the root under the fixed frame),
// joint_states, the sensors of its URDF's <gazebo> blocks and of <ns>/sensors, and the
// joint command topics (<ns>/<joint>/command, <ns>/joint_trajectory, and with
// <ns>/joint_group <ns>/joint_group_command; <ns>/joint_interfaces as ~joint_interfaces),
// all in its namespace <ns>. The same classes serve the robot of robot_description, so an
// added robot behaves as that one does; what it physically is lives in the simulation's
// model slot.
#pragma once

#include <ros/ros.h>

#include <memory>
#include <string>

#include "pfx_ros/pfx_node_joint_commands.h"
#include "pfx_ros/pfx_node_sensors.h"
#include "pfx_ros/pfx_node_simulation.h"
#include "pfx_ros/pfx_node_state_publisher.h"

namespace pfx {

class PfxNodeModel {
 public:
  // `robotNamespace` is resolved as NodeHandle resolves it (relative: in the node's
  // namespace). `log`: the node's, for warnings about its topics' messages.
  PfxNodeModel(PfxNodeSimulation& simulation, PfxUInt32 slot, const std::string& robotNamespace,
               const std::string& fixedFrame, bool useSimTime, PfxNodeRefusalLog& log);

  // Reads its sensors and joint command parameters and advertises and subscribes; false,
  // with *message saying why, when one is malformed (nothing is left advertised then).
  bool configure(std::string* message);
  // Before every step: trajectories become position targets.
  void beforeStep();
  // After every step: the sensors that are due publish.
  void afterStep(const ros::Time& stamp);
  void publishState(const ros::Time& stamp);
  // After ~reset or ~load_world rebuilt the world.
  void rebind();
  // Ends the trajectories that hold one of `joints`, which ~set_joint_command has just
  // commanded.
  void releaseFromTrajectories(const std::vector<PfxUInt32>& joints);

  PfxUInt32 getSlot() const { return m_slot; }
  const std::string& getNamespace() const { return m_handle.getNamespace(); }
  std::size_t getNumSensors() const { return m_sensors->getNumSensors(); }

 private:
  PfxNodeSimulation& m_simulation;
  PfxUInt32 m_slot;
  ros::NodeHandle m_handle;
  std::unique_ptr<PfxNodeStatePublisher> m_state;
  std::unique_ptr<PfxNodeSensors> m_sensors;
  std::unique_ptr<PfxNodeJointCommands> m_jointCommands;
};

}  // namespace pfx
