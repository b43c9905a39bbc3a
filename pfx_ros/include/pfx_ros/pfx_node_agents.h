// The node's agents as ROS sees them (README, "Agents"): those declared in ~agents, the
// services ~spawn_agent and ~delete_agent (pfx/SpawnAgent, pfx/DeleteAgent), and one
// geometry_msgs/Twist subscription <name>/cmd_vel, in the node's namespace, per agent that
// has no waypoints. The agents themselves live in the simulation (pfx_node_agent_set.h);
// their frames and markers are published with the robot's (pfx_node_state_publisher.h,
// pfx_node_markers.h).
//
// A Twist drives its agent as a mobile base is driven (REP 103): linear.x forward and
// linear.y to the left in the agent's heading, angular.z its turn rate; the other fields
// are not looked at. A speed above the agent's max_speed is cut to it and a turn rate above
// ~agent_max_turn_rate to that; a Twist with a NaN or infinite field is dropped with a
// warning, the previous command staying in force. The agent stops once its last command is
// older than ~agent_cmd_vel_timeout seconds of simulated time.
#pragma once

#include <geometry_msgs/Twist.h>
#include <ros/ros.h>

#include <map>
#include <string>
#include <vector>

#include "pfx/DeleteAgent.h"
#include "pfx/SpawnAgent.h"
#include "pfx_ros/pfx_node_refusal_log.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

// Empty when `name` can name an agent: letters, digits and underscores, a letter first (a
// valid ROS name without namespaces, so that <name>/cmd_vel and the frame are both valid);
// else why not.
std::string pfxCheckAgentName(const std::string& name);

class PfxNodeAgents {
 public:
  PfxNodeAgents(ros::NodeHandle& handle, ros::NodeHandle& privateHandle,
                PfxNodeSimulation& simulation, PfxNodeRefusalLog& refusals);

  // Adds the agents of ~agents (a list of dicts: README, "Agents"); false, with *message
  // naming the agent, the key and the reason, when one is malformed or refused (the agents
  // before it stay).
  bool addDeclared(std::string* message);

 private:
  bool spawn(SpawnAgent::Request& req, SpawnAgent::Response& res);
  bool remove(DeleteAgent::Request& req, DeleteAgent::Response& res);
  void onCommand(const std::string& name, const geometry_msgs::Twist& twist);
  // PfxNodeSimulation::addAgent, then the agent's subscription.
  bool add(const PfxNodeAgentSpec& spec, std::string* message);

  ros::NodeHandle& m_handle;
  ros::NodeHandle& m_privateHandle;
  PfxNodeSimulation& m_simulation;
  PfxNodeRefusalLog& m_refusals;
  std::vector<ros::ServiceServer> m_servers;
  std::map<std::string, ros::Subscriber> m_commands;  // by agent name
};

}  // namespace pfx
