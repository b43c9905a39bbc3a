#include "pfx_ros/pfx_node_agents.h"

#include <boost/function.hpp>
#include <cctype>
#include <set>

#include "pfx_ros/pfx_ros_conversions.h"
#include "pfx_ros/pfx_node_xmlrpc.h"

namespace pfx {

namespace {

// The spawn request's defaults where it gives 0 (PfxNodeAgentSpec's values).
const double kDefaultMass = PfxNodeAgentSpec().mass;
const double kDefaultMaxSpeed = PfxNodeAgentSpec().maxSpeed;

// A list of 2 or 3 numbers (x, y and optionally z) into `out`; false otherwise.
bool readPoint(XmlRpc::XmlRpcValue& value, PfxVector3& out) {
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray) return false;
  if (value.size() != 2 && value.size() != 3) return false;
  double xyz[3] = {0, 0, 0};
  for (int i = 0; i < value.size(); ++i) {
    if (!pfxReadXmlRpcNumber(value[i], xyz[i])) return false;
  }
  out = PfxVector3(PfxFloat(xyz[0]), PfxFloat(xyz[1]), PfxFloat(xyz[2]));
  return true;
}

// One entry of ~agents into `spec`; empty, or what is wrong with it.
std::string readDeclared(XmlRpc::XmlRpcValue& entry, PfxNodeAgentSpec& spec) {
  if (entry.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    return "is not a dict (name, radius, height, mass, max_speed, position, yaw, waypoints)";
  }
  static const std::set<std::string> kKeys = {"name",      "radius",   "height", "mass",
                                              "max_speed", "position", "yaw",    "waypoints"};
  for (auto& [key, value] : entry) {
    if (kKeys.count(key) == 0) return "unknown key '" + key + "'";
  }
  if (!entry.hasMember("name") || entry["name"].getType() != XmlRpc::XmlRpcValue::TypeString) {
    return "has no name (a string)";
  }
  spec.name = static_cast<std::string>(entry["name"]);
  const std::pair<const char*, PfxFloat*> numbers[] = {{"radius", &spec.radius},
                                                       {"height", &spec.height},
                                                       {"mass", &spec.mass},
                                                       {"max_speed", &spec.maxSpeed},
                                                       {"yaw", &spec.yaw}};
  for (const auto& [key, field] : numbers) {
    if (!entry.hasMember(key)) continue;
    double x = 0;
    if (!pfxReadXmlRpcNumber(entry[key], x)) return std::string(key) + " is not a number";
    *field = PfxFloat(x);
  }
  if (entry.hasMember("position") && !readPoint(entry["position"], spec.foot)) {
    return "position is not a list [x, y] or [x, y, z] of numbers";
  }
  if (entry.hasMember("waypoints")) {
    XmlRpc::XmlRpcValue& list = entry["waypoints"];
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) return "waypoints is not a list";
    for (int i = 0; i < list.size(); ++i) {
      PfxVector3 point;
      if (!readPoint(list[i], point)) {
        return "waypoint " + std::to_string(i) + " is not a list [x, y] or [x, y, z] of numbers";
      }
      spec.waypoints.push_back(point);
    }
  }
  return "";
}

}  // namespace

