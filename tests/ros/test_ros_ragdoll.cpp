// rostest (ragdoll.test): launch/ragdoll.launch as a user starts it, a real rosmaster and
// the real pfx_node, checked from outside through TF, /clock and the node's services. The
// tests run in order and share the one simulation: the fall, then queries on the ragdoll
// at rest, pause, bad requests, and moves that reset undoes.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdio>
#include <mutex>
#include <set>

#include "pfx/ApplyBodyWrench.h"
#include "pfx/GetContacts.h"
#include "pfx/Raycast.h"
#include "pfx/RaycastBatch.h"
#include "pfx/SetBodyState.h"
#include "pfx/SetJointCommand.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
const std::string kFixedFrame = "world";
// Where no part of the fallen ragdoll can be: the ground is 20 m wide around the origin.
const double kFreeX = 5.0;
const double kFreeY = -4.0;

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::ClockWatcher> clock;
  pfx_test::UrdfRobot robot;
  double initialHeight = 0;
};
Shared* shared = nullptr;

pfx::Raycast::Response raycast(double x, double y, double z, double dx, double dy, double dz) {
  return pfx_test::raycast(kNode + "raycast", x, y, z, dx, dy, dz);
}

bool trigger(const std::string& name) {
  std_srvs::Trigger srv;
  return call(kNode + name, srv).response.success;
}

std::map<std::string, geometry_msgs::TransformStamped> allLinkPoses() {
  std::map<std::string, geometry_msgs::TransformStamped> poses;
  for (const std::string& link : shared->robot.links) {
    EXPECT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, link, poses[link])) << link;
  }
  return poses;
}

geometry_msgs::TransformStamped rootPose() {
  geometry_msgs::TransformStamped pose;
  EXPECT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, shared->robot.root, pose));
  return pose;
}

bool isRagdollLink(const std::string& name) { return pfx_test::hasLink(shared->robot, name); }

TEST(Ragdoll, TfForEveryLink) {
  ASSERT_FALSE(shared->robot.links.empty());
  for (const std::string& link : shared->robot.links) {
    geometry_msgs::TransformStamped pose;
    EXPECT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, kFixedFrame, link, pose))
        << "no transform from " << kFixedFrame << " to " << link;
  }
}

TEST(Ragdoll, FallsOntoTheGroundAndTouchesIt) {
  ASSERT_TRUE(shared->clock->waitUntil(4.0, 30.0)) << "the simulation does not advance";
  // Give the TF of the last step time to arrive.
  ros::WallDuration(0.2).sleep();
  const geometry_msgs::TransformStamped root = rootPose();
  EXPECT_LT(root.transform.translation.z, shared->initialHeight - 0.5)
      << "the ragdoll did not fall";
  for (const auto& [link, pose] : allLinkPoses()) {
    EXPECT_GT(pose.transform.translation.z, -0.02) << link << " is below the ground";
    EXPECT_LT(pose.transform.translation.z, 0.8) << link << " is not down on the ground";
  }

  pfx::GetContacts all;
  all = call(kNode + "get_contacts", all);
  ASSERT_TRUE(all.response.success) << all.response.message;
  std::string onGround;
  for (const pfx::Contact& c : all.response.contacts) {
    if (c.link_a == "ground" && isRagdollLink(c.link_b)) onGround = c.link_b;
    if (c.link_b == "ground" && isRagdollLink(c.link_a)) onGround = c.link_a;
    EXPECT_GE(c.impulse, 0);
    EXPECT_NEAR(std::hypot(c.normal.x, c.normal.y, c.normal.z), 1.0, 1e-3);
  }
  ASSERT_FALSE(onGround.empty()) << "no contact between the ragdoll and the ground among "
                                 << all.response.contacts.size();

  // The contacts of one link name it first, with the normal pointing away from it: from a
  // link lying on the ground, down.
  pfx::GetContacts one;
  one.request.link = onGround;
  one = call(kNode + "get_contacts", one);
  ASSERT_TRUE(one.response.success) << one.response.message;
  ASSERT_FALSE(one.response.contacts.empty());
  bool groundSeen = false;
  for (const pfx::Contact& c : one.response.contacts) {
    EXPECT_EQ(c.link_a, onGround);
    if (c.link_b == "ground") {
      groundSeen = true;
      EXPECT_LT(c.normal.z, -0.5) << "normal from " << onGround << " into the ground";
      EXPECT_LT(std::abs(c.position.z), 0.02) << "a ground contact away from z = 0";
    }
  }
  EXPECT_TRUE(groundSeen);
}

