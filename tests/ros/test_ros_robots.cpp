// rostest (robots.test): two robots that nobody on this project wrote, each in its own
// pfx_node started by launch/robot.launch (namespaces /kuka and /r2d2, wall-clock time):
// the KUKA iiwa arm bolted to the world, hanging under gravity within its joint limits
// and following position commands, and r2d2 dropped onto the ground, standing. Both
// answer rays that hit them.
#include <sensor_msgs/JointState.h>

#include <mutex>

#include "pfx/Raycast.h"
#include "pfx/SetJointCommand.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kFixedFrame = "world";

// The latest /<ns>/joint_states.
class JointStateWatcher {
 public:
  JointStateWatcher(ros::NodeHandle& nh, const std::string& topic)
      : m_sub(nh.subscribe(topic, 10, &JointStateWatcher::onState, this)) {}
  std::map<std::string, double> positions() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_positions;
  }

 private:
  void onState(const sensor_msgs::JointState& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (std::size_t i = 0; i < msg.name.size() && i < msg.position.size(); ++i) {
      m_positions[msg.name[i]] = msg.position[i];
    }
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::map<std::string, double> m_positions;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<JointStateWatcher> kukaJoints;
  pfx_test::UrdfRobot kuka;
  pfx_test::UrdfRobot r2d2;
};
Shared* shared = nullptr;

pfx::Raycast::Response raycast(const std::string& ns, double x, double y, double z, double dx,
                               double dy, double dz) {
  return pfx_test::raycast("/" + ns + "/pfx_node/raycast", x, y, z, dx, dy, dz);
}

TEST(Kuka, TfForEveryLink) {
  ASSERT_EQ(shared->kuka.links.size(), 8u);  // lbr_iiwa_link_0 .. 7
  for (const std::string& link : shared->kuka.links) {
    geometry_msgs::TransformStamped pose;
    EXPECT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, link, pose)) << link;
  }
}

TEST(Kuka, HangsWithinItsLimitsOnAFixedBase) {
  ros::WallDuration(2.0).sleep();  // the limp arm falls against its limits
  const std::map<std::string, double> positions = shared->kukaJoints->positions();
  int checked = 0;
  for (const auto& [name, joint] : shared->kuka.joints) {
    if (joint->type != urdf::Joint::REVOLUTE) continue;
    ASSERT_TRUE(positions.count(name)) << name << " missing from /kuka/joint_states";
    EXPECT_GE(positions.at(name), joint->limits->lower - 0.02) << name;
    EXPECT_LE(positions.at(name), joint->limits->upper + 0.02) << name;
    ++checked;
  }
  EXPECT_EQ(checked, 7);
  geometry_msgs::TransformStamped base;
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, shared->kuka.root, base));
  EXPECT_NEAR(base.transform.translation.x, 0.0, 1e-6);
  EXPECT_NEAR(base.transform.translation.y, 0.0, 1e-6);
  EXPECT_NEAR(base.transform.translation.z, 0.0, 1e-6);
  EXPECT_NEAR(base.transform.rotation.w, 1.0, 1e-6);
}

TEST(Kuka, FollowsPositionCommands) {
  pfx::SetJointCommand command;
  command.request.mode = pfx::SetJointCommand::Request::POSITION;
  const double targets[7] = {0.3, 0.6, -0.4, -1.0, 0.2, 0.5, 0.0};
  for (int j = 0; j < 7; ++j) {
    command.request.names.push_back("lbr_iiwa_joint_" + std::to_string(j + 1));
    command.request.targets.push_back(targets[j]);
  }
  command = call("/kuka/pfx_node/set_joint_command", command);
  ASSERT_TRUE(command.response.success) << command.response.message;
  // Wall-clock time: on a loaded machine the simulation may run behind real time.
  std::map<std::string, double> positions;
  const auto reached = [&] {
    positions = shared->kukaJoints->positions();
    for (int j = 0; j < 7; ++j) {
      const auto it = positions.find(command.request.names[j]);
      if (it == positions.end() || std::abs(it->second - targets[j]) > 0.02) return false;
    }
    return true;
  };
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  while (!reached() && ros::WallTime::now() < deadline) ros::WallDuration(0.1).sleep();
  for (int j = 0; j < 7; ++j) {
    const std::string name = command.request.names[j];
    ASSERT_TRUE(positions.count(name)) << name;
    EXPECT_NEAR(positions.at(name), targets[j], 0.02) << name;
  }
}

TEST(Kuka, RaycastHitsTheBase) {
  // Sideways at the base, which is bolted to the world at the origin.
  const pfx::Raycast::Response hit = raycast("kuka", 1.0, 0.0, 0.05, -2.0, 0.0, 0.0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.link, shared->kuka.root);
  EXPECT_GT(hit.point.x, 0.0);
  EXPECT_LT(hit.point.x, 0.2);
  EXPECT_GT(hit.normal.x, 0.5);
}

TEST(R2d2, TfForEveryLink) {
  ASSERT_EQ(shared->r2d2.links.size(), 16u);
  for (const std::string& link : shared->r2d2.links) {
    geometry_msgs::TransformStamped pose;
    EXPECT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, link, pose)) << link;
  }
}

TEST(R2d2, StandsOnTheGround) {
  // Dropped from 0.6 m, where its wheels hang 0.13 m above the ground: it lands, stands
  // with its base link at about 0.47 m, and stays there.
  geometry_msgs::TransformStamped base, previous;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  double moved = 1;
  while (ros::WallTime::now() < deadline) {
    previous = base;
    ros::WallDuration(0.5).sleep();
    ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, shared->r2d2.root, base));
    moved = std::abs(base.transform.translation.z - previous.transform.translation.z);
    if (moved < 1e-3 && base.transform.translation.z < 0.55) break;
  }
  EXPECT_LT(moved, 1e-3) << "r2d2 does not come to rest";
  const auto& q = base.transform.rotation;
  // z of the base's own z axis: 1 when upright.
  const double upright = 1 - 2 * (q.x * q.x + q.y * q.y);
  EXPECT_GT(upright, 0.95) << "r2d2 fell over";
  EXPECT_GT(base.transform.translation.z, 0.40);
  EXPECT_LT(base.transform.translation.z, 0.52);
}

TEST(R2d2, RaycastDownHitsIt) {
  geometry_msgs::TransformStamped base;
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, shared->r2d2.root, base));
  const pfx::Raycast::Response hit =
      raycast("r2d2", base.transform.translation.x, base.transform.translation.y, 3.0, 0, 0, -4.0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_TRUE(pfx_test::hasLink(shared->r2d2, hit.link)) << "hit '" << hit.link << "'";
  EXPECT_GT(hit.point.z, 0.6);  // the head, above the body
  EXPECT_NEAR(hit.normal.z, 1.0, 0.1);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_robots");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.kukaJoints = std::make_unique<JointStateWatcher>(state.ros->nh, "/kuka/joint_states");
  shared = &state;
  if (!pfx_test::waitForServices({"/kuka/pfx_node/raycast", "/r2d2/pfx_node/raycast"}, 30.0)) {
    ROS_FATAL("the pfx_node services did not appear");
    return 1;
  }
  if (!pfx_test::readRobot("/kuka/robot_description", state.kuka) ||
      !pfx_test::readRobot("/r2d2/robot_description", state.r2d2)) {
    ROS_FATAL("a robot_description is missing or not a URDF");
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
