#include "pfx_ros/pfx_node_agent_set.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pfx/high_level/pfx_body_init.h"

namespace pfx {

namespace {

// The controller climbs steps up to this high (m) when the agent is tall enough for it.
const PfxFloat kMaxStepHeight = PfxFloat(0.35);
// Sizes and speeds beyond these are typing mistakes, not people or robots; they would also
// take the solver out of the range it is tuned for.
const PfxFloat kMaxSize = 100;  // m
const PfxFloat kMaxMass = 1e5;  // kg
const PfxFloat kMaxSpeed = 50;  // m/s

bool inRange(PfxFloat x, PfxFloat low, PfxFloat high) {
  return std::isfinite(x) && x > low && x <= high;
}

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

PfxFloat wrapAngle(PfxFloat angle) { return std::atan2(std::sin(angle), std::cos(angle)); }

}  // namespace

PfxNodeAgentSet::PfxNodeAgentSet(PfxWorld& world, const PfxNodeAgentSetParam& param)
    : m_world(world), m_param(param), m_controller(world) {}

PfxCharacterParam PfxNodeAgentSet::characterParam(const PfxNodeAgentSpec& spec) const {
  PfxCharacterParam param;
  param.radius = spec.radius;
  param.height = spec.height;
  param.mass = spec.mass;
  param.maxSpeed = spec.maxSpeed;
  // Pushes and accelerates like the controller's 80 kg default (20 m/s^2), whatever its mass.
  param.maxForce = PfxCharacterParam().maxForce / PfxCharacterParam().mass * spec.mass;
  param.maxStepHeight = std::min(kMaxStepHeight, spec.height - 2 * spec.radius);
  return param;
}

std::string PfxNodeAgentSet::check(const PfxNodeAgentSpec& spec) const {
  if (spec.name.empty()) return "no name given";
  if (find(spec.name) >= 0) return "an agent named '" + spec.name + "' exists already";
  if (!inRange(spec.radius, 0, kMaxSize)) {
    return "radius " + number(spec.radius) + " m: must be > 0 and at most " + number(kMaxSize);
  }
  if (!inRange(spec.height, 2 * spec.radius, kMaxSize)) {
    return "height " + number(spec.height) + " m: must be more than twice the radius (" +
           number(2 * spec.radius) + ") and at most " + number(kMaxSize);
  }
  if (!inRange(spec.mass, 0, kMaxMass)) {
    return "mass " + number(spec.mass) + " kg: must be > 0 and at most " + number(kMaxMass);
  }
  if (!inRange(spec.maxSpeed, 0, kMaxSpeed)) {
    return "max_speed " + number(spec.maxSpeed) + " m/s: must be > 0 and at most " +
           number(kMaxSpeed);
  }
  if (!pfxIsFinite(spec.foot)) return "position is not finite";
  // A body that leaves the world's bounds is stopped there for good (outOfWorldBehavior).
  const PfxWorldParam& world = m_world.getParam();
  auto inWorld = [&](const PfxVector3& p) {
    return ((p - world.worldCenter).cwiseAbs().array() <= world.worldExtent.array()).all();
  };
  const std::string bounds = "the world (at most " + number(world.worldExtent.x()) + ", " +
                             number(world.worldExtent.y()) + " and " +
                             number(world.worldExtent.z()) + " m from its centre along x, y and z)";
  if (!inWorld(spec.foot) || !inWorld(spec.foot + PfxVector3(0, 0, spec.height))) {
    return "position is outside " + bounds;
  }
  if (!std::isfinite(spec.yaw)) return "yaw is not finite";
  for (std::size_t i = 0; i < spec.waypoints.size(); ++i) {
    const std::string which = "waypoint " + std::to_string(i);
    if (!pfxIsFinite(spec.waypoints[i])) return which + " is not finite";
    PfxVector3 level = spec.waypoints[i];
    level.z() = spec.foot.z();  // its z is not looked at
    if (!inWorld(level)) return which + " is outside " + bounds;
  }
  // What is checked above is what pfxCheckCharacterParam asks of characterParam(spec).
  return "";
}

PfxInt32 PfxNodeAgentSet::findOverlap(const PfxNodeAgentSpec& spec, PfxFloat tolerance,
                                      PfxInt64& bodyId, PfxFloat& depth) {
  // The capsule the controller would build, queried where it would stand.
  PfxCollidable collidable;
  collidable.reset();
  PfxShape capsule = pfxMakeShape(PfxCapsule(spec.height / 2 - spec.radius, spec.radius));
  capsule.setOffsetOrientation(PfxQuat::FromTwoVectors(PfxVector3::UnitX(), PfxVector3::UnitZ()));
  collidable.addShape(capsule);
  collidable.finish();
  PfxContactQueryInput query;
  query.collidable = &collidable;
  query.transform =
      pfxMakeTransform(PfxQuat::Identity(), spec.foot + PfxVector3(0, 0, spec.height / 2));
  PfxQueryContact contacts[64];
  PfxQueryContactsResult result;
  if (const PfxInt32 err = m_world.queryContacts(query, contacts, 64, result); err != PFX_OK) {
    return err;
  }
  depth = 0;
  bodyId = -1;
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    const PfxFloat overlap = -contacts[i].m_contact.m_distance;
    if (overlap > tolerance && overlap > depth) {
      depth = overlap;
      bodyId = contacts[i].m_rigidBodyId;
    }
  }
  return PFX_OK;
}

