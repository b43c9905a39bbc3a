// ~link_states (pfx/LinkStates, as gazebo_msgs/LinkStates): every link of every model in
// the world, the robot of robot_description's and the added models', named
// "<model>::<link>" (the URDF's names), with the pose of the link's frame and its twist
// (the frame origin's velocity and the angular velocity) in the fixed frame.
#pragma once

#include <ros/ros.h>

#include <string>

#include "pfx/LinkStates.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeLinkStates {
 public:
  PfxNodeLinkStates(ros::NodeHandle& privateHandle, const std::string& fixedFrame);
  void publish(const PfxNodeSimulation& simulation, const ros::Time& stamp);

 private:
  ros::Publisher m_publisher;
  pfx::LinkStates m_message;
};

}  // namespace pfx
