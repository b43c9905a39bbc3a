#include "pfx_ros/pfx_node_link_states.h"

#include "pfx/high_level/pfx_imu_reading.h"
#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

PfxNodeLinkStates::PfxNodeLinkStates(ros::NodeHandle& privateHandle, const std::string& fixedFrame)
    : m_publisher(privateHandle.advertise<pfx::LinkStates>("link_states", 10)) {
  m_message.header.frame_id = fixedFrame;
}

void PfxNodeLinkStates::publish(const PfxNodeSimulation& simulation, const ros::Time& stamp) {
  m_message.header.stamp = stamp;
  m_message.name.clear();
  m_message.pose.clear();
  m_message.twist.clear();
  const PfxWorld& world = simulation.getWorld();
  for (PfxUInt32 slot = 0; slot < simulation.getNumModelSlots(); ++slot) {
    if (!simulation.hasModel(slot)) continue;
    const PfxUrdfModel& model = simulation.getModel(slot);
    const std::string& modelName = simulation.getModelName(slot);
    for (PfxUInt32 i = 0; i < model.links.size(); ++i) {
      const PfxTransform3 pose = simulation.getLinkPose(i, slot);
      const PfxRigidState& state = world.getRigidState(model.links[i].bodyId);
      geometry_msgs::Pose poseMsg;
      poseMsg.position = pfxToPointMsg(pose.translation());
      poseMsg.orientation = pfxToQuaternionMsg(PfxQuat(pose.linear()));
      geometry_msgs::Twist twist;
      twist.linear = pfxToVector3Msg(pfxGetPointVelocity(state, pose.translation()));
      twist.angular = pfxToVector3Msg(state.getAngularVelocity());
      m_message.name.push_back(modelName + "::" + model.links[i].name);
      m_message.pose.push_back(poseMsg);
      m_message.twist.push_back(twist);
    }
  }
  m_publisher.publish(m_message);
}

}  // namespace pfx
