// The agents of pfx_node: characters of the world (pfx_character_controller.h) that have a
// name and a heading, and walk either where velocity commands send them or around a loop of
// waypoints. No ROS types here: PfxNodeSimulation owns the set with its world and updates it
// before every step; pfx_node_agents.h reads ROS parameters, services and topics into it.
//
// The world is z-up (gravity along -z), so an agent's heading is a turn about +z from +x. The
// controller keeps the capsule upright and never turns it: the heading is the set's own, and
// only says which way a command's linear.x points and where the agent's TF frame faces.
#pragma once

#include <string>
#include <vector>

#include "pfx/high_level/pfx_character_controller.h"

namespace pfx {

struct PfxNodeAgentSpec {
  std::string name;
  PfxFloat radius = PfxFloat(0.25);  // m, > 0
  PfxFloat height = PfxFloat(1.7);   // m, foot to head, > 2 radius
  PfxFloat mass = 80;                // kg, > 0
  // m/s, > 0: faster commands are cut down to it; a waypoint agent walks at it.
  PfxFloat maxSpeed = PfxFloat(1.5);
  PfxVector3 foot = PfxVector3::Zero();  // start: the capsule's lowest point
  PfxFloat yaw = 0;                      // start heading (rad)
  // Empty: the agent walks where commands send it. Otherwise it walks to each in turn and
  // from the last back to the first, forever; a waypoint's z is not looked at.
  std::vector<PfxVector3> waypoints;
};

struct PfxNodeAgentSetParam {
  // An agent stops when its last command is older than this (s of simulated time), so that
  // a driver that dies does not leave it walking.
  double commandTimeout = 0.5;
  PfxFloat maxTurnRate = 3;  // rad/s: faster turn commands are cut down to it
  // A waypoint is reached when the foot is this close to it horizontally (m).
  PfxFloat waypointTolerance = PfxFloat(0.1);
};

// Where an agent is, as the node publishes it.
struct PfxNodeAgentState {
  PfxVector3 foot = PfxVector3::Zero();
  PfxFloat yaw = 0;
  PfxUInt32 nextWaypoint = 0;  // index into spec.waypoints of the one it walks to
  PfxUInt32 waypointsReached = 0;
};

class PfxNodeAgentSet {
 public:
  // `world` must outlive the set; its gravity must be along -z.
  PfxNodeAgentSet(PfxWorld& world, const PfxNodeAgentSetParam& param);

  // Empty when `spec` is a valid agent for this set (a new name, sizes, speeds and poses in
  // range, its start and waypoints inside the world's bounds), else the reason. Says nothing about where it stands: see findOverlap.
  std::string check(const PfxNodeAgentSpec& spec) const;
  // The body that a capsule of `spec` at its start would overlap deepest, by more than
  // `tolerance` (m), and by how much; bodyId -1 when none does. Fails as
  // PfxWorld::queryContacts fails (a body whose state went bad), writing nothing.
  PfxInt32 findOverlap(const PfxNodeAgentSpec& spec, PfxFloat tolerance, PfxInt64& bodyId,
                       PfxFloat& depth);
  // Adds the agent standing at its start; the id is its index (getAgentSpec, getAgentState)
  // until an agent before it is removed. Rejects what check() rejects (with the reason in
  // *message); nothing changes then.
  PfxInt32 add(const PfxNodeAgentSpec& spec, std::string* message);
  // Takes the agent out of the world, its body removed (PfxWorld::removeRigidBody).
  // Rejects an unknown name (PFX_ERR_OUT_OF_RANGE).
  PfxInt32 remove(const std::string& name);
  // A velocity command: vx forward, vy to the left (m/s, in the agent's heading) and a turn
  // rate (rad/s), given at simulated time `time`; held until a newer one or the timeout.
  // Rejects an unknown name (PFX_ERR_OUT_OF_RANGE), a waypoint agent and a non-finite value
  // (PFX_ERR_INVALID_VALUE), leaving the last command as it was.
  PfxInt32 command(const std::string& name, PfxFloat vx, PfxFloat vy, PfxFloat turnRate,
                   double time);

  // Steers every agent for the step that starts at simulated time `time` and lasts
  // `timeStep`, and runs the controller's update: call right before PfxWorld::step().
  PfxInt32 update(double time, PfxFloat timeStep);

  PfxUInt32 getNumAgents() const { return static_cast<PfxUInt32>(m_agents.size()); }
  const PfxNodeAgentSpec& getAgentSpec(PfxUInt32 i) const { return m_agents[i].spec; }
  PfxUInt32 getAgentBody(PfxUInt32 i) const { return m_agents[i].bodyId; }
  PfxNodeAgentState getAgentState(PfxUInt32 i) const;
  // Index of the agent named `name`, or -1.
  PfxInt32 find(const std::string& name) const;
  // True for the body of an agent.
  bool isAgentBody(PfxUInt32 bodyId) const;
  const PfxNodeAgentSetParam& getParam() const { return m_param; }

 private:
  struct Agent {
    PfxNodeAgentSpec spec;
    PfxUInt32 characterId = 0;
    PfxUInt32 bodyId = 0;
    PfxFloat yaw = 0;
    PfxFloat vx = 0, vy = 0, turnRate = 0;  // the last command, cut to the limits
    double commandTime = 0;
    bool commanded = false;
    PfxUInt32 nextWaypoint = 0;
    PfxUInt32 waypointsReached = 0;
  };
  PfxCharacterParam characterParam(const PfxNodeAgentSpec& spec) const;
  PfxVector3 steer(Agent& agent, const PfxVector3& foot, double time, PfxFloat timeStep);

  PfxWorld& m_world;
  PfxNodeAgentSetParam m_param;
  PfxCharacterController m_controller;
  std::vector<Agent> m_agents;
};

}  // namespace pfx