// The first message on a topic, waiting up to `wallSeconds`.
template <typename Message>
typename Message::ConstPtr firstMessage(const std::string& topic, double wallSeconds) {
  typename Message::ConstPtr received;
  std::mutex mutex;
  ros::Subscriber sub =
      shared->ros->nh.subscribe<Message>(topic, 1, [&](const typename Message::ConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!received) received = msg;
      });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (received || ros::WallTime::now() > deadline) return received;
    }
    ros::WallDuration(0.02).sleep();
  }
}

TEST(Ragdoll, PublishesJointStatesDiagnosticsAndMarkers) {
  const auto joints = firstMessage<sensor_msgs::JointState>("/joint_states", 5.0);
  ASSERT_TRUE(joints) << "no /joint_states";
  std::set<std::string> movable;
  for (const auto& [name, joint] : shared->robot.joints) {
    if (joint->type == urdf::Joint::REVOLUTE || joint->type == urdf::Joint::CONTINUOUS ||
        joint->type == urdf::Joint::PRISMATIC) {
      movable.insert(name);
    }
  }
  EXPECT_EQ(std::set<std::string>(joints->name.begin(), joints->name.end()), movable);
  EXPECT_EQ(joints->position.size(), joints->name.size());
  EXPECT_EQ(joints->velocity.size(), joints->name.size());
  for (std::size_t i = 0; i < joints->name.size(); ++i) {
    const urdf::JointConstSharedPtr& joint = shared->robot.joints.at(joints->name[i]);
    if (joint->type != urdf::Joint::REVOLUTE) continue;
    // The loader's collapsed shoulders and hips may pass a limit at second order.
    EXPECT_GE(joints->position[i], joint->limits->lower - 0.05) << joints->name[i];
    EXPECT_LE(joints->position[i], joint->limits->upper + 0.05) << joints->name[i];
  }

  const auto diagnostics = firstMessage<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5.0);
  ASSERT_TRUE(diagnostics) << "no /diagnostics";
  ASSERT_EQ(diagnostics->status.size(), 1u);
  std::map<std::string, double> values;
  for (const auto& kv : diagnostics->status[0].values) values[kv.key] = std::stod(kv.value);
  for (const char* key :
       {"step time mean (ms)", "real-time factor", "max penetration (m)", "max joint gap (m)",
        "max energy change per step (J)", "contact points", "stage solve_constraints mean (ms)"}) {
    ASSERT_TRUE(values.count(key)) << "/diagnostics lacks '" << key << "'";
  }
  EXPECT_GT(values["step time mean (ms)"], 0);
  EXPECT_GT(values["real-time factor"], 0);
  EXPECT_GT(values["contact points"], 0) << "the ragdoll lies on the ground";
  EXPECT_LT(values["max penetration (m)"], 0.05);
  EXPECT_LT(values["max joint gap (m)"], 0.01);

  // A new subscriber gets the fixed bodies too: the ground.
  const auto markers = firstMessage<visualization_msgs::MarkerArray>("/pfx_node/markers", 5.0);
  ASSERT_TRUE(markers) << "no ~markers";
  std::map<std::string, int> triangleLists;
  for (const visualization_msgs::Marker& m : markers->markers) {
    EXPECT_EQ(m.header.frame_id, kFixedFrame);
    if (m.action != visualization_msgs::Marker::ADD) continue;
    if (m.type == visualization_msgs::Marker::TRIANGLE_LIST) {
      ++triangleLists[m.ns];
      EXPECT_FALSE(m.points.empty());
      EXPECT_EQ(m.points.size() % 3, 0u);
    }
    if (m.type == visualization_msgs::Marker::LINE_LIST) {
      EXPECT_EQ(m.points.size() % 2, 0u);
    }
  }
  // One body per ragdoll link that has mass; the massless helper links have none.
  EXPECT_EQ(triangleLists["shapes"], shared->robot.massiveLinks);
  EXPECT_EQ(triangleLists["static_shapes"], 1);
}

