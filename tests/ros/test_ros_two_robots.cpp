// rostest (two_robots.test): launch/two_robots.launch as a user starts it, without rviz.
// The TurtleBot of robot_description has the frames and topics its URDF names (base_scan,
// /scan, /imu, /joint_states), the second one, tb2 of ~models, the same under the prefix
// tb2/ and the namespace /tb2, at the pose the launch file gives it; each robot's scan and
// IMU are its own; ~models and ~link_states name both models; a model spawned while the
// node runs is drawn in ~markers, and a model-qualified link name reaches it.
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <limits>
#include <set>

#include "pfx/DeleteModel.h"
#include "pfx/LinkStates.h"
#include "pfx/SetBodyState.h"
#include "pfx/SpawnModel.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
const double kGravity = 9.80665;
// two_robots.launch: tb2's pose (x, y, yaw).
const double kTb2X = 0.8;
const double kTb2Y = 0.6;
const double kTb2Yaw = 2.4;
// Where this test spawns a crate (tests/ros/data/crate.urdf): clear of both robots and of
// tests/ros/data/obstacles.xml.
const double kCrateX = -1.5;
const double kCrateY = 0.5;

struct Robot {
  Robot(ros::NodeHandle& nh, const std::string& ns)
      : joints(nh, ns + "/joint_states"), scan(nh, ns + "/scan"), imu(nh, ns + "/imu") {}
  pfx_test::Latest<sensor_msgs::JointState> joints;
  pfx_test::Latest<sensor_msgs::LaserScan> scan;
  pfx_test::Latest<sensor_msgs::Imu> imu;
};

// The markers of the namespace "shapes" in the node's latest MarkerArray that draw
// something, by id, with the mean of their points.
class ShapeMarkers {
 public:
  explicit ShapeMarkers(ros::NodeHandle& nh)
      : m_sub(nh.subscribe(kNode + "markers", 5, &ShapeMarkers::onMarkers, this)) {}
  std::map<int, geometry_msgs::Point> drawn() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_drawn;
  }

 private:
  void onMarkers(const visualization_msgs::MarkerArray& array) {
    std::map<int, geometry_msgs::Point> drawn;
    for (const visualization_msgs::Marker& marker : array.markers) {
      if (marker.ns != "shapes" || marker.action != visualization_msgs::Marker::ADD ||
          marker.points.empty()) {
        continue;
      }
      geometry_msgs::Point mean;
      for (const geometry_msgs::Point& p : marker.points) {
        mean.x += p.x / double(marker.points.size());
        mean.y += p.y / double(marker.points.size());
        mean.z += p.z / double(marker.points.size());
      }
      drawn[marker.id] = mean;
    }
    std::lock_guard<std::mutex> lock(m_mutex);
    m_drawn = drawn;
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::map<int, geometry_msgs::Point> m_drawn;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::ClockWatcher> clock;
  std::unique_ptr<Robot> first, second;
  std::unique_ptr<pfx_test::Latest<pfx::LinkStates>> linkStates;
  std::unique_ptr<ShapeMarkers> markers;
};
Shared* shared = nullptr;

double yawOf(const geometry_msgs::Quaternion& q) {
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

TEST(TwoRobots, EachRobotHasItsFramesWhereTheLaunchFilePutsIt) {
  geometry_msgs::TransformStamped frame;
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "world", "base_footprint", frame));
  EXPECT_NEAR(frame.transform.translation.x, 0, 0.05);
  EXPECT_NEAR(frame.transform.translation.y, 0, 0.05);
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "world", "tb2/base_footprint", frame));
  EXPECT_NEAR(frame.transform.translation.x, kTb2X, 0.05);
  EXPECT_NEAR(frame.transform.translation.y, kTb2Y, 0.05);
  EXPECT_NEAR(yawOf(frame.transform.rotation), kTb2Yaw, 0.05);
  // Each laser hangs from its own robot.
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "base_footprint", "base_scan", frame));
  geometry_msgs::TransformStamped second;
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "tb2/base_footprint", "tb2/base_scan", second));
  EXPECT_NEAR(frame.transform.translation.z, second.transform.translation.z, 1e-3);
  EXPECT_GT(frame.transform.translation.z, 0.1);
}

