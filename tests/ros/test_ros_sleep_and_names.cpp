// rostest (sleep_and_names.test): tests/ros/data/sleeper.urdf, a robot lying flat on the
// ground, falls asleep there. Asleep, it is still in get_contacts and in the way of rays, and
// the queries do not wake it. Contacts and hits name the link whose <collision> they meet
// (arm, not the massless helper link1_14 lumped with it). /joint_states names every joint
// with a coordinate in every message, in the file's order (the mimic follower and the joint
// held at zero under the massless sensor too). Driven past its limit without a force limit,
// the gripper stops at the limit, the service says which target it cut, and the follower
// mirrors the leader.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <sensor_msgs/JointState.h>
#include <visualization_msgs/MarkerArray.h>

#include <mutex>
#include <regex>
#include <set>

#include "pfx/GetContacts.h"
#include "pfx/Raycast.h"
#include "pfx/RaycastBatch.h"
#include "pfx/SetJointCommand.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
// The robot's four bodies: the base, the arm (lumped with its helper) and two fingers.
constexpr double kRobotBodies = 4;

// The latest values of the node's /diagnostics, and how many reports came.
class DiagnosticsWatcher {
 public:
  explicit DiagnosticsWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/diagnostics", 10, &DiagnosticsWatcher::onReport, this)) {}
  int reports() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_reports;
  }
  // The value under `key` in the latest report, NaN before the first.
  double value(const std::string& key) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    const auto it = m_values.find(key);
    return it == m_values.end() ? std::nan("") : std::stod(it->second);
  }
  bool robotAsleep() const {
    return value("bodies awake") == 0 && value("bodies asleep") >= kRobotBodies;
  }
  // Waits for a report after the one seen now; false after `wallSeconds`.
  bool waitForNextReport(double wallSeconds) const {
    const int seen = reports();
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (reports() == seen) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.02).sleep();
    }
    return true;
  }

 private:
  void onReport(const diagnostic_msgs::DiagnosticArray& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const diagnostic_msgs::DiagnosticStatus& status : msg.status) {
      if (status.name != "pfx_node: simulation") continue;
      for (const diagnostic_msgs::KeyValue& kv : status.values) m_values[kv.key] = kv.value;
      ++m_reports;
    }
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::map<std::string, std::string> m_values;
  int m_reports = 0;
};

// Every /joint_states message: the name lists that differ from the first one's, and the
// latest positions.
class JointStateWatcher {
 public:
  explicit JointStateWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/joint_states", 100, &JointStateWatcher::onState, this)) {}
  int messages() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_messages;
  }
  std::vector<std::string> firstNames() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_firstNames;
  }
  int messagesWithOtherNames() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_otherNames;
  }
  int messagesWithMissingValues() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_missingValues;
  }
  std::map<std::string, double> positions() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_positions;
  }

 private:
  void onState(const sensor_msgs::JointState& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_messages++ == 0) m_firstNames = msg.name;
    if (msg.name != m_firstNames) ++m_otherNames;
    if (msg.position.size() != msg.name.size() || msg.velocity.size() != msg.name.size()) {
      ++m_missingValues;
      return;
    }
    for (std::size_t i = 0; i < msg.name.size(); ++i) m_positions[msg.name[i]] = msg.position[i];
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  int m_messages = 0;
  int m_otherNames = 0;
  int m_missingValues = 0;
  std::vector<std::string> m_firstNames;
  std::map<std::string, double> m_positions;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<DiagnosticsWatcher> diagnostics;
  std::unique_ptr<JointStateWatcher> joints;
  pfx_test::UrdfRobot robot;
  std::string urdfText;
};
Shared* shared = nullptr;

// The joints with one coordinate (revolute, continuous, prismatic), in the file's order.
std::vector<std::string> jointsWithACoordinateInFileOrder() {
  std::vector<std::string> names;
  const std::regex jointTag("<joint\\s[^>]*name=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(shared->urdfText.begin(), shared->urdfText.end(), jointTag);
       it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1];
    const auto joint = shared->robot.joints.find(name);
    if (joint == shared->robot.joints.end()) continue;
    const int type = joint->second->type;
    if (type == urdf::Joint::REVOLUTE || type == urdf::Joint::CONTINUOUS ||
        type == urdf::Joint::PRISMATIC) {
      names.push_back(name);
    }
  }
  return names;
}

// The link a ray straight down onto (x, y) hits.
std::string linkBelow(double x, double y) {
  const pfx::Raycast::Response hit = pfx_test::raycast(kNode + "raycast", x, y, 1.0, 0, 0, -2.0);
  EXPECT_TRUE(hit.success) << hit.message;
  return hit.hit ? hit.link : "";
}