TEST(Ragdoll, RaycastDownHitsTheGroundAtZero) {
  const pfx::Raycast::Response hit = raycast(kFreeX, kFreeY, 2.0, 0, 0, -4.0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.link, "ground");
  EXPECT_NEAR(hit.point.x, kFreeX, 1e-4);
  EXPECT_NEAR(hit.point.y, kFreeY, 1e-4);
  EXPECT_NEAR(hit.point.z, 0.0, 1e-4);
  EXPECT_NEAR(hit.normal.z, 1.0, 1e-4);
  EXPECT_NEAR(hit.fraction, 0.5, 1e-4 / 4.0);
  EXPECT_NEAR(hit.distance, 2.0, 1e-4);

  const pfx::Raycast::Response up = raycast(kFreeX, kFreeY, 2.0, 0, 0, 4.0);
  ASSERT_TRUE(up.success) << up.message;
  EXPECT_FALSE(up.hit);
  EXPECT_EQ(up.link, "");
  EXPECT_EQ(up.fraction, 1.0);
}

TEST(Ragdoll, RaycastDownOntoTheRagdollNamesALink) {
  const geometry_msgs::TransformStamped root = rootPose();
  const double x = root.transform.translation.x;
  const double y = root.transform.translation.y;
  const pfx::Raycast::Response hit = raycast(x, y, 3.0, 0, 0, -4.0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_TRUE(isRagdollLink(hit.link)) << "hit '" << hit.link << "'";
  EXPECT_GT(hit.point.z, 0.01);
}

TEST(Ragdoll, RaycastBatchAnswersAsSingleRays) {
  ASSERT_TRUE(trigger("pause"));
  const geometry_msgs::TransformStamped root = rootPose();
  pfx::RaycastBatch batch;
  for (int i = -3; i <= 3; ++i) {
    for (int j = -3; j <= 3; ++j) {
      geometry_msgs::Point origin;
      origin.x = root.transform.translation.x + 0.15 * i;
      origin.y = root.transform.translation.y + 0.15 * j;
      origin.z = 3.0;
      geometry_msgs::Vector3 direction;
      direction.z = -5.0;
      batch.request.origins.push_back(origin);
      batch.request.directions.push_back(direction);
    }
  }
  batch = call(kNode + "raycast_batch", batch);
  ASSERT_TRUE(batch.response.success) << batch.response.message;
  const std::size_t n = batch.request.origins.size();
  ASSERT_EQ(batch.response.hit.size(), n);
  ASSERT_EQ(batch.response.links.size(), n);
  int onRagdoll = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& o = batch.request.origins[k];
    const pfx::Raycast::Response single = raycast(o.x, o.y, o.z, 0, 0, -5.0);
    ASSERT_TRUE(single.success);
    EXPECT_EQ(batch.response.hit[k], single.hit) << "ray " << k;
    EXPECT_EQ(batch.response.links[k], single.link) << "ray " << k;
    EXPECT_EQ(batch.response.fractions[k], single.fraction) << "ray " << k;
    EXPECT_EQ(batch.response.points[k].z, single.point.z) << "ray " << k;
    onRagdoll += isRagdollLink(single.link) ? 1 : 0;
  }
  EXPECT_GT(onRagdoll, 0);
  EXPECT_TRUE(trigger("unpause"));
}

TEST(Ragdoll, RaycastBatchOfTheLargestSizeIsAnswered) {
  int maxRays = 0;
  ros::param::param(kNode + "max_batch_rays", maxRays, 100000);
  // A grid of rays straight down over a 4 m square around the origin.
  pfx::RaycastBatch batch;
  const int side = int(std::ceil(std::sqrt(double(maxRays))));
  for (int k = 0; k < maxRays; ++k) {
    geometry_msgs::Point origin;
    origin.x = -2.0 + 4.0 * (k / side) / side;
    origin.y = -2.0 + 4.0 * (k % side) / side;
    origin.z = 3.0;
    geometry_msgs::Vector3 direction;
    direction.z = -4.0;
    batch.request.origins.push_back(origin);
    batch.request.directions.push_back(direction);
  }
  const ros::WallTime start = ros::WallTime::now();
  batch = call(kNode + "raycast_batch", batch);
  const double seconds = (ros::WallTime::now() - start).toSec();
  ASSERT_TRUE(batch.response.success) << batch.response.message;
  ASSERT_EQ(batch.response.hit.size(), std::size_t(maxRays));
  int onRagdoll = 0;
  for (int k = 0; k < maxRays; ++k) {
    ASSERT_TRUE(batch.response.hit[k]) << "ray " << k << " hit neither ragdoll nor ground";
    if (batch.response.links[k] == "ground") {
      ASSERT_NEAR(batch.response.points[k].z, 0.0, 1e-4) << "ray " << k;
    } else {
      ASSERT_TRUE(isRagdollLink(batch.response.links[k])) << batch.response.links[k];
      ++onRagdoll;
    }
  }
  EXPECT_GT(onRagdoll, 0);
  std::printf("%d rays in one call answered in %.3f s, %d of them on the ragdoll\n", maxRays,
              seconds, onRagdoll);
}

