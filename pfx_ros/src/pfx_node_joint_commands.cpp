#include "pfx_ros/pfx_node_joint_commands.h"

#include <ros/names.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "pfx/low_level/pfx_error_detail.h"

namespace pfx {

namespace {

constexpr const char* kInterfaceNames = "position, velocity or effort";

bool parseInterface(const std::string& text, PfxJointDrive& drive) {
  if (text == "position") {
    drive = kPfxJointDrivePosition;
  } else if (text == "velocity") {
    drive = kPfxJointDriveVelocity;
  } else if (text == "effort") {
    drive = kPfxJointDriveEffort;
  } else {
    return false;
  }
  return true;
}

bool contains(const std::vector<PfxUInt32>& joints, PfxUInt32 joint) {
  return std::find(joints.begin(), joints.end(), joint) != joints.end();
}

}  // namespace

PfxNodeJointCommands::PfxNodeJointCommands(ros::NodeHandle& handle,
                                           ros::NodeHandle& privateHandle,
                                           PfxNodeSimulation& simulation, PfxNodeRefusalLog& log,
                                           bool useSimTime, PfxUInt32 model)
    : m_handle(handle),
      m_privateHandle(privateHandle),
      m_simulation(simulation),
      m_log(log),
      m_useSimTime(useSimTime),
      m_model(model) {}

PfxInt32 PfxNodeJointCommands::commandable(const std::string& name, std::string* why) const {
  const PfxInt32 index = m_simulation.findJoint(name, m_model);
  if (index < 0) {
    *why = "unknown joint '" + name + "'";
    return -1;
  }
  const PfxUrdfModel& model = m_simulation.getModel(m_model);
  const PfxUrdfJoint& joint = model.joints[index];
  if (joint.jointId == kPfxUrdfNoJoint) {
    *why = "joint '" + name + "' has no coordinate to drive";
    return -1;
  }
  if (joint.mimicLeader >= 0) {
    *why = "joint '" + name + "' mimics '" + model.joints[joint.mimicLeader].name +
           "': command the leader";
    return -1;
  }
  return index;
}

bool PfxNodeJointCommands::configure(std::string* message) {
  const PfxUrdfModel& model = m_simulation.getModel(m_model);
  m_interfaces.assign(model.joints.size(), kPfxJointDrivePosition);
  m_generation = m_simulation.getGeneration();
  if (!readInterfaces(message) || !readGroup(message)) return false;
  for (PfxUInt32 i = 0; i < model.joints.size(); ++i) {
    const std::string& name = model.joints[i].name;
    std::string why;
    if (commandable(name, &why) < 0) continue;
    if (!ros::names::validate(name, why)) {
      ROS_WARN("pfx_node: joint '%s' gets no command topic: its name is no ROS name (%s)",
               name.c_str(), why.c_str());
      continue;
    }
    m_subscribers.push_back(m_handle.subscribe<std_msgs::Float64>(
        name + "/command", 1,
        boost::function<void(const std_msgs::Float64::ConstPtr&)>(
            [this, i](const std_msgs::Float64::ConstPtr& msg) { onJointCommand(i, *msg); })));
  }
  if (!m_groupJoints.empty()) {
    m_subscribers.push_back(m_privateHandle.subscribe(
        "joint_group_command", 1, &PfxNodeJointCommands::onGroupCommand, this));
  }
  m_subscribers.push_back(
      m_privateHandle.subscribe("joint_trajectory", 10, &PfxNodeJointCommands::onTrajectory, this));
  return true;
}

bool PfxNodeJointCommands::readInterfaces(std::string* message) {
  XmlRpc::XmlRpcValue interfaces;
  if (!m_privateHandle.getParam("joint_interfaces", interfaces)) return true;
  if (interfaces.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    *message = "~joint_interfaces must be a dict {joint: position|velocity|effort}";
    return false;
  }
  for (auto& [name, value] : interfaces) {
    std::string why;
    const PfxInt32 joint = commandable(name, &why);
    if (joint < 0) {
      *message = "~joint_interfaces: " + why;
      return false;
    }
    if (value.getType() != XmlRpc::XmlRpcValue::TypeString ||
        !parseInterface(static_cast<std::string>(value), m_interfaces[joint])) {
      *message = "~joint_interfaces: joint '" + name + "': the interface is " + kInterfaceNames;
      return false;
    }
  }
  return true;
}

bool PfxNodeJointCommands::readGroup(std::string* message) {
  XmlRpc::XmlRpcValue group;
  if (!m_privateHandle.getParam("joint_group", group)) return true;
  if (group.getType() != XmlRpc::XmlRpcValue::TypeStruct || !group.hasMember("joints") ||
      group["joints"].getType() != XmlRpc::XmlRpcValue::TypeArray || group["joints"].size() == 0) {
    *message = "~joint_group must be a dict with a non-empty list `joints` (and `interface`)";
    return false;
  }
  for (auto& [key, value] : group) {
    if (key != "joints" && key != "interface") {
      *message = "~joint_group: unknown key '" + key + "' (joints, interface)";
      return false;
    }
  }
  if (group.hasMember("interface") &&
      (group["interface"].getType() != XmlRpc::XmlRpcValue::TypeString ||
       !parseInterface(static_cast<std::string>(group["interface"]), m_groupInterface))) {
    *message = std::string("~joint_group: the interface is ") + kInterfaceNames;
    return false;
  }
  XmlRpc::XmlRpcValue& joints = group["joints"];
  for (int i = 0; i < joints.size(); ++i) {
    if (joints[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
      *message = "~joint_group: joints[" + std::to_string(i) + "] is not a joint name";
      return false;
    }
    std::string why;
    const PfxInt32 joint = commandable(static_cast<std::string>(joints[i]), &why);
    if (joint < 0) {
      *message = "~joint_group: " + why;
      return false;
    }
    if (contains(m_groupJoints, PfxUInt32(joint))) {
      *message = "~joint_group: joint '" + static_cast<std::string>(joints[i]) + "' named twice";
      return false;
    }
    m_groupJoints.push_back(PfxUInt32(joint));
  }
  return true;
}

bool PfxNodeJointCommands::command(const std::string& source, const std::vector<PfxUInt32>& joints,
                                   PfxJointDrive drive, const std::vector<double>& values) {
  const std::vector<PfxFloat> targets(values.begin(), values.end());
  const std::vector<PfxFloat> noForceLimits(joints.size(), 0);
  if (const PfxInt32 err = m_simulation.setJointCommands(joints, drive, targets, noForceLimits,
                                                         m_model);
      err != PFX_OK) {
    m_log.warn(source + " refused: " + pfxErrorString(err));
    return false;
  }
  const PfxUrdfModel& model = m_simulation.getModel(m_model);
  for (std::size_t i = 0; i < joints.size(); ++i) {
    std::string note;
    pfxClampUrdfJointTarget(model.joints[joints[i]], drive, targets[i], &note);
    if (!note.empty()) m_log.warn(source + ": " + note);
  }
  return true;
}

void PfxNodeJointCommands::releaseFromTrajectories(const std::vector<PfxUInt32>& joints) {
  for (Trajectory* trajectory : {&m_current, &m_next}) {
    const bool holds = std::any_of(joints.begin(), joints.end(), [&](PfxUInt32 joint) {
      return contains(trajectory->joints, joint);
    });
    if (!holds) continue;
    ROS_INFO("pfx_node: a joint command ends the joint trajectory %s",
             trajectory == &m_current ? "being followed" : "waiting to start");
    *trajectory = Trajectory();
  }
}

void PfxNodeJointCommands::onJointCommand(PfxUInt32 joint, const std_msgs::Float64& msg) {
  const std::string& name = m_simulation.getModel(m_model).joints[joint].name;
  const std::string source = m_handle.resolveName(name + "/command");
  if (!std::isfinite(msg.data)) {
    m_log.warn(source + " dropped: the value is not finite");
    return;
  }
  if (command(source, {joint}, m_interfaces[joint], {msg.data})) {
    releaseFromTrajectories({joint});
  }
}

void PfxNodeJointCommands::onGroupCommand(const std_msgs::Float64MultiArray& msg) {
  const std::string source = m_privateHandle.resolveName("joint_group_command");
  if (msg.data.size() != m_groupJoints.size()) {
    m_log.warn(source + " dropped: " + std::to_string(msg.data.size()) + " values for " +
               std::to_string(m_groupJoints.size()) + " joints");
    return;
  }
  for (std::size_t i = 0; i < msg.data.size(); ++i) {
    if (!std::isfinite(msg.data[i])) {
      m_log.warn(source + " dropped: the value of joint '" +
                 m_simulation.getModel(m_model).joints[m_groupJoints[i]].name + "' is not finite");
      return;
    }
  }
  if (command(source, m_groupJoints, m_groupInterface, msg.data)) {
    releaseFromTrajectories(m_groupJoints);
  }
}

void PfxNodeJointCommands::onTrajectory(const trajectory_msgs::JointTrajectory& msg) {
  const auto drop = [this](const std::string& why) {
    m_log.warn(m_privateHandle.resolveName("joint_trajectory") + " dropped: " + why);
  };
  if (msg.joint_names.empty()) return drop("no joint_names");
  Trajectory next;
  for (const std::string& name : msg.joint_names) {
    std::string why;
    const PfxInt32 joint = commandable(name, &why);
    if (joint < 0) return drop(why);
    if (contains(next.joints, PfxUInt32(joint))) return drop("joint '" + name + "' named twice");
    next.joints.push_back(PfxUInt32(joint));
  }
  for (const trajectory_msgs::JointTrajectoryPoint& point : msg.points) {
    PfxJointTrajectoryPoint p;
    p.timeFromStart = point.time_from_start.toSec();
    p.positions = point.positions;
    p.velocities = point.velocities;
    next.points.push_back(std::move(p));
  }
  // Checked now against the joints' present state, so that a bad trajectory is refused on
  // arrival, not when it would start.
  const double now = m_simulation.getTime();
  const std::vector<double> here(next.joints.size(), 0);
  if (next.curve.set(now, here, here, next.points) != PFX_OK) {
    std::string detail = pfxGetLastErrorDetail();
    const std::string prefix = "PfxJointTrajectory::set: ";
    if (detail.compare(0, prefix.size(), prefix) == 0) detail.erase(0, prefix.size());
    return drop(detail);
  }
  const ros::Time nowStamp = m_useSimTime ? ros::Time(now) : ros::Time::now();
  next.startTime = msg.header.stamp.isZero() ? now : now + (msg.header.stamp - nowStamp).toSec();
  m_next = std::move(next);
  if (m_next.startTime <= now) activate(m_next);
}

void PfxNodeJointCommands::activate(Trajectory& next) {
  // The joints start from where they are, or, on a trajectory being followed, from where it
  // meant them to be.
  const double now = m_simulation.getTime();
  std::vector<double> measured, measuredVelocities;
  pfxGetUrdfJointStates(m_simulation.getWorld(), m_simulation.getModel(m_model), measured,
                        measuredVelocities);
  if (m_current.active) m_current.curve.sample(now, m_positions, m_velocities);
  std::vector<double> positions, velocities;
  for (const PfxUInt32 joint : next.joints) {
    const auto followed = std::find(m_current.joints.begin(), m_current.joints.end(), joint);
    if (m_current.active && followed != m_current.joints.end()) {
      positions.push_back(m_positions[followed - m_current.joints.begin()]);
      velocities.push_back(m_velocities[followed - m_current.joints.begin()]);
    } else {
      positions.push_back(measured[joint]);
      velocities.push_back(measuredVelocities[joint]);
    }
  }
  next.curve.set(next.startTime, positions, velocities, next.points);
  next.points.clear();
  next.active = true;
  m_current = std::move(next);
  next = Trajectory();
}

void PfxNodeJointCommands::update() {
  if (m_simulation.getGeneration() != m_generation) {
    m_generation = m_simulation.getGeneration();
    m_current = Trajectory();
    m_next = Trajectory();
  }
  const double end = m_simulation.getTime() + m_simulation.getTimeStep();
  if (!m_next.joints.empty() && m_next.startTime < end) activate(m_next);
  if (!m_current.active) return;
  // The target is where the joint should be when the step ends, which the position drive
  // reaches within the step.
  m_current.curve.sample(end, m_positions, m_velocities);
  if (!command(m_privateHandle.resolveName("joint_trajectory"), m_current.joints, kPfxJointDrivePosition, m_positions) ||
      end > m_current.curve.getEndTime()) {
    // Done (the drives hold the last point) or refused: nothing more to send.
    m_current = Trajectory();
  }
}

}  // namespace pfx