// Where rays from above meet each link of the robot lying flat (tests/ros/data/sleeper.urdf:
// the base's box at the origin, the arm's box beyond x = -0.25, the fingers beyond x = 0.22
// at y = +-0.08, the sensor's sphere above the base's centre).
struct Target {
  double x, y;
  const char* link;
};
const Target kTargets[] = {{0.1, 0.1, "base"},
                           {-0.45, 0.0, "arm"},
                           {0.3, 0.08, "finger_left"},
                           {0.3, -0.08, "finger_right"},
                           {0.0, 0.0, "sensor"}};

TEST(Sleep, TheRobotFallsAsleepOnTheGround) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (!shared->diagnostics->robotAsleep() && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(shared->diagnostics->robotAsleep())
      << "awake: " << shared->diagnostics->value("bodies awake")
      << ", asleep: " << shared->diagnostics->value("bodies asleep");
  // Sleep on through one more report: the queries below meet a robot that has been asleep.
  ASSERT_TRUE(shared->diagnostics->waitForNextReport(10.0));
  EXPECT_TRUE(shared->diagnostics->robotAsleep());
  EXPECT_GT(shared->diagnostics->value("contact points"), 0);
}

TEST(Sleep, GetContactsListsTheSleepingRobotsContactsNamedAfterTheirLinks) {
  ASSERT_TRUE(shared->diagnostics->robotAsleep());
  pfx::GetContacts all;
  all = call(kNode + "get_contacts", all);
  ASSERT_TRUE(all.response.success) << all.response.message;
  ASSERT_FALSE(all.response.contacts.empty()) << "a sleeping robot's contacts are contacts";
  EXPECT_LE(all.response.contacts.size(), shared->diagnostics->value("contact points"));
  EXPECT_EQ(all.response.contacts.size(),
            shared->diagnostics->value("contact points touching or pushing (get_contacts)"));
  std::set<std::string> onGround;
  for (const pfx::Contact& c : all.response.contacts) {
    ASSERT_TRUE(c.link_a == "ground" || c.link_b == "ground") << c.link_a << " " << c.link_b;
    const std::string link = c.link_a == "ground" ? c.link_b : c.link_a;
    EXPECT_TRUE(pfx_test::hasLink(shared->robot, link)) << link;
    onGround.insert(link);
  }
  // Named after the links whose boxes lie on the ground, never after the massless helper.
  EXPECT_EQ(onGround, (std::set<std::string>{"base", "arm", "finger_left", "finger_right"}));

  pfx::GetContacts arm;
  arm.request.link = "arm";
  arm = call(kNode + "get_contacts", arm);
  ASSERT_TRUE(arm.response.success) << arm.response.message;
  ASSERT_FALSE(arm.response.contacts.empty());
  for (const pfx::Contact& c : arm.response.contacts) {
    EXPECT_EQ(c.link_a, "arm");
    EXPECT_EQ(c.link_b, "ground");
    EXPECT_LT(c.normal.z, -0.5) << "normal from the arm into the ground";
    EXPECT_LT(c.position.x, -0.2) << "an arm contact under the base";
  }
  // Links without geometry of their own, or not touching anything, have no contacts.
  for (const char* link : {"link1_14", "sensor"}) {
    pfx::GetContacts none;
    none.request.link = link;
    none = call(kNode + "get_contacts", none);
    ASSERT_TRUE(none.response.success) << none.response.message;
    EXPECT_TRUE(none.response.contacts.empty()) << link;
  }
}

TEST(Sleep, RaysHitTheSleepingRobotAndNameTheLinkHit) {
  ASSERT_TRUE(shared->diagnostics->robotAsleep());
  pfx::RaycastBatch batch;
  for (const Target& target : kTargets) {
    EXPECT_EQ(linkBelow(target.x, target.y), target.link) << target.x << ", " << target.y;
    geometry_msgs::Point origin;
    origin.x = target.x;
    origin.y = target.y;
    origin.z = 1.0;
    geometry_msgs::Vector3 direction;
    direction.z = -2.0;
    batch.request.origins.push_back(origin);
    batch.request.directions.push_back(direction);
  }
  batch = call(kNode + "raycast_batch", batch);
  ASSERT_TRUE(batch.response.success) << batch.response.message;
  ASSERT_EQ(batch.response.links.size(), std::size(kTargets));
  for (std::size_t i = 0; i < std::size(kTargets); ++i) {
    EXPECT_EQ(batch.response.links[i], kTargets[i].link);
  }
  // Neither rays nor contact queries woke it.
  ASSERT_TRUE(shared->diagnostics->waitForNextReport(10.0));
  EXPECT_TRUE(shared->diagnostics->robotAsleep());
}

