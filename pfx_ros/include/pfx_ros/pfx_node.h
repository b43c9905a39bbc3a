// pfx_node: simulates the robot of robot_description (with a ground and an optional
// OctoMap) at a fixed time step, paced by a real-time factor, and publishes and serves
// what pfx_node_state_publisher.h, pfx_node_diagnostics.h, pfx_node_markers.h and
// pfx_node_services.h describe. Everything runs on one thread: service calls are answered
// between steps, so they always see a whole step.
#pragma once

#include <ros/ros.h>

#include <memory>
#include <string>

#include "pfx_ros/pfx_node_agents.h"
#include "pfx_ros/pfx_node_autosave.h"
#include "pfx_ros/pfx_node_cable_params.h"
#include "pfx_ros/pfx_node_diagnostics.h"
#include "pfx_ros/pfx_node_joint_commands.h"
#include "pfx_ros/pfx_node_link_states.h"
#include "pfx_ros/pfx_node_markers.h"
#include "pfx_ros/pfx_node_models.h"
#include "pfx_ros/pfx_node_refusal_log.h"
#include "pfx_ros/pfx_node_sensors.h"
#include "pfx_ros/pfx_node_services.h"
#include "pfx_ros/pfx_node_simulation.h"
#include "pfx_ros/pfx_node_state_publisher.h"

namespace pfx {

// The node's parameters (private unless said otherwise), as read by PfxNode::initialize.
struct PfxNodeParam {
  PfxNodeSimulationConfig simulation;  // robot_description (not private), ~urdf_path,
                                       // ~octomap_file, ~world_file, ~ground_plane, ~ground_size,
                                       // ~dt, ~substeps, ~iterations, ~threads, ~fixed_base,
                                       // ~initial_height, ~allow_missing_meshes,
                                       // ~agent_cmd_vel_timeout, ~agent_max_turn_rate,
                                       // ~agent_waypoint_tolerance
  std::string fixedFrame = "world";  // ~fixed_frame
  // ~agent_frame_prefix: agents' frames are <prefix>/<name>, or <name> when empty. The
  // agents themselves (~agents) are read by PfxNodeAgents (pfx_node_agents.h), the cables and
  // cloths (~cables, ~cloths) by pfxAddDeclaredCablesAndCloths (pfx_node_cable_params.h), the
  // sensors (~sensors, ~sensor_seed) by PfxNodeSensors (pfx_node_sensors.h), the joint command
  // topics (~joint_interfaces, ~joint_group) by PfxNodeJointCommands
  // (pfx_node_joint_commands.h), the added models (~models) by PfxNodeModels
  // (pfx_node_models.h).
  std::string agentFramePrefix = "agents";
  double realTimeFactor = 1;  // ~real_time_factor: 0 runs as fast as it can
  // Wall-clock rates (Hz) of what is published; 0 for the state means after every step,
  // 0 for markers or diagnostics means never.
  double publishRate = 100;    // ~publish_rate: TF, /joint_states, /clock
  double markerRate = 10;      // ~marker_rate
  double diagnosticsRate = 1;  // ~diagnostics_rate
  double linkStatesRate = 10;  // ~link_states_rate
  int maxBatchRays = 100000;   // ~max_batch_rays
  bool paused = false;         // ~paused: start paused
};

class PfxNode {
 public:
  PfxNode();
  ~PfxNode();

  // Reads the parameters and builds the world; false (with the reason logged) when a
  // parameter is invalid or the robot does not load.
  bool initialize();
  // Steps until ROS shuts down.
  void run();

 private:
  bool readParam(PfxNodeParam& param) const;
  ros::Time stamp() const;
  // One step as the loop takes it: the simulation, then the diagnostics' and sensors' share.
  PfxInt32 stepOnce();
  // After ~reset or ~load_world: the state publisher and the sensors start on the new
  // world. True when they did.
  bool rebindIfRebuilt();
  // TF and joint_states of every model (and /clock).
  void publishState();
  // ~step's steps, and the state after them published at once.
  PfxInt32 stepPaused(PfxInt32 steps);
  // ~delete_model of the robot of robot_description: its bodies, then its sensors and
  // command topics; /clock and the agents' frames stay. Empty, or why not.
  std::string removeRobot();

  ros::NodeHandle m_handle;
  ros::NodeHandle m_privateHandle{"~"};
  PfxNodeParam m_param;
  bool m_useSimTime = false;
  PfxNodeSimulation m_simulation;
  PfxUInt32 m_boundGeneration = 0;
  ros::Time m_lastStateStamp;
  // Before the parts that log refusals through it, so that it outlives them.
  PfxNodeRefusalLog m_refusals;
  std::unique_ptr<PfxNodeServices> m_services;
  std::unique_ptr<PfxNodeStatePublisher> m_statePublisher;
  std::unique_ptr<PfxNodeDiagnostics> m_diagnostics;
  std::unique_ptr<PfxNodeMarkers> m_markers;
  std::unique_ptr<PfxNodeAgents> m_agents;
  // The robot of robot_description's; null once it is deleted.
  std::unique_ptr<PfxNodeSensors> m_sensors;
  std::unique_ptr<PfxNodeJointCommands> m_jointCommands;
  std::unique_ptr<PfxNodeModels> m_models;
  std::unique_ptr<PfxNodeLinkStates> m_linkStates;
  PfxNodeAutosave m_autosave;  // ~autosave_period, ~autosave_file, ~resume
};

}  // namespace pfx
