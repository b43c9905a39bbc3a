#include "pfx_ros/pfx_node_state_publisher.h"

#include <rosgraph_msgs/Clock.h>

#include <unordered_map>

#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

PfxNodeStatePublisher::PfxNodeStatePublisher(ros::NodeHandle& handle, const std::string& fixedFrame,
                                             const std::string& agentFramePrefix, bool publishClock,
                                             PfxUInt32 model)
    : m_fixedFrame(fixedFrame),
      m_agentFramePrefix(agentFramePrefix.empty() ? "" : agentFramePrefix + "/"),
      m_publishClock(publishClock),
      m_model(model) {
  m_jointStates = handle.advertise<sensor_msgs::JointState>("joint_states", 10);
  if (m_publishClock) m_clock = handle.advertise<rosgraph_msgs::Clock>("/clock", 10);
}

void PfxNodeStatePublisher::bind(const PfxNodeSimulation& simulation) {
  if (!simulation.hasModel(m_model)) {
    m_parentLink.clear();
    m_transforms.clear();
    m_linkPoses.clear();
    m_publishedJoints.clear();
    m_jointStates.shutdown();
    return;
  }
  const PfxUrdfModel& model = simulation.getModel(m_model);
  std::unordered_map<std::string, PfxInt32> linkIndex;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    linkIndex[model.links[i].name] = PfxInt32(i);
  }
  m_parentLink.assign(model.links.size(), -1);
  for (const PfxUrdfJoint& joint : model.joints) {
    const auto child = linkIndex.find(joint.childLink);
    const auto parent = linkIndex.find(joint.parentLink);
    if (child != linkIndex.end() && parent != linkIndex.end()) {
      m_parentLink[child->second] = parent->second;
    }
  }
  m_transforms.assign(model.links.size(), geometry_msgs::TransformStamped());
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    m_transforms[i].header.frame_id =
        m_parentLink[i] < 0 ? m_fixedFrame
                            : simulation.getLinkName(PfxUInt32(m_parentLink[i]), m_model);
    m_transforms[i].child_frame_id = simulation.getLinkName(PfxUInt32(i), m_model);
  }
  m_linkPoses.resize(model.links.size());

  m_publishedJoints.clear();
  m_jointState.name.clear();
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const PfxUrdfJointType type = model.joints[j].type;
    if (type != kPfxUrdfRevolute && type != kPfxUrdfContinuous && type != kPfxUrdfPrismatic) {
      continue;
    }
    m_publishedJoints.push_back(PfxUInt32(j));
    m_jointState.name.push_back(model.joints[j].name);
  }
  m_jointState.position.resize(m_publishedJoints.size());
  m_jointState.velocity.resize(m_publishedJoints.size());
}

void PfxNodeStatePublisher::publish(const PfxNodeSimulation& simulation, const ros::Time& stamp) {
  for (std::size_t i = 0; i < m_linkPoses.size(); ++i) {
    m_linkPoses[i] = simulation.getLinkPose(PfxUInt32(i), m_model);
  }
  for (std::size_t i = 0; i < m_linkPoses.size(); ++i) {
    const PfxTransform3 pose =
        m_parentLink[i] < 0
            ? m_linkPoses[i]
            : PfxTransform3(m_linkPoses[m_parentLink[i]].inverse() * m_linkPoses[i]);
    m_transforms[i].header.stamp = stamp;
    m_transforms[i].transform = pfxToTransformMsg(pose);
  }
  // Agents come and go between publications: their frames are made anew each time.
  const PfxNodeAgentSet& agents = simulation.getAgents();
  const PfxUInt32 numAgents = m_model == 0 ? agents.getNumAgents() : 0;
  m_transforms.resize(m_linkPoses.size() + numAgents);
  for (PfxUInt32 i = 0; i < numAgents; ++i) {
    const PfxNodeAgentState state = agents.getAgentState(i);
    geometry_msgs::TransformStamped& agent = m_transforms[m_linkPoses.size() + i];
    agent.header.frame_id = m_fixedFrame;
    agent.header.stamp = stamp;
    agent.child_frame_id = m_agentFramePrefix + agents.getAgentSpec(i).name;
    agent.transform = pfxToTransformMsg(pfxMakeTransform(
        PfxQuat(Eigen::AngleAxis<PfxFloat>(state.yaw, PfxVector3::UnitZ())), state.foot));
  }
  if (!m_transforms.empty()) m_broadcaster.sendTransform(m_transforms);

  if (simulation.hasModel(m_model)) {
    pfxGetUrdfJointStates(simulation.getWorld(), simulation.getModel(m_model), m_positions,
                          m_velocities);
    for (std::size_t k = 0; k < m_publishedJoints.size(); ++k) {
      m_jointState.position[k] = m_positions[m_publishedJoints[k]];
      m_jointState.velocity[k] = m_velocities[m_publishedJoints[k]];
    }
    m_jointState.header.stamp = stamp;
    m_jointStates.publish(m_jointState);
  }

  if (m_publishClock) {
    rosgraph_msgs::Clock clock;
    clock.clock = stamp;
    m_clock.publish(clock);
  }
}

}  // namespace pfx