std::string pfxCheckAgentName(const std::string& name) {
  if (name.empty()) return "no name given";
  bool valid = std::isalpha(static_cast<unsigned char>(name[0])) != 0;
  for (const char c : name) {
    valid = valid && (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_');
  }
  if (!valid) {
    return "'" + name + "' is not a valid agent name (letters, digits and _, a letter first)";
  }
  return "";
}

PfxNodeAgents::PfxNodeAgents(ros::NodeHandle& handle, ros::NodeHandle& privateHandle,
                             PfxNodeSimulation& simulation, PfxNodeRefusalLog& refusals)
    : m_handle(handle),
      m_privateHandle(privateHandle),
      m_simulation(simulation),
      m_refusals(refusals) {
  m_servers.push_back(privateHandle.advertiseService("spawn_agent", &PfxNodeAgents::spawn, this));
  m_servers.push_back(privateHandle.advertiseService("delete_agent", &PfxNodeAgents::remove, this));
}

bool PfxNodeAgents::add(const PfxNodeAgentSpec& spec, std::string* message) {
  if (const std::string why = pfxCheckAgentName(spec.name); !why.empty()) {
    if (message) *message = why;
    return false;
  }
  if (m_simulation.addAgent(spec, message) != PFX_OK) return false;
  if (spec.waypoints.empty()) {
    const std::string name = spec.name;
    m_commands[name] = m_handle.subscribe<geometry_msgs::Twist>(
        name + "/cmd_vel", 1,
        boost::function<void(const geometry_msgs::Twist::ConstPtr&)>(
            [this, name](const geometry_msgs::Twist::ConstPtr& twist) {
              onCommand(name, *twist);
            }));
  }
  return true;
}

bool PfxNodeAgents::addDeclared(std::string* message) {
  XmlRpc::XmlRpcValue list;
  if (!m_privateHandle.getParam("agents", list)) return true;
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    if (message) *message = "~agents must be a list of dicts";
    return false;
  }
  for (int i = 0; i < list.size(); ++i) {
    PfxNodeAgentSpec spec;
    std::string why = readDeclared(list[i], spec);
    if (why.empty()) add(spec, &why);  // which says why when it refuses
    if (!why.empty()) {
      if (message) *message = "~agents[" + std::to_string(i) + "]: " + why;
      return false;
    }
    ROS_INFO("pfx_node: agent '%s' at (%g, %g, %g), %s", spec.name.c_str(), double(spec.foot.x()),
             double(spec.foot.y()), double(spec.foot.z()),
             spec.waypoints.empty() ? "driven by cmd_vel" : "walking its waypoints");
  }
  return true;
}

bool PfxNodeAgents::spawn(SpawnAgent::Request& req, SpawnAgent::Response& res) {
  PfxNodeAgentSpec spec;
  spec.name = req.name;
  spec.radius = PfxFloat(req.radius);
  spec.height = PfxFloat(req.height);
  spec.mass = PfxFloat(req.mass == 0 ? kDefaultMass : req.mass);
  spec.maxSpeed = PfxFloat(req.max_speed == 0 ? kDefaultMaxSpeed : req.max_speed);
  spec.foot = pfxFromMsg(req.position);
  spec.yaw = PfxFloat(req.yaw);
  for (const geometry_msgs::Point& point : req.waypoints) {
    spec.waypoints.push_back(pfxFromMsg(point));
  }
  std::string why;
  if (!add(spec, &why)) return pfxRejectRequest(m_refusals, res, "spawn_agent", why);
  res.success = true;
  res.message =
      "agent '" + spec.name + "' added, " +
      (spec.waypoints.empty() ? "driven by " + m_handle.resolveName(spec.name + "/cmd_vel")
                              : "walking " + std::to_string(spec.waypoints.size()) + " waypoints");
  return true;
}

bool PfxNodeAgents::remove(DeleteAgent::Request& req, DeleteAgent::Response& res) {
  std::string why;
  if (m_simulation.removeAgent(req.name, &why) != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, "delete_agent", req.name.empty() ? "no name given" : why);
  }
  m_commands.erase(req.name);
  res.success = true;
  res.message = "agent '" + req.name + "' deleted";
  return true;
}

void PfxNodeAgents::onCommand(const std::string& name, const geometry_msgs::Twist& twist) {
  const PfxInt32 err = m_simulation.commandAgent(
      name, PfxFloat(twist.linear.x), PfxFloat(twist.linear.y), PfxFloat(twist.angular.z));
  if (err != PFX_OK) {
    m_refusals.warn(m_handle.resolveName(name + "/cmd_vel") +
                    " dropped: linear.x, linear.y and angular.z must be finite");
  }
}

}  // namespace pfx