TEST(TwoRobots, EachRobotPublishesItsJointStates) {
  const double now = shared->clock->now();
  for (Robot* robot : {shared->first.get(), shared->second.get()}) {
    sensor_msgs::JointState joints;
    ASSERT_TRUE(robot->joints.waitFor(now, joints));
    const std::set<std::string> names(joints.name.begin(), joints.name.end());
    EXPECT_EQ(names, (std::set<std::string>{"wheel_left_joint", "wheel_right_joint"}));
    ASSERT_EQ(joints.position.size(), 2u);
  }
}

TEST(TwoRobots, EachRobotsLaserAndImuReadInItsOwnFrame) {
  const double now = shared->clock->now();
  sensor_msgs::LaserScan first, second;
  ASSERT_TRUE(shared->first->scan.waitFor(now, first));
  ASSERT_TRUE(shared->second->scan.waitFor(now, second));
  EXPECT_EQ(first.header.frame_id, "base_scan");
  EXPECT_EQ(second.header.frame_id, "tb2/base_scan");
  ASSERT_EQ(first.ranges.size(), 360u);
  ASSERT_EQ(second.ranges.size(), 360u);
  // 1 m apart, each sees the other (and the wall): both see something within range, and
  // not the same thing.
  int hitsFirst = 0, hitsSecond = 0, differ = 0;
  for (std::size_t i = 0; i < 360; ++i) {
    hitsFirst += first.ranges[i] < first.range_max;
    hitsSecond += second.ranges[i] < second.range_max;
    differ += std::abs(first.ranges[i] - second.ranges[i]) > 0.05;
  }
  EXPECT_GT(hitsFirst, 10);
  EXPECT_GT(hitsSecond, 10);
  EXPECT_GT(differ, 10);

  sensor_msgs::Imu imuFirst, imuSecond;
  ASSERT_TRUE(shared->first->imu.waitFor(now, imuFirst));
  ASSERT_TRUE(shared->second->imu.waitFor(now, imuSecond));
  EXPECT_EQ(imuFirst.header.frame_id, "imu_link");
  EXPECT_EQ(imuSecond.header.frame_id, "tb2/imu_link");
  // Standing on the ground: +g upwards, whichever way each faces.
  EXPECT_NEAR(imuFirst.linear_acceleration.z, kGravity, 0.3);
  EXPECT_NEAR(imuSecond.linear_acceleration.z, kGravity, 0.3);
}

TEST(TwoRobots, ModelsAndLinkStatesNameBothRobots) {
  XmlRpc::XmlRpcValue models;
  ASSERT_TRUE(ros::param::get(kNode + "models", models));
  ASSERT_EQ(models.getType(), XmlRpc::XmlRpcValue::TypeArray);
  ASSERT_EQ(models.size(), 1);
  EXPECT_EQ(static_cast<std::string>(models[0]["name"]), "tb2");

  pfx::LinkStates states;
  ASSERT_TRUE(shared->linkStates->waitFor(shared->clock->now(), states));
  std::set<std::string> modelNames;
  for (const std::string& name : states.name) modelNames.insert(name.substr(0, name.find("::")));
  EXPECT_EQ(modelNames, (std::set<std::string>{"turtlebot3_burger", "tb2"}));
  for (const std::string model : {"turtlebot3_burger::", "tb2::"}) {
    for (const std::string link : {"base_footprint", "base_scan", "imu_link", "wheel_left_link"}) {
      EXPECT_EQ(std::count(states.name.begin(), states.name.end(), model + link), 1) << model + link;
    }
  }
}

