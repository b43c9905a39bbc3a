// Joint control by topics, as ros_control's controllers under Gazebo take it (README,
// "Joint commands"):
// - <joint>/command (std_msgs/Float64), in the node's namespace, for every revolute,
//   continuous and prismatic joint that is not a mimic follower: a position, velocity or
//   effort as ~joint_interfaces says for that joint (position by default);
// - ~joint_group_command (std_msgs/Float64MultiArray): one value per joint of
//   ~joint_group's `joints`, all in its `interface`, all or none;
// - ~joint_trajectory (trajectory_msgs/JointTrajectory): followed in simulated time through
//   PfxJointTrajectory (cubic between points that carry velocities, straight lines
//   otherwise) as position targets, holding the last point at the end; a header stamp of 0
//   starts it now, and a new trajectory replaces the one being followed from its own start
//   time (one still waiting to start at once).
// Every command goes through pfxSetUrdfJointCommand, so the URDF's limits and effort limits
// win. A bad message (NaN or infinite values, unknown, fixed or mimic-follower joints,
// wrong sizes, times that do not increase) is dropped with a warning naming what was wrong,
// and changes nothing. A command on a joint of the trajectory being followed (or waiting to
// start), by topic or by ~set_joint_command, ends that trajectory: the newest command rules.
#pragma once

#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <string>
#include <vector>

#include "pfx/high_level/pfx_joint_trajectory.h"
#include "pfx_ros/pfx_node_refusal_log.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeJointCommands {
 public:
  // `useSimTime`: trajectory stamps are simulated time (else wall-clock ROS time, mapped
  // onto simulated time at their arrival). `model`: the simulation's model slot whose
  // joints these are (0: the robot of robot_description).
  PfxNodeJointCommands(ros::NodeHandle& handle, ros::NodeHandle& privateHandle,
                       PfxNodeSimulation& simulation, PfxNodeRefusalLog& log, bool useSimTime,
                       PfxUInt32 model = 0);

  // Reads ~joint_interfaces ({joint: position|velocity|effort}) and ~joint_group
  // ({joints: [...], interface: ...}) and subscribes; false, with *message naming the
  // parameter, the joint and the reason, when one is malformed.
  bool configure(std::string* message);
  // Before each step: the trajectory's reference at the end of the step becomes the
  // joints' position targets. After ~reset or ~load_world, whose world has no commands,
  // the trajectories are dropped.
  void update();
  // Ends the trajectories (followed or waiting) that hold one of `joints` (indices into
  // the model's joints), which another command has just taken over.
  void releaseFromTrajectories(const std::vector<PfxUInt32>& joints);

 private:
  struct Trajectory {
    std::vector<PfxUInt32> joints;  // indices into the model's joints
    PfxJointTrajectory curve;
    std::vector<PfxJointTrajectoryPoint> points;  // until it starts
    double startTime = 0;
    bool active = false;
  };

  // Index of a joint that takes commands, or -1 with *why saying why not.
  PfxInt32 commandable(const std::string& name, std::string* why) const;
  bool readInterfaces(std::string* message);
  bool readGroup(std::string* message);
  void onJointCommand(PfxUInt32 joint, const std_msgs::Float64& msg);
  void onGroupCommand(const std_msgs::Float64MultiArray& msg);
  void onTrajectory(const trajectory_msgs::JointTrajectory& msg);
  // Sends commands of one drive; warns with `source` and is false when refused.
  bool command(const std::string& source, const std::vector<PfxUInt32>& joints, PfxJointDrive drive,
               const std::vector<double>& values);
  void activate(Trajectory& next);

  ros::NodeHandle& m_handle;
  ros::NodeHandle& m_privateHandle;
  PfxNodeSimulation& m_simulation;
  PfxNodeRefusalLog& m_log;  // the node's, for warnings about the topics' messages
  bool m_useSimTime;
  PfxUInt32 m_model;
  std::vector<PfxJointDrive> m_interfaces;  // per model joint
  std::vector<PfxUInt32> m_groupJoints;
  PfxJointDrive m_groupInterface = kPfxJointDrivePosition;
  Trajectory m_current;
  Trajectory m_next;  // starts later, replacing m_current then
  std::vector<ros::Subscriber> m_subscribers;
  std::vector<double> m_positions, m_velocities;  // scratch of update()
  PfxUInt32 m_generation = 0;  // of the world the trajectories were given for
};

}  // namespace pfx