TEST(Ragdoll, PauseStopsTheClockAndThePoses) {
  std_srvs::Trigger pause;
  pause = call(kNode + "pause", pause);
  ASSERT_TRUE(pause.response.success) << pause.response.message;
  // Messages already on their way arrive; after that nothing may change.
  ros::WallDuration(0.3).sleep();
  const double pausedAt = shared->clock->now();
  const auto before = allLinkPoses();
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(shared->clock->now(), pausedAt) << "/clock advanced while paused";
  const auto after = allLinkPoses();
  for (const auto& [link, pose] : before) {
    EXPECT_TRUE(pfx_test::samePose(pose, after.at(link))) << link << " moved while paused";
  }

  std_srvs::Trigger unpause;
  unpause = call(kNode + "unpause", unpause);
  ASSERT_TRUE(unpause.response.success) << unpause.response.message;
  EXPECT_TRUE(shared->clock->waitUntil(pausedAt + 0.2, 5.0)) << "/clock did not resume";
}

// Each of these would fling or move the ragdoll if it were carried out.
TEST(Ragdoll, BadRequestsAreRejectedAndChangeNothing) {
  const std::string root = shared->robot.root;
  ASSERT_TRUE(trigger("pause"));
  ros::WallDuration(0.3).sleep();
  const auto before = allLinkPoses();
  const double nan = std::nan("");
  const double inf = HUGE_VAL;
  int checked = 0;
  auto expectRejected = [&checked](const auto& response, const std::string& what) {
    EXPECT_FALSE(response.success) << what << " was accepted";
    EXPECT_FALSE(response.message.empty()) << what << " gave no reason";
    ++checked;
  };

  expectRejected(raycast(nan, 0, 1, 0, 0, -1), "raycast from NaN");
  expectRejected(raycast(0, 0, 1, 0, nan, -1), "raycast along NaN");
  expectRejected(raycast(0, 0, 1, 0, 0, 0), "zero-length raycast");
  expectRejected(raycast(0, 0, 1, 0, 0, -inf), "infinite raycast");
  expectRejected(raycast(1e300, 0, 1, 0, 0, -1), "raycast from beyond float range");

  {
    pfx::RaycastBatch million;
    million.request.origins.resize(1000000);
    million.request.directions.resize(1000000);
    for (auto& d : million.request.directions) d.z = -1;
    expectRejected(call(kNode + "raycast_batch", million).response, "a million rays");
    pfx::RaycastBatch uneven;
    uneven.request.origins.resize(2);
    uneven.request.directions.resize(1);
    uneven.request.directions[0].z = -1;
    expectRejected(call(kNode + "raycast_batch", uneven).response, "2 origins, 1 direction");
    pfx::RaycastBatch oneBad;
    oneBad.request.origins.resize(3);
    oneBad.request.directions.resize(3);
    oneBad.request.directions[0].z = -1;
    oneBad.request.directions[2].z = -1;
    const auto response = call(kNode + "raycast_batch", oneBad).response;
    expectRejected(response, "a batch with a zero-length ray");
    EXPECT_NE(response.message.find("ray 1"), std::string::npos) << response.message;
  }

  {
    pfx::GetContacts srv;
    srv.request.link = "no_such_link";
    expectRejected(call(kNode + "get_contacts", srv).response, "contacts of an unknown link");
  }

  {
    auto wrench = [&](const std::string& link, double fz, double tz, double duration) {
      pfx::ApplyBodyWrench srv;
      srv.request.link = link;
      srv.request.force.z = fz;
      srv.request.torque.z = tz;
      srv.request.duration = duration;
      return call(kNode + "apply_body_wrench", srv).response;
    };
    expectRejected(wrench("no_such_link", 1e5, 0, 0.1), "wrench on an unknown link");
    expectRejected(wrench("", 1e5, 0, 0.1), "wrench on no link");
    expectRejected(wrench(root, nan, 0, 0.1), "NaN force");
    expectRejected(wrench(root, 1e5, inf, 0.1), "infinite torque");
    expectRejected(wrench(root, 1e5, 0, -0.1), "negative duration");
    expectRejected(wrench(root, 1e5, 0, nan), "NaN duration");
  }

  {
    auto state = [&](const std::string& link, double z, double qw, double qx, double vx) {
      pfx::SetBodyState srv;
      srv.request.link = link;
      srv.request.pose.position.z = z;
      srv.request.pose.orientation.w = qw;
      srv.request.pose.orientation.x = qx;
      srv.request.twist.linear.x = vx;
      return call(kNode + "set_body_state", srv).response;
    };
    expectRejected(state("no_such_link", 3, 1, 0, 0), "state of an unknown link");
    expectRejected(state(root, 3, 0, 0, 0), "zero quaternion");
    expectRejected(state(root, 3, 2, 0, 0), "quaternion of norm 2");
    expectRejected(state(root, 3, 0.9, 0.1, 0), "quaternion of norm 0.905");
    expectRejected(state(root, 3, nan, 0, 0), "NaN quaternion");
    expectRejected(state(root, nan, 1, 0, 0), "NaN position");
    expectRejected(state(root, 3, 1, 0, nan), "NaN velocity");
  }

  {
    std::string movable, fixed;
    for (const auto& [name, joint] : shared->robot.joints) {
      const bool hasCoordinate = joint->type == urdf::Joint::REVOLUTE ||
                                 joint->type == urdf::Joint::CONTINUOUS ||
                                 joint->type == urdf::Joint::PRISMATIC;
      if (hasCoordinate && !joint->mimic && movable.empty()) movable = name;
      if (joint->type == urdf::Joint::FIXED && fixed.empty()) fixed = name;
    }
    ASSERT_FALSE(movable.empty()) << "the ragdoll has no revolute joint";
    auto command = [&](std::vector<std::string> names, int mode, std::vector<double> targets,
                       std::vector<double> maxForces) {
      pfx::SetJointCommand srv;
      srv.request.names = std::move(names);
      srv.request.mode = mode;
      srv.request.targets = std::move(targets);
      srv.request.max_forces = std::move(maxForces);
      return call(kNode + "set_joint_command", srv).response;
    };
    const int position = pfx::SetJointCommand::Request::POSITION;
    expectRejected(command({"no_such_joint"}, position, {0.5}, {}), "unknown joint");
    expectRejected(command({}, position, {}, {}), "no joints");
    expectRejected(command({movable}, 7, {0.5}, {}), "mode 7");
    expectRejected(command({movable}, position, {}, {}), "no target");
    expectRejected(command({movable}, position, {nan}, {}), "NaN target");
    expectRejected(command({movable}, position, {0.5}, {-1}), "negative max force");
    expectRejected(command({movable, movable}, position, {0.5, 0.5}, {}), "a joint twice");
    expectRejected(command({movable, "no_such_joint"}, position, {0.5, 0.5}, {}),
                   "a good joint and an unknown one");
    if (!fixed.empty()) {
      expectRejected(command({fixed}, position, {0.5}, {}), "a fixed joint");
    }
  }
  EXPECT_GE(checked, 30);

  // Nothing moved, nothing is pending, and the node still answers.
  const auto after = allLinkPoses();
  for (const auto& [link, pose] : before) {
    EXPECT_TRUE(pfx_test::samePose(pose, after.at(link))) << link << " moved";
  }
  const pfx::Raycast::Response good = raycast(kFreeX, kFreeY, 2.0, 0, 0, -4.0);
  EXPECT_TRUE(good.success) << good.message;
  EXPECT_TRUE(good.hit);

  const double resumedAt = shared->clock->now();
  const geometry_msgs::TransformStamped rootBefore = rootPose();
  ASSERT_TRUE(trigger("unpause"));
  ASSERT_TRUE(shared->clock->waitUntil(resumedAt + 0.5, 10.0));
  ros::WallDuration(0.2).sleep();
  const geometry_msgs::TransformStamped rootAfter = rootPose();
  const auto& p0 = rootBefore.transform.translation;
  const auto& p1 = rootAfter.transform.translation;
  EXPECT_LT(std::hypot(p1.x - p0.x, p1.y - p0.y, p1.z - p0.z), 0.05)
      << "the ragdoll moved after the rejected requests";
}