TEST(TwoRobots, ASpawnedModelIsDrawnAndReachedByItsQualifiedName) {
  // Markers go out only to subscribers.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10);
  std::map<int, geometry_msgs::Point> before;
  while ((before = shared->markers->drawn()).empty()) {
    ASSERT_LT(ros::WallTime::now(), deadline) << "no shapes in ~markers";
    ros::WallDuration(0.05).sleep();
  }

  pfx::SpawnModel spawn;
  spawn.request.name = "box";
  spawn.request.urdf = pfx_test::readText(std::string(PFX_SOURCE_DIR) + "/tests/ros/data/crate.urdf");
  spawn.request.pose.position.x = kCrateX;
  spawn.request.pose.position.y = kCrateY;
  spawn.request.pose.position.z = 0.26;
  spawn.request.pose.orientation.w = 1;
  const pfx::SpawnModel::Response spawned = call(kNode + "spawn_model", spawn).response;
  ASSERT_TRUE(spawned.success) << spawned.message;

  // A new shape marker, drawn where the crate stands.
  bool found = false;
  const ros::WallTime drawnBy = ros::WallTime::now() + ros::WallDuration(10);
  while (!found && ros::WallTime::now() < drawnBy) {
    for (const auto& [id, mean] : shared->markers->drawn()) {
      found = found || (before.count(id) == 0 && std::abs(mean.x - kCrateX) < 0.1 &&
                        std::abs(mean.y - kCrateY) < 0.1);
    }
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_TRUE(found) << "the spawned crate is not among the shapes of ~markers";

  // Gazebo's form of the name reaches the new model's link; a link the model lacks and a
  // NaN pose are refused.
  pfx::SetBodyState lift;
  lift.request.link = "box::crate";
  lift.request.pose.position.x = kCrateX;
  lift.request.pose.position.y = kCrateY;
  lift.request.pose.position.z = 3;
  lift.request.pose.orientation.w = 1;
  const pfx::SetBodyState::Response lifted = call(kNode + "set_body_state", lift).response;
  EXPECT_TRUE(lifted.success) << lifted.message;
  geometry_msgs::TransformStamped frame;
  bool high = false;
  const ros::WallTime liftedBy = ros::WallTime::now() + ros::WallDuration(5);
  while (!high && ros::WallTime::now() < liftedBy) {
    high = pfx_test::lookup(shared->ros->tfBuffer, "world", "box/crate", frame, 1) &&
           frame.transform.translation.z > 0.8;
    ros::WallDuration(0.01).sleep();
  }
  EXPECT_TRUE(high) << "box/crate at z = " << frame.transform.translation.z;
  pfx::SetBodyState bad = lift;
  bad.request.link = "box::lid";
  pfx::SetBodyState::Response refused = call(kNode + "set_body_state", bad).response;
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("model 'box' has no link 'lid'"), std::string::npos)
      << refused.message;
  bad = lift;
  bad.request.pose.position.z = std::numeric_limits<double>::quiet_NaN();
  refused = call(kNode + "set_body_state", bad).response;
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("position is not finite"), std::string::npos) << refused.message;

  pfx::DeleteModel remove;
  remove.request.name = "box";
  const pfx::DeleteModel::Response removed = call(kNode + "delete_model", remove).response;
  EXPECT_TRUE(removed.success) << removed.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_two_robots");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  ros::NodeHandle& nh = state.ros->nh;
  state.clock = std::make_unique<pfx_test::ClockWatcher>(nh);
  state.first = std::make_unique<Robot>(nh, "");
  state.second = std::make_unique<Robot>(nh, "/tb2");
  state.linkStates = std::make_unique<pfx_test::Latest<pfx::LinkStates>>(nh, kNode + "link_states");
  state.markers = std::make_unique<ShapeMarkers>(nh);
  shared = &state;
  if (!pfx_test::waitForServices({kNode + "spawn_model", kNode + "set_body_state"}, 30.0) ||
      !state.clock->waitUntil(0.5, 30.0)) {
    ROS_FATAL("the pfx_node of two_robots.launch did not come up");
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
