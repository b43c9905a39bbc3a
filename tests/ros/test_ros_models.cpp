// rostest (models.test): robots added to a running node with ~spawn_model beside the robot
// of robot_description (a crate), the node paused and stepped with ~step. Two copies of
// tests/ros/data/scout.urdf (alpha in /alpha with frames alpha/..., beta in /team/beta with
// frames beta/...) and the KUKA iiwa of ../shared/realworld each get their frames at their
// spawn poses, their own joint_states, command topics and sensors, which act on their robot
// only; ~link_states lists every link of every model with TF's poses; every bad request is
// refused with its reason and nothing changed; the services reach every model's links and
// joints by frame or model-qualified name (alpha::pan, box/crate); deleting alpha leaves beta
// as it was, ~reset builds the live models again at their spawn poses, and the robot of
// robot_description is deleted and spawned again under its name like any model.
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Trigger.h>

#include <limits>
#include <set>

#include "pfx/ApplyBodyWrench.h"
#include "pfx/DeleteModel.h"
#include "pfx/GetContacts.h"
#include "pfx/LinkStates.h"
#include "pfx/SetBodyState.h"
#include "pfx/SetJointCommand.h"
#include "pfx/SpawnModel.h"
#include "pfx/Step.h"
#include "pfx/WorldFile.h"
#include "pfx_ros_body_count.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
const double kDt = 0.004;
const double kGravity = 9.80665;
// Where the robots stand (their root links, fixed to the world): alpha faces the crate at
// the origin from +x, beta from -x, the iiwa stands aside.
const double kAlphaX = 2.5;
const double kBetaX = -2.0;
const double kIiwaY = 3.0;
const double kLaserForward = 0.22;  // scout.urdf: the laser's mount ahead of the base
const double kLaserHeight = 0.1;

// One scout's topics.
struct Scout {
  Scout(ros::NodeHandle& nh, const std::string& ns)
      : joints(nh, ns + "/joint_states"),
        scan(nh, ns + "/scan"),
        imu(nh, ns + "/imu"),
        pan(nh.advertise<std_msgs::Float64>(ns + "/pan/command", 1, true)) {}
  bool connected() const {
    return joints.connected() && scan.connected() && imu.connected() &&
           pan.getNumSubscribers() > 0;
  }
  pfx_test::Latest<sensor_msgs::JointState> joints;
  pfx_test::Latest<sensor_msgs::LaserScan> scan;
  pfx_test::Latest<sensor_msgs::Imu> imu;
  ros::Publisher pan;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::Latest<pfx::LinkStates>> linkStates;
  std::unique_ptr<pfx_test::BodyCount> bodies;
  std::unique_ptr<Scout> alpha, beta;
  std::unique_ptr<pfx_test::Latest<sensor_msgs::JointState>> iiwaJoints;
  double time = 0;  // simulated time after the last ~step
};
Shared* shared = nullptr;

double step(int steps) {
  pfx::Step srv;
  srv.request.steps = steps;
  const pfx::Step::Response res = call(kNode + "step", srv).response;
  EXPECT_TRUE(res.success) << res.message;
  shared->time = res.time;
  return res.time;
}

// Steps to the next step at which the scouts' lasers (10 Hz: every 25th step, counted from
// their spawn at time 0) and IMUs (every 5th) publish.
double stepToSensorUpdate() {
  const long count = std::lround(shared->time / kDt);
  return step(int(25 - count % 25));
}

geometry_msgs::Quaternion yawQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  return q;
}

pfx::SpawnModel::Request spawnRequest(const std::string& name, double x, double y, double yaw) {
  pfx::SpawnModel::Request req;
  req.name = name;
  req.pose.position.x = x;
  req.pose.position.y = y;
  req.pose.orientation = yawQuaternion(yaw);
  req.fixed_base = true;
  return req;
}

pfx::SpawnModel::Response spawn(const pfx::SpawnModel::Request& req) {
  pfx::SpawnModel srv;
  srv.request = req;
  return call(kNode + "spawn_model", srv).response;
}

pfx::DeleteModel::Response remove(const std::string& name) {
  pfx::DeleteModel srv;
  srv.request.name = name;
  return call(kNode + "delete_model", srv).response;
}

std::string scoutPath() { return std::string(PFX_SOURCE_DIR) + "/tests/ros/data/scout.urdf"; }
std::string cratePath() { return std::string(PFX_SOURCE_DIR) + "/tests/ros/data/crate.urdf"; }