TEST(Ragdoll, GoodCommandsAreAccepted) {
  std::string movable;
  for (const auto& [name, joint] : shared->robot.joints) {
    if ((joint->type == urdf::Joint::REVOLUTE || joint->type == urdf::Joint::CONTINUOUS) &&
        !joint->mimic) {
      movable = name;
      break;
    }
  }
  pfx::SetJointCommand hold;
  hold.request.names = {movable};
  hold.request.mode = pfx::SetJointCommand::Request::POSITION;
  hold.request.targets = {0.0};
  hold = call(kNode + "set_joint_command", hold);
  EXPECT_TRUE(hold.response.success) << hold.response.message;
  pfx::SetJointCommand release;
  release.request.names = {movable};
  release.request.mode = pfx::SetJointCommand::Request::OFF;
  release = call(kNode + "set_joint_command", release);
  EXPECT_TRUE(release.response.success) << release.response.message;
}

TEST(Ragdoll, WrenchLiftsTheRoot) {
  const double start = shared->clock->now();
  const double z0 = rootPose().transform.translation.z;
  pfx::ApplyBodyWrench lift;
  lift.request.link = shared->robot.root;
  lift.request.force.z = 3000;  // several times the weight of the whole ragdoll
  lift.request.duration = 0.3;
  lift = call(kNode + "apply_body_wrench", lift);
  ASSERT_TRUE(lift.response.success) << lift.response.message;
  ASSERT_TRUE(shared->clock->waitUntil(start + 0.4, 10.0));
  ros::WallDuration(0.1).sleep();
  EXPECT_GT(rootPose().transform.translation.z, z0 + 0.1) << "the wrench did not lift it";
}

