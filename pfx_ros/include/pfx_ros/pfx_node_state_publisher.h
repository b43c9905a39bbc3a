// What the node publishes of the robot's state: TF for every link (the URDF tree, its
// root under the fixed frame), /joint_states, and /clock when the node runs on simulated
// time (use_sim_time). Every message of /joint_states names every revolute, continuous and
// prismatic joint of the URDF, in the file's order: mimic followers, and joints held at zero
// under a massless leaf (position and velocity 0) too, so that whoever rebuilds the robot
// from it (robot_state_publisher, MoveIt) finds each joint it knows. Floating and planar
// joints have no single coordinate; TF gives their child's pose. Each agent has a frame
// <agent frame prefix>/<name> under the fixed frame, at its foot and turned to its heading,
// published with the links and no longer once the agent is deleted.
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/transform_broadcaster.h>

#include <string>
#include <vector>

#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeStatePublisher {
 public:
  // An empty agentFramePrefix names agents' frames by the agents' names alone. `model` is
  // the simulation's model slot published: the robot of robot_description (0) publishes
  // the agents' frames too; an added model publishes its links only, under their names
  // with its frame prefix (PfxNodeSimulation::getLinkName), and joint_states in `handle`'s
  // namespace.
  PfxNodeStatePublisher(ros::NodeHandle& handle, const std::string& fixedFrame,
                        const std::string& agentFramePrefix, bool publishClock,
                        PfxUInt32 model = 0);

  // Reads the link tree and joint list of the simulation's robot; call after every load
  // or reset, and after the model is removed (then only the agents' frames and /clock are
  // published, and joint_states no longer).
  void bind(const PfxNodeSimulation& simulation);
  void publish(const PfxNodeSimulation& simulation, const ros::Time& stamp);

 private:
  std::string m_fixedFrame;
  std::string m_agentFramePrefix;  // with its slash
  bool m_publishClock;
  PfxUInt32 m_model;
  tf2_ros::TransformBroadcaster m_broadcaster;
  ros::Publisher m_jointStates;
  ros::Publisher m_clock;
  // Per link: index of its parent link in the model, or -1 when it hangs from the fixed frame.
  std::vector<PfxInt32> m_parentLink;
  std::vector<geometry_msgs::TransformStamped> m_transforms;  // the links', then the agents'
  std::vector<PfxTransform3> m_linkPoses;
  std::vector<PfxUInt32> m_publishedJoints;  // indices into the model's joints
  std::vector<double> m_positions;
  std::vector<double> m_velocities;
  sensor_msgs::JointState m_jointState;
};

}  // namespace pfx