// The public copy beside the checkout when there is one, else the repository's own copy
// (the same file).
std::string iiwaPath() {
  const std::string realworld = std::string(PFX_SOURCE_DIR) + "/../shared/realworld/kuka_iiwa/model.urdf";
  return std::ifstream(realworld).good() ? realworld
                                         : std::string(PFX_SOURCE_DIR) + "/urdf/kuka_iiwa/model.urdf";
}

// The transform of `frame` in the world as TF has it at `time`, waiting for it.
bool frameAt(const std::string& frame, double time, geometry_msgs::TransformStamped& out) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5);
  for (;;) {
    if (pfx_test::lookup(shared->ros->tfBuffer, "world", frame, out, 1) &&
        std::abs(out.header.stamp.toSec() - time) < 1e-9) {
      return true;
    }
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.01).sleep();
  }
}

double jointPosition(const sensor_msgs::JointState& state, const std::string& joint) {
  for (std::size_t i = 0; i < state.name.size(); ++i) {
    if (state.name[i] == joint) return state.position[i];
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Commands a scout's pan joint and steps until it is within 0.01 rad of the target (at most
// 2 s of simulated time); returns the position reached.
double drivePan(Scout& scout, double target) {
  std_msgs::Float64 command;
  command.data = target;
  scout.pan.publish(command);
  // The command travels to the node while it waits paused; each round steps 0.2 s.
  double position = std::numeric_limits<double>::quiet_NaN();
  for (int round = 0; round < 10; ++round) {
    ros::WallDuration(0.05).sleep();
    const double time = step(50);
    sensor_msgs::JointState state;
    EXPECT_TRUE(scout.joints.waitFor(time, state));
    position = jointPosition(state, "pan");
    if (std::abs(position - target) < 0.01) break;
  }
  return position;
}

std::set<std::string> linkStateNames(double time) {
  pfx::LinkStates states;
  EXPECT_TRUE(shared->linkStates->waitFor(time, states));
  return std::set<std::string>(states.name.begin(), states.name.end());
}

std::set<std::string> advertisedTopics() {
  ros::master::V_TopicInfo topics;
  ros::master::getTopics(topics);
  std::set<std::string> names;
  for (const ros::master::TopicInfo& topic : topics) names.insert(topic.name);
  return names;
}

TEST(Models, SpawnedRobotsStandWhereAskedUnderTheirPrefixes) {
  pfx::SpawnModel::Request alpha = spawnRequest("alpha", kAlphaX, 0, M_PI);
  alpha.param_name = "/scout_description";
  const pfx::SpawnModel::Response a = spawn(alpha);
  ASSERT_TRUE(a.success) << a.message;

  pfx::SpawnModel::Request beta = spawnRequest("beta", kBetaX, 0, 0);
  beta.urdf = pfx_test::readText(scoutPath());
  beta.robot_namespace = "team/beta";
  const pfx::SpawnModel::Response b = spawn(beta);
  ASSERT_TRUE(b.success) << b.message;

  pfx::SpawnModel::Request iiwa = spawnRequest("iiwa", 0, kIiwaY, M_PI / 2);
  iiwa.urdf_path = iiwaPath();
  const pfx::SpawnModel::Response c = spawn(iiwa);
  ASSERT_TRUE(c.success) << c.message;

  // The node publishes nothing while paused: connect before the first step.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10);
  while (!(shared->alpha->connected() && shared->beta->connected() &&
           shared->iiwaJoints->connected())) {
    ASSERT_LT(ros::WallTime::now(), deadline) << "the models' topics did not connect";
    ros::WallDuration(0.02).sleep();
  }
  const double time = step(25);

  geometry_msgs::TransformStamped frame;
  ASSERT_TRUE(frameAt("alpha/base_link", time, frame));
  EXPECT_NEAR(frame.transform.translation.x, kAlphaX, 1e-5);
  EXPECT_NEAR(frame.transform.translation.y, 0, 1e-5);
  EXPECT_NEAR(std::abs(frame.transform.rotation.z), 1, 1e-5);  // turned half round
  ASSERT_TRUE(frameAt("alpha/laser_link", time, frame));
  EXPECT_NEAR(frame.transform.translation.x, kAlphaX - kLaserForward, 1e-5);
  EXPECT_NEAR(frame.transform.translation.z, kLaserHeight, 1e-5);
  ASSERT_TRUE(frameAt("beta/laser_link", time, frame));
  EXPECT_NEAR(frame.transform.translation.x, kBetaX + kLaserForward, 1e-5);
  EXPECT_NEAR(frame.transform.translation.z, kLaserHeight, 1e-5);
  ASSERT_TRUE(frameAt("iiwa/lbr_iiwa_link_0", time, frame));
  EXPECT_NEAR(frame.transform.translation.y, kIiwaY, 1e-5);
  EXPECT_NEAR(frame.transform.rotation.z, std::sin(M_PI / 4), 1e-5);
  // The robot of robot_description keeps its names, without a prefix.
  EXPECT_TRUE(frameAt("crate", time, frame));

  sensor_msgs::JointState joints;
  ASSERT_TRUE(shared->alpha->joints.waitFor(time, joints));
  EXPECT_EQ(joints.name, std::vector<std::string>{"pan"});
  ASSERT_TRUE(shared->beta->joints.waitFor(time, joints));
  EXPECT_EQ(joints.name, std::vector<std::string>{"pan"});
  ASSERT_TRUE(shared->iiwaJoints->waitFor(time, joints));
  ASSERT_EQ(joints.name.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(joints.name[i], "lbr_iiwa_joint_" + std::to_string(i + 1));
  }
}

TEST(Models, EachRobotsCommandsMoveOnlyThatRobot) {
  EXPECT_NEAR(drivePan(*shared->alpha, 0.5), 0.5, 0.01);
  sensor_msgs::JointState beta;
  ASSERT_TRUE(shared->beta->joints.waitFor(shared->time, beta));
  EXPECT_NEAR(jointPosition(beta, "pan"), 0, 1e-3) << "alpha's command moved beta";

  EXPECT_NEAR(drivePan(*shared->beta, -0.4), -0.4, 0.01);
  sensor_msgs::JointState alpha;
  ASSERT_TRUE(shared->alpha->joints.waitFor(shared->time, alpha));
  EXPECT_NEAR(jointPosition(alpha, "pan"), 0.5, 0.01) << "beta's command moved alpha";
}

// A scout's scan in its own frame, its centre beam the ray that ~raycast casts from its
// laser straight ahead, and its IMU at rest in its own frame.
void expectOwnSensors(Scout& scout, const std::string& prefix, double laserX, double ahead,
                      double time) {
  sensor_msgs::LaserScan scan;
  ASSERT_TRUE(scout.scan.waitFor(time, scan)) << prefix;
  EXPECT_EQ(scan.header.frame_id, prefix + "/laser_link");
  ASSERT_EQ(scan.ranges.size(), 31u);
  const pfx::Raycast::Response ray =
      pfx_test::raycast(kNode + "raycast", laserX, 0, kLaserHeight, 8 * ahead, 0, 0);
  ASSERT_TRUE(ray.success) << ray.message;
  ASSERT_TRUE(ray.hit) << prefix;
  EXPECT_EQ(ray.link, "crate");
  EXPECT_NEAR(scan.ranges[15], ray.distance, 1e-4) << prefix;

  sensor_msgs::Imu imu;
  ASSERT_TRUE(scout.imu.waitFor(time, imu)) << prefix;
  EXPECT_EQ(imu.header.frame_id, prefix + "/base_link");
  EXPECT_NEAR(imu.linear_acceleration.z, kGravity, 1e-3) << prefix;
  EXPECT_NEAR(imu.angular_velocity.z, 0, 1e-6) << prefix;
}

TEST(Models, EachRobotsSensorsSeeFromThatRobot) {
  const double time = stepToSensorUpdate();
  expectOwnSensors(*shared->alpha, "alpha", kAlphaX - kLaserForward, -1, time);
  expectOwnSensors(*shared->beta, "beta", kBetaX + kLaserForward, 1, time);
  // The two lasers stand at different distances from the crate: 1.78 and 1.28 m.
  sensor_msgs::LaserScan a, b;
  ASSERT_TRUE(shared->alpha->scan.waitFor(time, a));
  ASSERT_TRUE(shared->beta->scan.waitFor(time, b));
  EXPECT_GT(std::abs(a.ranges[15] - b.ranges[15]), 0.4);
}

TEST(Models, LinkStatesListEveryLinkOfEveryModelAsTfHasIt) {
  const double time = step(1);
  pfx::LinkStates states;
  ASSERT_TRUE(shared->linkStates->waitFor(time, states));
  EXPECT_EQ(states.header.frame_id, "world");
  std::set<std::string> expected = {"crate::crate"};
  for (const std::string scout : {"alpha", "beta"}) {
    for (const std::string link : {"base_link", "head", "laser_link"}) {
      expected.insert(scout + "::" + link);
    }
  }
  for (int i = 0; i <= 7; ++i) expected.insert("iiwa::lbr_iiwa_link_" + std::to_string(i));
  EXPECT_EQ(std::set<std::string>(states.name.begin(), states.name.end()), expected);
  ASSERT_EQ(states.pose.size(), states.name.size());
  ASSERT_EQ(states.twist.size(), states.name.size());
  for (std::size_t i = 0; i < states.name.size(); ++i) {
    const std::string& name = states.name[i];
    const std::size_t colons = name.find("::");
    const std::string model = name.substr(0, colons);
    const std::string link = name.substr(colons + 2);
    const std::string frameName = model == "crate" ? link : model + "/" + link;
    geometry_msgs::TransformStamped frame;
    ASSERT_TRUE(frameAt(frameName, time, frame)) << frameName;
    const geometry_msgs::Pose& pose = states.pose[i];
    EXPECT_NEAR(pose.position.x, frame.transform.translation.x, 1e-6) << name;
    EXPECT_NEAR(pose.position.y, frame.transform.translation.y, 1e-6) << name;
    EXPECT_NEAR(pose.position.z, frame.transform.translation.z, 1e-6) << name;
    // q and -q are one rotation.
    const double dot = pose.orientation.x * frame.transform.rotation.x +
                       pose.orientation.y * frame.transform.rotation.y +
                       pose.orientation.z * frame.transform.rotation.z +
                       pose.orientation.w * frame.transform.rotation.w;
    EXPECT_NEAR(std::abs(dot), 1, 1e-6) << name;
    if (link == "base_link") {  // bolted to the world
      EXPECT_EQ(states.twist[i].linear.x, 0) << name;
      EXPECT_EQ(states.twist[i].angular.z, 0) << name;
    }
  }
}

pfx::SetJointCommand::Response commandJoints(const std::vector<std::string>& names,
                                             double target) {
  pfx::SetJointCommand srv;
  srv.request.names = names;
  srv.request.mode = pfx::SetJointCommand::Request::POSITION;
  srv.request.targets.assign(names.size(), target);
  return call(kNode + "set_joint_command", srv).response;
}

// Both scouts' pan joints after `steps` steps.
std::pair<double, double> pansAfter(int steps) {
  const double time = step(steps);
  sensor_msgs::JointState alpha, beta;
  EXPECT_TRUE(shared->alpha->joints.waitFor(time, alpha));
  EXPECT_TRUE(shared->beta->joints.waitFor(time, beta));
  return {jointPosition(alpha, "pan"), jointPosition(beta, "pan")};
}

pfx::SetBodyState::Response setBodyState(const std::string& link, double x, double y, double z) {
  pfx::SetBodyState srv;
  srv.request.link = link;
  srv.request.pose.position.x = x;
  srv.request.pose.position.y = y;
  srv.request.pose.position.z = z;
  srv.request.pose.orientation.w = 1;
  return call(kNode + "set_body_state", srv).response;
}

pfx::ApplyBodyWrench::Response pushAlongX(const std::string& link, double force) {
  pfx::ApplyBodyWrench srv;
  srv.request.link = link;
  srv.request.force.x = force;
  srv.request.duration = 0.1;
  return call(kNode + "apply_body_wrench", srv).response;
}

pfx::GetContacts::Response contactsOf(const std::string& link) {
  pfx::GetContacts srv;
  srv.request.link = link;
  return call(kNode + "get_contacts", srv).response;
}

void expectRefused(bool success, const std::string& message, const std::string& reason) {
  EXPECT_FALSE(success) << reason;
  EXPECT_NE(message.find(reason), std::string::npos)
      << "'" << message << "' does not say '" << reason << "'";
}

TEST(Models, JointServicesReachEveryModelByItsQualifiedName) {
  // Alpha's pan stands at 0.5 and beta's at -0.4 (EachRobotsCommandsMoveOnlyThatRobot).
  pfx::SetJointCommand::Response res = commandJoints({"beta::pan"}, 0.2);
  ASSERT_TRUE(res.success) << res.message;
  auto [alpha, beta] = pansAfter(250);
  EXPECT_NEAR(beta, 0.2, 0.01);
  EXPECT_NEAR(alpha, 0.5, 0.01) << "beta's command moved alpha";
  res = commandJoints({"beta/pan"}, -0.4);
  ASSERT_TRUE(res.success) << res.message;
  std::tie(alpha, beta) = pansAfter(250);
  EXPECT_NEAR(beta, -0.4, 0.01);
  EXPECT_NEAR(alpha, 0.5, 0.01);

  res = commandJoints({"alpha::pan", "beta::pan"}, 0);
  expectRefused(res.success, res.message, "command one model per request");
  res = commandJoints({"ghost::pan"}, 0);
  expectRefused(res.success, res.message, "no model is named 'ghost'");
  res = commandJoints({"alpha::tilt"}, 0);
  expectRefused(res.success, res.message, "model 'alpha' has no joint 'tilt'");
  res = commandJoints({"pan"}, 0);  // the crate, robot_description, has no joints
  expectRefused(res.success, res.message, "unknown joint 'pan'");
  res = commandJoints({"beta::pan"}, std::numeric_limits<double>::quiet_NaN());
  expectRefused(res.success, res.message, "target of joint 'beta::pan' is not finite");
  std::tie(alpha, beta) = pansAfter(50);
  EXPECT_NEAR(beta, -0.4, 1e-3) << "a refused command moved beta";
  EXPECT_NEAR(alpha, 0.5, 0.01) << "a refused command moved alpha";
}

TEST(Models, LinkServicesReachEveryModelByFrameOrQualifiedName) {
  // A loose crate, model "box", given beta's prefix: "beta/crate" is its link's frame, which
  // comes before the qualified names, so that "beta::crate" names no link.
  pfx::SpawnModel::Request box = spawnRequest("box", 0, -3, 0);
  box.fixed_base = false;
  box.pose.position.z = 0.26;
  box.urdf = pfx_test::readText(cratePath());
  box.tf_prefix = "beta";
  const pfx::SpawnModel::Response spawned = spawn(box);
  ASSERT_TRUE(spawned.success) << spawned.message;

  pfx::SetBodyState::Response lifted = setBodyState("box::crate", 0, -3, 1);
  ASSERT_TRUE(lifted.success) << lifted.message;
  double time = step(1);
  geometry_msgs::TransformStamped frame;
  ASSERT_TRUE(frameAt("beta/crate", time, frame));
  EXPECT_GT(frame.transform.translation.z, 0.9);
  EXPECT_LE(frame.transform.translation.z, 1.0);

  time = step(250);  // fallen and at rest on the ground
  const pfx::GetContacts::Response byModel = contactsOf("box/crate");
  ASSERT_TRUE(byModel.success) << byModel.message;
  ASSERT_FALSE(byModel.contacts.empty());
  for (const pfx::Contact& contact : byModel.contacts) {
    EXPECT_EQ(contact.link_a, "beta/crate");
    EXPECT_EQ(contact.link_b, "ground");
  }
  EXPECT_EQ(contactsOf("beta/crate").contacts.size(), byModel.contacts.size());

  ASSERT_TRUE(frameAt("beta/crate", time, frame));
  const double restX = frame.transform.translation.x;
  const pfx::ApplyBodyWrench::Response pushed = pushAlongX("beta/crate", 600);
  ASSERT_TRUE(pushed.success) << pushed.message;
  time = step(250);
  ASSERT_TRUE(frameAt("beta/crate", time, frame));
  EXPECT_GT(frame.transform.translation.x - restX, 0.01) << "the push did not move the box";

  const geometry_msgs::TransformStamped before = frame;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  pfx::ApplyBodyWrench::Response wrench = pushAlongX("beta::crate", 600);
  expectRefused(wrench.success, wrench.message, "model 'beta' has no link 'crate'");
  wrench = pushAlongX("ghost/crate", 600);
  expectRefused(wrench.success, wrench.message, "no model is named 'ghost'");
  wrench = pushAlongX("box::crate", nan);
  expectRefused(wrench.success, wrench.message, "force is not finite");
  pfx::SetBodyState::Response state = setBodyState("box::crate", nan, -3, 1);
  expectRefused(state.success, state.message, "position is not finite");
  state = setBodyState("box::lid", 0, -3, 1);
  expectRefused(state.success, state.message, "model 'box' has no link 'lid'");
  const pfx::GetContacts::Response contacts = contactsOf("ghost::crate");
  expectRefused(contacts.success, contacts.message, "no model is named 'ghost'");
  time = step(25);
  ASSERT_TRUE(frameAt("beta/crate", time, frame));
  EXPECT_NEAR(frame.transform.translation.x, before.transform.translation.x, 1e-4);
  EXPECT_NEAR(frame.transform.translation.z, before.transform.translation.z, 1e-4);

  const pfx::DeleteModel::Response deleted = remove("box");
  EXPECT_TRUE(deleted.success) << deleted.message;
}

struct BadRequest {
  const char* what;
  pfx::SpawnModel::Request request;
  const char* reason;  // a part of the message
};

TEST(Models, BadRequestsAreRefusedWithTheirReasonAndChangeNothing) {
  const double before = step(1);
  const std::set<std::string> names = linkStateNames(before);
  const std::set<std::string> topics = advertisedTopics();
  const double bodies = shared->bodies->next();
  ASSERT_GT(bodies, 0);

  const std::string scout = pfx_test::readText(scoutPath());
  std::vector<BadRequest> bad;
  auto add = [&](const char* what, const char* reason, auto edit) {
    BadRequest entry{what, spawnRequest("gamma", 0, -3, 0), reason};
    entry.request.urdf = scout;
    edit(entry.request);
    bad.push_back(entry);
  };
  add("a name taken by a model", "a model named 'alpha' is in the world already",
      [](auto& r) { r.name = "alpha"; });
  add("the name of the robot of robot_description", "a model named 'crate'",
      [](auto& r) { r.name = "crate"; });
  add("a name that is no ROS name", "is not letters, digits and _",
      [](auto& r) { r.name = "2scout"; });
  add("an empty name", "is not letters, digits and _", [](auto& r) { r.name = ""; });
  add("malformed URDF text", "malformed XML",
      [](auto& r) { r.urdf = "<robot name='gamma'><link name='a'>"; });
  add("a URDF without links", "robot: no links", [](auto& r) { r.urdf = "<robot name='gamma'/>"; });
  add("a missing parameter", "no parameter '/no_such_description' is set", [](auto& r) {
    r.urdf.clear();
    r.param_name = "/no_such_description";
  });
  add("a parameter that is no string", "does not hold a string", [](auto& r) {
    r.urdf.clear();
    r.param_name = "/pfx_node/diagnostics_rate";
  });
  add("both text and parameter", "not both", [](auto& r) { r.param_name = "/scout_description"; });
  add("no URDF at all", "no URDF given", [](auto& r) { r.urdf.clear(); });
  add("a file that does not exist", "cannot open", [](auto& r) {
    r.urdf.clear();
    r.urdf_path = "/no/such/robot.urdf";
  });
  add("a NaN position", "the position must be finite",
      [](auto& r) { r.pose.position.y = std::numeric_limits<double>::quiet_NaN(); });
  add("a position far outside the world", "within 1000 m", [](auto& r) { r.pose.position.x = 5000; });
  add("a quaternion of length 0.5", "not a unit quaternion",
      [](auto& r) { r.pose.orientation.w = 0.5; });
  add("a zero quaternion", "not a unit quaternion", [](auto& r) { r.pose.orientation.w = 0; });
  add("a NaN quaternion", "not a unit quaternion",
      [](auto& r) { r.pose.orientation.x = std::numeric_limits<double>::quiet_NaN(); });
  add("a namespace with a space", "is not a ROS namespace",
      [](auto& r) { r.robot_namespace = "team gamma"; });
  add("a private namespace", "is not a ROS namespace", [](auto& r) { r.robot_namespace = "~gamma"; });
  add("another model's namespace", "is model 'alpha''s already",
      [](auto& r) { r.robot_namespace = "/alpha"; });
  add("the node's namespace", "the namespace of the robot of robot_description or of the node",
      [](auto& r) { r.robot_namespace = "/pfx_node"; });
  add("a bad TF prefix", "tf_prefix", [](auto& r) { r.tf_prefix = "gamma//x"; });
  // Loaded, then found to clash with beta's frames, and taken out again.
  add("another model's TF prefix", "'beta/base_link' names a link",
      [](auto& r) { r.tf_prefix = "beta"; });
  for (const BadRequest& entry : bad) {
    const pfx::SpawnModel::Response res = spawn(entry.request);
    EXPECT_FALSE(res.success) << entry.what;
    EXPECT_NE(res.message.find(entry.reason), std::string::npos)
        << entry.what << ": '" << res.message << "' does not say '" << entry.reason << "'";
  }
  const std::pair<const char*, const char*> badDeletes[] = {
      {"nobody", "no model named 'nobody'"}, {"", "no name given"}};
  for (const auto& [name, reason] : badDeletes) {
    const pfx::DeleteModel::Response res = remove(name);
    EXPECT_FALSE(res.success) << name;
    EXPECT_NE(res.message.find(reason), std::string::npos) << res.message;
  }
  pfx::WorldFile load;
  load.request.path = "/tmp/pfx_models_test_world.pfxw";
  const pfx::WorldFile::Response loaded = call(kNode + "load_world", load).response;
  EXPECT_FALSE(loaded.success);
  EXPECT_NE(loaded.message.find("delete the models first"), std::string::npos) << loaded.message;

  const double after = step(1);
  EXPECT_EQ(linkStateNames(after), names);
  EXPECT_EQ(advertisedTopics(), topics);
  EXPECT_EQ(shared->bodies->next(), bodies);
}

TEST(Models, DeletingOneRobotLeavesTheOtherAsItWas) {
  const double before = step(1);
  pfx::LinkStates statesBefore;
  ASSERT_TRUE(shared->linkStates->waitFor(before, statesBefore));
  const double bodies = shared->bodies->next();
  // Straight down onto alpha's base behind its head: its box, until it is deleted.
  const pfx::Raycast::Response onAlpha =
      pfx_test::raycast(kNode + "raycast", kAlphaX + 0.15, 0, 1, 0, 0, -2);
  ASSERT_TRUE(onAlpha.hit);
  EXPECT_EQ(onAlpha.link, "alpha/base_link");

  const pfx::DeleteModel::Response res = remove("alpha");
  ASSERT_TRUE(res.success) << res.message;
  const double time = stepToSensorUpdate();

  const pfx::Raycast::Response through =
      pfx_test::raycast(kNode + "raycast", kAlphaX + 0.15, 0, 1, 0, 0, -2);
  ASSERT_TRUE(through.hit);
  EXPECT_EQ(through.link, "ground");
  EXPECT_NEAR(through.point.z, 0, 1e-4);
  EXPECT_EQ(shared->bodies->next(), bodies - 2);  // scout.urdf: base (with its laser) and head
  const std::set<std::string> topics = advertisedTopics();
  EXPECT_EQ(topics.count("/alpha/joint_states"), 0u);
  EXPECT_EQ(topics.count("/alpha/scan"), 0u);
  EXPECT_EQ(topics.count("/team/beta/joint_states"), 1u);

  pfx::LinkStates statesAfter;
  ASSERT_TRUE(shared->linkStates->waitFor(time, statesAfter));
  std::map<std::string, geometry_msgs::Pose> after;
  for (std::size_t i = 0; i < statesAfter.name.size(); ++i) {
    EXPECT_NE(statesAfter.name[i].rfind("alpha::", 0), 0u) << statesAfter.name[i];
    after[statesAfter.name[i]] = statesAfter.pose[i];
  }
  for (std::size_t i = 0; i < statesBefore.name.size(); ++i) {
    const std::string& name = statesBefore.name[i];
    if (name.rfind("beta::", 0) != 0) continue;
    ASSERT_EQ(after.count(name), 1u) << name;
    EXPECT_NEAR(after[name].position.x, statesBefore.pose[i].position.x, 1e-5) << name;
    EXPECT_NEAR(after[name].position.y, statesBefore.pose[i].position.y, 1e-5) << name;
    EXPECT_NEAR(after[name].orientation.z, statesBefore.pose[i].orientation.z, 1e-4) << name;
  }
  // Beta's sensors and commands carry on.
  expectOwnSensors(*shared->beta, "beta", kBetaX + kLaserForward, 1, time);
  EXPECT_NEAR(drivePan(*shared->beta, 0.3), 0.3, 0.01);
  // The name is free again.
  pfx::SpawnModel::Request again = spawnRequest("alpha", kAlphaX, 0, M_PI);
  again.param_name = "/scout_description";
  const pfx::SpawnModel::Response respawned = spawn(again);
  EXPECT_TRUE(respawned.success) << respawned.message;
  const pfx::DeleteModel::Response deleted = remove("alpha");
  EXPECT_TRUE(deleted.success) << deleted.message;
}

TEST(Models, ResetBuildsTheLiveModelsAgainAtTheirSpawnPoses) {
  ASSERT_TRUE(call(kNode + "reset", std_srvs::Trigger()).response.success);
  const double time = step(1);
  EXPECT_EQ(linkStateNames(time).count("beta::head"), 1u);
  EXPECT_EQ(linkStateNames(time).count("alpha::head"), 0u);
  sensor_msgs::JointState beta;
  ASSERT_TRUE(shared->beta->joints.waitFor(time, beta));
  EXPECT_NEAR(jointPosition(beta, "pan"), 0, 1e-3);
  geometry_msgs::TransformStamped frame;
  ASSERT_TRUE(frameAt("beta/base_link", time, frame));
  EXPECT_NEAR(frame.transform.translation.x, kBetaX, 1e-5);
}

TEST(Models, TheRobotOfRobotDescriptionIsDeletedAndSpawnedAgainAsAModel) {
  step(1);
  const double bodies = shared->bodies->next();
  pfx::Raycast::Response down = pfx_test::raycast(kNode + "raycast", 0, 0, 2, 0, 0, -3);
  ASSERT_TRUE(down.hit);
  EXPECT_EQ(down.link, "crate");

  const pfx::DeleteModel::Response deleted = remove("crate");
  ASSERT_TRUE(deleted.success) << deleted.message;
  double time = step(1);
  down = pfx_test::raycast(kNode + "raycast", 0, 0, 2, 0, 0, -3);
  EXPECT_EQ(down.link, "ground");
  EXPECT_EQ(shared->bodies->next(), bodies - 1);
  EXPECT_EQ(linkStateNames(time).count("crate::crate"), 0u);
  const pfx::DeleteModel::Response again = remove("crate");
  expectRefused(again.success, again.message, "no model named 'crate'");
  pfx::SetBodyState::Response state = setBodyState("crate", 0, 0, 1);
  expectRefused(state.success, state.message, "unknown link 'crate'");

  // Its name is free: spawned again, it is a model like the others, frames prefixed.
  pfx::SpawnModel::Request crate = spawnRequest("crate", 0, 0, 0);
  crate.fixed_base = false;
  crate.pose.position.z = 0.26;
  crate.urdf = pfx_test::readText(cratePath());
  const pfx::SpawnModel::Response spawned = spawn(crate);
  ASSERT_TRUE(spawned.success) << spawned.message;
  time = step(25);
  EXPECT_EQ(linkStateNames(time).count("crate::crate"), 1u);
  down = pfx_test::raycast(kNode + "raycast", 0, 0, 2, 0, 0, -3);
  EXPECT_EQ(down.link, "crate/crate");
  EXPECT_TRUE(setBodyState("crate::crate", 0, 0, 0.26).success);

  // ~reset builds the spawned crate again, not the deleted robot.
  ASSERT_TRUE(call(kNode + "reset", std_srvs::Trigger()).response.success);
  time = step(1);
  EXPECT_EQ(linkStateNames(time).count("crate::crate"), 1u);
  EXPECT_EQ(shared->bodies->next(), bodies);
  down = pfx_test::raycast(kNode + "raycast", 0, 0, 2, 0, 0, -3);
  EXPECT_EQ(down.link, "crate/crate");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_models");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  ros::NodeHandle& nh = state.ros->nh;
  state.linkStates = std::make_unique<pfx_test::Latest<pfx::LinkStates>>(nh, kNode + "link_states");
  state.bodies = std::make_unique<pfx_test::BodyCount>(nh);
  state.alpha = std::make_unique<Scout>(nh, "/alpha");
  state.beta = std::make_unique<Scout>(nh, "/team/beta");
  state.iiwaJoints = std::make_unique<pfx_test::Latest<sensor_msgs::JointState>>(nh, "/iiwa/joint_states");
  shared = &state;
  if (!pfx_test::waitForServices({kNode + "spawn_model", kNode + "delete_model", kNode + "step"},
                                 30.0)) {
    ROS_FATAL("the pfx_node services did not appear");
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  std::printf("test_ros_models: %.3f s of simulated time stepped\n", state.time);
  shared = nullptr;
  return result;
}