// Seen through rays, which see the world as it is between steps: TF only follows steps.
TEST(Ragdoll, SetBodyStateMovesTheLinkAndResetPutsItBack) {
  ASSERT_TRUE(trigger("pause"));
  pfx::SetBodyState move;
  move.request.link = shared->robot.root;
  move.request.pose.position.x = 2.0;
  move.request.pose.position.y = 2.0;
  move.request.pose.position.z = 3.0;
  move.request.pose.orientation.w = 1.0;
  move = call(kNode + "set_body_state", move);
  ASSERT_TRUE(move.response.success) << move.response.message;
  const pfx::Raycast::Response moved = raycast(2.0, 2.0, 6.0, 0, 0, -7.0);
  ASSERT_TRUE(moved.success);
  EXPECT_EQ(moved.link, shared->robot.root);
  EXPECT_GT(moved.point.z, 3.0);
  EXPECT_LT(moved.point.z, 3.5);

  std_srvs::Trigger reset;
  reset = call(kNode + "reset", reset);
  ASSERT_TRUE(reset.response.success) << reset.response.message;
  const pfx::Raycast::Response back = raycast(2.0, 2.0, 6.0, 0, 0, -7.0);
  EXPECT_EQ(back.link, "ground") << "the root link is still where set_body_state put it";
  // The ragdoll stands again where it started, its root at the initial height.
  const pfx::Raycast::Response start = raycast(0.0, 0.0, 6.0, 0, 0, -7.0);
  EXPECT_TRUE(isRagdollLink(start.link)) << "hit '" << start.link << "'";
  EXPECT_GT(start.point.z, shared->initialHeight);

  const double resumedAt = shared->clock->now();
  ASSERT_TRUE(trigger("unpause"));
  ASSERT_TRUE(shared->clock->waitUntil(resumedAt + 0.05, 10.0));
  ros::WallDuration(0.05).sleep();
  EXPECT_GT(rootPose().transform.translation.z, shared->initialHeight - 0.3)
      << "TF does not show the ragdoll back at its start";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_ragdoll");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.clock = std::make_unique<pfx_test::ClockWatcher>(state.ros->nh);
  shared = &state;
  if (!pfx_test::waitForServices({kNode + "raycast", kNode + "reset"}, 30.0)) {
    ROS_FATAL("pfx_node's services did not appear");
    return 1;
  }
  if (!pfx_test::readRobot("/robot_description", state.robot)) {
    ROS_FATAL("robot_description is missing or not a URDF");
    return 1;
  }
  ros::param::get("/pfx_node/initial_height", state.initialHeight);
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