PfxInt32 PfxNodeAgentSet::add(const PfxNodeAgentSpec& spec, std::string* message) {
  if (const std::string why = check(spec); !why.empty()) {
    if (message) *message = why;
    return PFX_ERR_INVALID_VALUE;
  }
  // Room first, so that nothing can fail once the character is in the world.
  m_agents.reserve(m_agents.size() + 1);
  Agent agent;
  agent.spec = spec;
  agent.yaw = wrapAngle(spec.yaw);
  if (const PfxInt32 err =
          m_controller.addCharacter(characterParam(spec), spec.foot, &agent.characterId);
      err != PFX_OK) {
    if (message) *message = std::string("the world refused its body: ") + pfxErrorString(err);
    return err;
  }
  PfxCharacterStatus status;
  m_controller.getStatus(agent.characterId, status);
  agent.bodyId = status.rigidBodyId;
  m_agents.push_back(std::move(agent));
  return PFX_OK;
}

PfxInt32 PfxNodeAgentSet::remove(const std::string& name) {
  const PfxInt32 index = find(name);
  if (index < 0) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = m_controller.removeCharacter(m_agents[index].characterId);
      err != PFX_OK) {
    return err;
  }
  m_agents.erase(m_agents.begin() + index);
  return PFX_OK;
}

PfxInt32 PfxNodeAgentSet::command(const std::string& name, PfxFloat vx, PfxFloat vy,
                                  PfxFloat turnRate, double time) {
  const PfxInt32 index = find(name);
  if (index < 0) return PFX_ERR_OUT_OF_RANGE;
  Agent& agent = m_agents[index];
  if (!agent.spec.waypoints.empty()) return PFX_ERR_INVALID_VALUE;
  if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(turnRate)) {
    return PFX_ERR_INVALID_VALUE;
  }
  // The controller cuts the speed too, but only once the command is turned into the world
  // frame; cut here, the kept command is the one that acts.
  const PfxFloat speed = std::hypot(vx, vy);
  const PfxFloat scale = speed > agent.spec.maxSpeed ? agent.spec.maxSpeed / speed : 1;
  agent.vx = vx * scale;
  agent.vy = vy * scale;
  agent.turnRate = std::clamp(turnRate, -m_param.maxTurnRate, m_param.maxTurnRate);
  agent.commandTime = time;
  agent.commanded = true;
  return PFX_OK;
}

PfxVector3 PfxNodeAgentSet::steer(Agent& agent, const PfxVector3& foot, double time,
                                  PfxFloat timeStep) {
  if (agent.spec.waypoints.empty()) {
    if (!agent.commanded || time - agent.commandTime > m_param.commandTimeout) {
      return PfxVector3::Zero();
    }
    agent.yaw = wrapAngle(agent.yaw + agent.turnRate * timeStep);
    const PfxFloat c = std::cos(agent.yaw), s = std::sin(agent.yaw);
    return PfxVector3(c * agent.vx - s * agent.vy, s * agent.vx + c * agent.vy, 0);
  }
  const std::vector<PfxVector3>& waypoints = agent.spec.waypoints;
  // At most one waypoint is passed per step, so that a loop of points closer together than
  // the tolerance does not spin here.
  PfxVector3 toTarget = waypoints[agent.nextWaypoint] - foot;
  toTarget.z() = 0;
  if (toTarget.norm() <= m_param.waypointTolerance) {
    agent.nextWaypoint = (agent.nextWaypoint + 1) % waypoints.size();
    ++agent.waypointsReached;
    toTarget = waypoints[agent.nextWaypoint] - foot;
    toTarget.z() = 0;
  }
  const PfxFloat distance = toTarget.norm();
  if (distance <= m_param.waypointTolerance) return PfxVector3::Zero();
  agent.yaw = std::atan2(toTarget.y(), toTarget.x());
  return toTarget * (agent.spec.maxSpeed / distance);
}

PfxInt32 PfxNodeAgentSet::update(double time, PfxFloat timeStep) {
  for (Agent& agent : m_agents) {
    PfxCharacterStatus status;
    m_controller.getStatus(agent.characterId, status);
    const PfxVector3 velocity = steer(agent, status.footPosition, time, timeStep);
    if (const PfxInt32 err = m_controller.setDesiredVelocity(agent.characterId, velocity);
        err != PFX_OK) {
      return err;
    }
  }
  return m_controller.update();
}

PfxNodeAgentState PfxNodeAgentSet::getAgentState(PfxUInt32 i) const {
  const Agent& agent = m_agents[i];
  PfxCharacterStatus status;
  m_controller.getStatus(agent.characterId, status);
  PfxNodeAgentState state;
  state.foot = status.footPosition;
  state.yaw = agent.yaw;
  state.nextWaypoint = agent.nextWaypoint;
  state.waypointsReached = agent.waypointsReached;
  return state;
}

PfxInt32 PfxNodeAgentSet::find(const std::string& name) const {
  for (std::size_t i = 0; i < m_agents.size(); ++i) {
    if (m_agents[i].spec.name == name) return static_cast<PfxInt32>(i);
  }
  return -1;
}

bool PfxNodeAgentSet::isAgentBody(PfxUInt32 bodyId) const {
  return std::any_of(m_agents.begin(), m_agents.end(),
                     [bodyId](const Agent& agent) { return agent.bodyId == bodyId; });
}

}  // namespace pfx