TEST(Sleep, TheMarkersDrawTheSleepingContacts) {
  ASSERT_TRUE(shared->diagnostics->robotAsleep());
  std::mutex mutex;
  std::size_t contactPoints = 0;
  bool received = false;
  ros::Subscriber sub = shared->ros->nh.subscribe<visualization_msgs::MarkerArray>(
      kNode + "markers", 1, [&](const visualization_msgs::MarkerArray::ConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const visualization_msgs::Marker& marker : msg->markers) {
          if (marker.ns == "contacts" && marker.type == visualization_msgs::Marker::POINTS) {
            contactPoints = marker.points.size();
            received = true;
          }
        }
      });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (received || ros::WallTime::now() > deadline) break;
    }
    ros::WallDuration(0.02).sleep();
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_TRUE(received) << "no contact markers";
  // Both ends of every contact point.
  EXPECT_EQ(contactPoints, 2 * shared->diagnostics->value("contact points"));
}

TEST(JointStates, EveryJointWithACoordinateInEveryMessageInFileOrder) {
  const std::vector<std::string> expected = jointsWithACoordinateInFileOrder();
  ASSERT_EQ(expected, (std::vector<std::string>{"arm_joint", "finger_joint", "finger_mimic_joint",
                                                "sensor_pan"}))
      << "tests/ros/data/sleeper.urdf changed";
  ASSERT_GT(shared->joints->messages(), 10);
  EXPECT_EQ(shared->joints->firstNames(), expected);
  EXPECT_EQ(shared->joints->messagesWithOtherNames(), 0);
  EXPECT_EQ(shared->joints->messagesWithMissingValues(), 0);
  // The sensor's joint is held at zero (its link has no mass and no child).
  EXPECT_EQ(shared->joints->positions().at("sensor_pan"), 0.0);
}

TEST(JointStates, AGripperDrivenPastItsLimitStopsThereAndItsMimicFollows) {
  pfx::SetJointCommand command;
  command.request.mode = pfx::SetJointCommand::Request::POSITION;
  command.request.names = {"finger_joint"};
  command.request.targets = {0.8};  // upper limit 0.5; no max_forces: the URDF effort, 5 N m
  command = call(kNode + "set_joint_command", command);
  ASSERT_TRUE(command.response.success) << command.response.message;
  EXPECT_NE(command.response.message.find("finger_joint"), std::string::npos)
      << command.response.message;
  EXPECT_NE(command.response.message.find("0.5"), std::string::npos) << command.response.message;

  const auto reached = [] {
    const std::map<std::string, double> q = shared->joints->positions();
    return std::abs(q.at("finger_joint") - 0.5) < 0.02 &&
           std::abs(q.at("finger_mimic_joint") + 0.5) < 0.02;
  };
  double worstExcursion = 0;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!reached() && ros::WallTime::now() < deadline) {
    const std::map<std::string, double> q = shared->joints->positions();
    worstExcursion =
        std::max({worstExcursion, q.at("finger_joint") - 0.5, -0.5 - q.at("finger_mimic_joint")});
    ros::WallDuration(0.01).sleep();
  }
  const std::map<std::string, double> q = shared->joints->positions();
  EXPECT_NEAR(q.at("finger_joint"), 0.5, 0.02);
  EXPECT_NEAR(q.at("finger_mimic_joint"), -0.5, 0.02);
  EXPECT_LT(worstExcursion, 0.02) << "past the limit on the way";
  EXPECT_EQ(q.at("sensor_pan"), 0.0);
  EXPECT_EQ(shared->joints->messagesWithOtherNames(), 0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_sleep_and_names");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.diagnostics = std::make_unique<DiagnosticsWatcher>(state.ros->nh);
  state.joints = std::make_unique<JointStateWatcher>(state.ros->nh);
  shared = &state;
  if (!pfx_test::waitForServices({kNode + "raycast", kNode + "get_contacts"}, 30.0)) {
    ROS_FATAL("the pfx_node services did not appear");
    return 1;
  }
  if (!ros::param::get("/robot_description", state.urdfText) ||
      !pfx_test::readRobot("/robot_description", state.robot)) {
    ROS_FATAL("robot_description is missing or not a URDF");
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
