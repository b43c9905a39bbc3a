// rostest (agents.test): agents beside a loose crate. The declared ones come up from ~agents;
// the one driven by cmd_vel walks the commanded speed (measured between two stamps of its TF
// frame once it has sped up), turns at the commanded rate, stops after the timeout, and is
// held to its max_speed; the other walks its square of waypoints in order, round and round.
// Rays and get_contacts name agents. Two agents walking into each other, and one walking
// into the crate, never overlap beyond a small tolerance. A deleted agent leaves TF,
// markers, rays, contacts and the world (its body is removed: /diagnostics counts one body
// fewer). Every bad request is refused with its reason and changes nothing: no body is added
// (/diagnostics), no frame appears, other agents stay put. A reset puts the agents back at
// their starts; the world saves with agents in it, and loads once they are deleted, without
// the saved agents' bodies.
#include <geometry_msgs/Twist.h>
#include <std_srvs/Trigger.h>
#include <tf2/utils.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <limits>
#include <mutex>

#include "pfx/DeleteAgent.h"
#include "pfx/GetContacts.h"
#include "pfx/RaycastBatch.h"
#include "pfx/SpawnAgent.h"
#include "pfx/WorldFile.h"
#include "pfx_ros_body_count.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
// The crate's half extents (tests/ros/data/crate.urdf) in its own frame.
const double kCrateHalfX = 0.5, kCrateHalfY = 0.3;
// How far two shapes may sink into each other while pushing (m): the solver lets contacts
// overlap by a few millimetres.
const double kOverlapTolerance = 0.02;

struct Pose2 {
  double x = 0, y = 0, yaw = 0;
};

Pose2 toPose(const geometry_msgs::TransformStamped& t) {
  return {t.transform.translation.x, t.transform.translation.y, tf2::getYaw(t.transform.rotation)};
}

// The pose of `frame` in `parent` at simulated time `t`, waiting up to `wallSeconds` for TF
// to reach it.
bool poseAt(const std::string& parent, const std::string& frame, double t, Pose2& out,
            double wallSeconds = 10);
// The newest pose of `frame` in `parent`.
bool latestPose(const std::string& parent, const std::string& frame, Pose2& out);

// The agents' markers as rviz would keep them: ADD replaces, DELETE removes.
class AgentMarkers {
 public:
  explicit AgentMarkers(ros::NodeHandle& nh)
      : m_sub(nh.subscribe(kNode + "markers", 10, &AgentMarkers::onMarkers, this)) {}
  // The ids of the markers whose text (the label) is `name`, and of those after it that the
  // same agent owns (consecutive ids, kMarkersPerAgent of them).
  int drawnWithLabel(const std::string& name) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    int found = 0;
    for (const auto& [id, marker] : m_kept) found += marker.text == name ? 1 : 0;
    return found;
  }
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_kept.size();
  }
  bool hasId(int id) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_kept.count(id) != 0;
  }
  // The first id of the agent whose label is `name`, -1 when not drawn.
  int labelId(const std::string& name) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const auto& [id, marker] : m_kept) {
      if (marker.text == name) return id;
    }
    return -1;
  }

 private:
  void onMarkers(const visualization_msgs::MarkerArray& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const visualization_msgs::Marker& marker : msg.markers) {
      if (marker.ns != "agents") continue;
      if (marker.action == visualization_msgs::Marker::DELETE) {
        m_kept.erase(marker.id);
      } else {
        m_kept[marker.id] = marker;
      }
    }
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::map<int, visualization_msgs::Marker> m_kept;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::ClockWatcher> clock;
  std::unique_ptr<AgentMarkers> markers;
  std::unique_ptr<pfx_test::BodyCount> bodies;
};
Shared* shared = nullptr;

bool poseAt(const std::string& parent, const std::string& frame, double t, Pose2& out,
            double wallSeconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
  for (;;) {
    try {
      out = toPose(shared->ros->tfBuffer.lookupTransform(parent, frame, ros::Time(t)));
      return true;
    } catch (const tf2::TransformException&) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.02).sleep();
    }
  }
}

bool latestPose(const std::string& parent, const std::string& frame, Pose2& out) {
  geometry_msgs::TransformStamped t;
  if (!pfx_test::lookup(shared->ros->tfBuffer, parent, frame, t)) return false;
  out = toPose(t);
  return true;
}

double distance(const Pose2& a, const Pose2& b) { return std::hypot(a.x - b.x, a.y - b.y); }

pfx::SpawnAgent makeAgent(const std::string& name, double x, double y, double radius = 0.3,
                          double height = 1.8) {
  pfx::SpawnAgent srv;
  srv.request.name = name;
  srv.request.radius = radius;
  srv.request.height = height;
  srv.request.position.x = x;
  srv.request.position.y = y;
  return srv;
}

geometry_msgs::Point point(double x, double y) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  return p;
}

pfx::DeleteAgent::Response deleteAgent(const std::string& name) {
  pfx::DeleteAgent srv;
  srv.request.name = name;
  return call(kNode + "delete_agent", srv).response;
}

// Publishes `twist` on <agent>/cmd_vel at 20 Hz of wall time until `done()`; false when that
// does not come within 60 s of wall time.
bool driveUntil(const std::string& agent, const geometry_msgs::Twist& twist,
                const std::function<bool()>& done) {
  static std::map<std::string, ros::Publisher> publishers;
  ros::Publisher& pub = publishers[agent];
  if (!pub) {
    pub = shared->ros->nh.advertise<geometry_msgs::Twist>("/" + agent + "/cmd_vel", 1);
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5.0);
    while (pub.getNumSubscribers() == 0 && ros::WallTime::now() < deadline) {
      ros::WallDuration(0.02).sleep();
    }
    if (pub.getNumSubscribers() == 0) return false;
  }
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (!done()) {
    if (ros::WallTime::now() > deadline) return false;
    pub.publish(twist);
    ros::WallDuration(0.05).sleep();
  }
  return true;
}

// Drives until simulated time `until`.
bool drive(const std::string& agent, const geometry_msgs::Twist& twist, double until) {
  return driveUntil(agent, twist, [until] { return shared->clock->now() >= until; });
}

// Drives `agent` (its frame under the fixed frame `world`) until its TF pose first shows the
// command acting, and then for `seconds` of simulated time more; `*start` is the stamp of
// that first pose. A command acts only once the node has it, which on a loaded machine may be
// well after the test published it, so what the test measures is timed from there rather
// than from the clock at the first publication. A command that moves the agent shows when its
// foot has moved 1 mm, a turn alone when its heading has turned 1 mrad (a turn still going on
// from the last command moves no foot).
bool driveFromStart(const std::string& agent, const geometry_msgs::Twist& twist, double seconds,
                    double* start) {
  const std::string frame = "agents/" + agent;
  geometry_msgs::TransformStamped t;
  if (!pfx_test::lookup(shared->ros->tfBuffer, "world", frame, t)) return false;
  const Pose2 before = toPose(t);
  const bool turnOnly = twist.linear.x == 0 && twist.linear.y == 0;
  auto acting = [&](const Pose2& now) {
    return turnOnly ? std::abs(std::remainder(now.yaw - before.yaw, 2 * M_PI)) > 1e-3
                    : distance(now, before) > 1e-3;
  };
  *start = -1;
  return driveUntil(agent, twist, [&] {
    if (*start < 0 && pfx_test::lookup(shared->ros->tfBuffer, "world", frame, t) &&
        acting(toPose(t))) {
      *start = t.header.stamp.toSec();
    }
    return *start >= 0 && shared->clock->now() >= *start + seconds;
  });
}

geometry_msgs::Twist twist(double vx, double vy, double wz) {
  geometry_msgs::Twist t;
  t.linear.x = vx;
  t.linear.y = vy;
  t.angular.z = wz;
  return t;
}

TEST(Agents, DeclaredAgentsAreInTfAndMarkers) {
  Pose2 driver, walker;
  ASSERT_TRUE(latestPose("world", "agents/driver", driver));
  ASSERT_TRUE(latestPose("world", "agents/walker", walker));
  // The driver stands where ~agents put it (its foot on the ground at z = 0).
  EXPECT_NEAR(driver.x, -4.0, 0.01);
  EXPECT_NEAR(driver.y, 4.0, 0.01);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while ((shared->markers->drawnWithLabel("driver") == 0 ||
          shared->markers->drawnWithLabel("walker") == 0) &&
         ros::WallTime::now() < deadline) {
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_EQ(shared->markers->drawnWithLabel("driver"), 1);
  EXPECT_EQ(shared->markers->drawnWithLabel("walker"), 1);
  // Five markers each: cylinder, two spheres, arrow, label.
  EXPECT_EQ(shared->markers->size(), 10u);
}

TEST(Agents, CmdVelDrivesAtTheCommandedSpeedTurnsAndStopsAfterTheTimeout) {
  const double speed = 1.0;
  double t0;
  // Half a second to reach the speed (it accelerates at 20 m/s^2), then 1.5 s measured.
  ASSERT_TRUE(driveFromStart("driver", twist(speed, 0, 0), 2.2, &t0));
  Pose2 a, b;
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 0.5, a));
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 2.0, b));
  const double expected = speed * 1.5;
  const double travelled = b.x - a.x;
  std::printf("cmd_vel 1.0 m/s for 1.5 s: travelled %.6f m (error %.2e m), sideways %.2e m\n",
              travelled, travelled - expected, b.y - a.y);
  EXPECT_NEAR(travelled, expected, 0.02 * expected);
  EXPECT_NEAR(b.y - a.y, 0.0, 0.01);
  EXPECT_NEAR(b.yaw, 0.0, 1e-3);

  // No more commands: it stops once the last is 0.5 s old; between 1.5 s and 2.5 s after
  // the last one it does not move.
  const double stopped = shared->clock->now();
  ASSERT_TRUE(shared->clock->waitUntil(stopped + 2.6, 20));
  ASSERT_TRUE(poseAt("world", "agents/driver", stopped + 1.5, a));
  ASSERT_TRUE(poseAt("world", "agents/driver", stopped + 2.5, b));
  std::printf("after the timeout: moved %.2e m in 1 s\n", distance(a, b));
  EXPECT_LT(distance(a, b), 0.002);

  // A turn at 1 rad/s, measured over 1 s.
  ASSERT_TRUE(driveFromStart("driver", twist(0, 0, 1.0), 1.4, &t0));
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 0.2, a));
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 1.2, b));
  const double turned = std::remainder(b.yaw - a.yaw, 2 * M_PI);
  std::printf("angular.z 1.0 rad/s for 1 s: turned %.6f rad\n", turned);
  EXPECT_NEAR(turned, 1.0, 0.02);

  // linear.x is forward in the heading; 100 m/s is cut to max_speed, 1.5 m/s. The heading is
  // the one the agent drives at, read from its pose while it drives: the turn goes on until
  // the node's last turn command is 0.5 s old, and the node may have had that command later
  // than the test published it.
  ASSERT_TRUE(driveFromStart("driver", twist(100, 0, 0), 1.7, &t0));
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 0.5, a));
  ASSERT_TRUE(poseAt("world", "agents/driver", t0 + 1.5, b));
  const double along = (b.x - a.x) * std::cos(a.yaw) + (b.y - a.y) * std::sin(a.yaw);
  const double across = -(b.x - a.x) * std::sin(a.yaw) + (b.y - a.y) * std::cos(a.yaw);
  std::printf("cmd_vel 100 m/s (max_speed 1.5) for 1 s at yaw %.3f: %.6f m along, %.2e across\n",
              a.yaw, along, across);
  EXPECT_NEAR(along, 1.5, 0.03);
  EXPECT_NEAR(across, 0.0, 0.01);
  EXPECT_NEAR(std::remainder(b.yaw - a.yaw, 2 * M_PI), 0.0, 1e-3);
  ASSERT_TRUE(shared->clock->waitUntil(shared->clock->now() + 1.0, 10));
}

TEST(Agents, WaypointAgentWalksItsWaypointsInALoop) {
  const Pose2 waypoints[] = {{3, -3, 0}, {5, -3, 0}, {5, -1, 0}, {3, -1, 0}};
  // A lap is 8 m at 1.5 m/s. Its frame is sampled afterwards, every 10 ms of simulated time
  // over 9 s (TF keeps 10 s), so that a slow test process misses no corner.
  const double start = shared->clock->now();
  ASSERT_TRUE(shared->clock->waitUntil(start + 9.0, 30));
  std::vector<int> visits;
  for (double t = start; t <= start + 9.0; t += 0.01) {
    Pose2 at;
    ASSERT_TRUE(poseAt("world", "agents/walker", t, at, 1)) << t;
    for (int i = 0; i < 4; ++i) {
      if (distance(at, waypoints[i]) < 0.15 && (visits.empty() || visits.back() != i)) {
        visits.push_back(i);
      }
    }
  }
  // A whole lap and back to the corner it was first seen at, at least.
  ASSERT_GE(visits.size(), 5u);
  for (std::size_t k = 1; k < visits.size(); ++k) {
    EXPECT_EQ(visits[k], (visits[k - 1] + 1) % 4) << "visit " << k;
  }
  std::printf("walker: %zu corners visited in order in 9 s of simulated time\n", visits.size());
}

TEST(Agents, RaysAndContactsNameTheAgent) {
  Pose2 driver;
  ASSERT_TRUE(latestPose("world", "agents/driver", driver));
  // From 2 m to its -x side at chest height, towards it.
  const pfx::Raycast::Response hit =
      pfx_test::raycast(kNode + "raycast", driver.x - 2, driver.y, 1.0, 4, 0, 0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.link, "driver");
  EXPECT_NEAR(hit.point.x, driver.x - 0.3, 0.01);

  pfx::RaycastBatch batch;
  batch.request.origins.push_back(point(driver.x, driver.y + 2));
  batch.request.origins.back().z = 1.0;
  geometry_msgs::Vector3 down;
  down.y = -4;
  batch.request.directions.push_back(down);
  batch = call(kNode + "raycast_batch", batch);
  ASSERT_TRUE(batch.response.success) << batch.response.message;
  ASSERT_EQ(batch.response.links.size(), 1u);
  EXPECT_EQ(batch.response.links[0], "driver");

  pfx::GetContacts contacts;
  contacts.request.link = "driver";
  contacts = call(kNode + "get_contacts", contacts);
  ASSERT_TRUE(contacts.response.success) << contacts.response.message;
  ASSERT_FALSE(contacts.response.contacts.empty());
  for (const pfx::Contact& c : contacts.response.contacts) {
    EXPECT_EQ(c.link_a, "driver");
    EXPECT_EQ(c.link_b, "ground");
  }
}

// Samples the two frames at every 10 ms of simulated time in [from, to] and returns their
// least horizontal distance.
double leastDistance(const std::string& a, const std::string& b, double from, double to) {
  double least = std::numeric_limits<double>::infinity();
  for (double t = from; t <= to; t += 0.01) {
    Pose2 pa, pb;
    EXPECT_TRUE(poseAt("world", a, t, pa, 1) && poseAt("world", b, t, pb, 1)) << t;
    least = std::min(least, distance(pa, pb));
  }
  return least;
}

TEST(Agents, TwoAgentsWalkingIntoEachOtherDoNotOverlap) {
  // Head on along y = -5, 5 cm off centre so that they may also slide past.
  pfx::SpawnAgent a = makeAgent("a1", -2, -5.0, 0.3, 1.8);
  a.request.waypoints = {point(2, -5.05), point(-2, -5.0)};
  pfx::SpawnAgent b = makeAgent("a2", 2, -5.05, 0.25, 1.6);
  b.request.waypoints = {point(-2, -5.0), point(2, -5.05)};
  a = call(kNode + "spawn_agent", a);
  ASSERT_TRUE(a.response.success) << a.response.message;
  b = call(kNode + "spawn_agent", b);
  ASSERT_TRUE(b.response.success) << b.response.message;
  const double start = shared->clock->now() + 0.1;
  ASSERT_TRUE(shared->clock->waitUntil(start + 5.0, 30));
  const double least = leastDistance("agents/a1", "agents/a2", start, start + 5.0);
  std::printf("two agents (radii 0.3 and 0.25) head on: least distance of their axes %.4f m\n",
              least);
  EXPECT_GE(least, 0.55 - kOverlapTolerance);
  EXPECT_LT(least, 0.55 + 0.05) << "they never met";
  EXPECT_TRUE(deleteAgent("a1").success);
  EXPECT_TRUE(deleteAgent("a2").success);
}

// Distance from (x, y) to the crate's rectangle in the crate's frame (0 inside).
double distanceToCrate(const Pose2& p) {
  const double dx = std::max(0.0, std::abs(p.x) - kCrateHalfX);
  const double dy = std::max(0.0, std::abs(p.y) - kCrateHalfY);
  return std::hypot(dx, dy);
}

TEST(Agents, AnAgentWalkingIntoTheRobotPushesItWithoutPassingThrough) {
  pfx::SpawnAgent srv = makeAgent("pusher", -3, 0, 0.3, 1.8);
  srv = call(kNode + "spawn_agent", srv);
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  // Its frame is first published after the step that follows the spawn.
  const double start = shared->clock->now() + 0.1;
  Pose2 crateBefore;
  ASSERT_TRUE(poseAt("world", "crate", start, crateBefore));
  ASSERT_TRUE(drive("pusher", twist(1.0, 0, 0), start + 5.0));
  Pose2 crateAfter, pusher;
  ASSERT_TRUE(poseAt("world", "crate", start + 5.0, crateAfter));
  ASSERT_TRUE(poseAt("crate", "agents/pusher", start + 5.0, pusher));
  double least = std::numeric_limits<double>::infinity();
  for (double t = start; t <= start + 5.0; t += 0.01) {
    Pose2 p;
    ASSERT_TRUE(poseAt("crate", "agents/pusher", t, p, 1)) << t;
    least = std::min(least, distanceToCrate(p));
  }
  std::printf(
      "pusher (radius 0.3) into the crate: least axis-to-box distance %.4f m, crate "
      "pushed %.3f m, pusher at x = %.3f m in the crate's frame\n",
      least, crateAfter.x - crateBefore.x, pusher.x);
  EXPECT_GE(least, 0.3 - kOverlapTolerance);
  EXPECT_LT(pusher.x, -kCrateHalfX) << "passed through";
  // Walking 5 s at 1 m/s from 2.2 m away, it reached the crate and pushed it along +x.
  EXPECT_GT(crateAfter.x - crateBefore.x, 0.5);
  EXPECT_TRUE(deleteAgent("pusher").success);
}

TEST(Agents, DeleteRemovesTheAgentFromTfMarkersRaysAndContacts) {
  Pose2 driver;
  ASSERT_TRUE(latestPose("world", "agents/driver", driver));
  const int firstId = shared->markers->labelId("driver") - 4;
  ASSERT_GE(firstId, 0);
  const double bodiesBefore = shared->bodies->next();
  const pfx::DeleteAgent::Response res = deleteAgent("driver");
  ASSERT_TRUE(res.success) << res.message;
  const double deletedAt = shared->clock->now();
  ASSERT_TRUE(shared->clock->waitUntil(deletedAt + 1.0, 10));
  EXPECT_EQ(shared->bodies->next(), bodiesBefore - 1) << "its body is still in the world";

  geometry_msgs::TransformStamped last;
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "world", "agents/driver", last));
  EXPECT_LT(last.header.stamp.toSec(), deletedAt + 0.1) << "its frame is still published";
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5.0);
  while (shared->markers->drawnWithLabel("driver") != 0 && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.05).sleep();
  }
  for (int id = firstId; id < firstId + 5; ++id) EXPECT_FALSE(shared->markers->hasId(id)) << id;

  const pfx::Raycast::Response hit =
      pfx_test::raycast(kNode + "raycast", driver.x - 2, driver.y, 1.0, 4, 0, 0);
  ASSERT_TRUE(hit.success) << hit.message;
  EXPECT_FALSE(hit.hit) << hit.link;
  pfx::GetContacts contacts;
  contacts.request.link = "driver";
  contacts = call(kNode + "get_contacts", contacts);
  EXPECT_FALSE(contacts.response.success);
  pfx::GetContacts all;
  all = call(kNode + "get_contacts", all);
  for (const pfx::Contact& c : all.response.contacts) {
    EXPECT_NE(c.link_a, "driver");
    EXPECT_NE(c.link_b, "driver");
  }
  // The name is free again.
  pfx::SpawnAgent again = call(kNode + "spawn_agent", makeAgent("driver", -4, 4));
  EXPECT_TRUE(again.response.success) << again.response.message;
  EXPECT_TRUE(deleteAgent("driver").success);
}

TEST(Agents, BadRequestsAreRefusedWithTheirReasonAndChangeNothing) {
  pfx::SpawnAgent stand = call(kNode + "spawn_agent", makeAgent("stand", -4, -1.5));
  ASSERT_TRUE(stand.response.success) << stand.response.message;
  ASSERT_TRUE(shared->clock->waitUntil(shared->clock->now() + 0.5, 10));
  Pose2 standBefore;
  ASSERT_TRUE(latestPose("world", "agents/stand", standBefore));
  const double bodiesBefore = shared->bodies->next();
  ASSERT_GT(bodiesBefore, 0);
  Pose2 crate;
  ASSERT_TRUE(latestPose("world", "crate", crate));

  struct Bad {
    const char* what;
    std::function<void(pfx::SpawnAgent&)> change;
    const char* reason;  // a part of the message
  };
  const Bad bad[] = {
      {"empty name", [](auto& s) { s.request.name = ""; }, "no name"},
      {"name with a space", [](auto& s) { s.request.name = "bad name"; }, "not a valid"},
      {"name with a slash", [](auto& s) { s.request.name = "a/b"; }, "not a valid"},
      {"name starting with a digit", [](auto& s) { s.request.name = "7up"; }, "not a valid"},
      {"taken name", [](auto& s) { s.request.name = "walker"; }, "exists already"},
      {"a link's name", [](auto& s) { s.request.name = "crate"; }, "body of the robot"},
      {"the ground's name", [](auto& s) { s.request.name = "ground"; }, "body of the robot"},
      {"zero radius", [](auto& s) { s.request.radius = 0; }, "radius"},
      {"negative radius", [](auto& s) { s.request.radius = -0.3; }, "radius"},
      {"NaN radius", [](auto& s) { s.request.radius = kNaN; }, "radius"},
      {"infinite radius", [](auto& s) { s.request.radius = kInf; }, "radius"},
      {"zero height", [](auto& s) { s.request.height = 0; }, "height"},
      {"height below two radii", [](auto& s) { s.request.height = 0.5; }, "height"},
      {"NaN height", [](auto& s) { s.request.height = kNaN; }, "height"},
      {"negative mass", [](auto& s) { s.request.mass = -80; }, "mass"},
      {"NaN max_speed", [](auto& s) { s.request.max_speed = kNaN; }, "max_speed"},
      {"negative max_speed", [](auto& s) { s.request.max_speed = -1; }, "max_speed"},
      {"NaN position", [](auto& s) { s.request.position.y = kNaN; }, "position"},
      {"infinite position", [](auto& s) { s.request.position.x = kInf; }, "position"},
      {"position outside the world", [](auto& s) { s.request.position.x = 5000; },
       "outside the world"},
      {"NaN yaw", [](auto& s) { s.request.yaw = kNaN; }, "yaw"},
      {"waypoint outside the world",
       [](auto& s) {
         s.request.waypoints = {point(0, 6), point(0, -2000)};
       },
       "waypoint 1 is outside the world"},
      {"NaN waypoint",
       [](auto& s) {
         s.request.waypoints = {point(0, 6), point(kNaN, 6)};
       },
       "waypoint 1"},
      {"inside the robot (pushed away from the origin, wherever it is now)",
       [&crate](auto& s) { s.request.position = point(crate.x + 0.2, crate.y + 0.1); }, "'crate'"},
      {"inside another agent", [](auto& s) { s.request.position = point(-4.3, -1.5); }, "'stand'"},
  };
  for (const Bad& b : bad) {
    pfx::SpawnAgent srv = makeAgent("newcomer", -6, 6);
    b.change(srv);
    srv = call(kNode + "spawn_agent", srv);
    EXPECT_FALSE(srv.response.success) << b.what;
    EXPECT_NE(srv.response.message.find(b.reason), std::string::npos)
        << b.what << ": " << srv.response.message;
    std::printf("spawn_agent, %s: %s\n", b.what, srv.response.message.c_str());
  }
  const std::pair<const char*, const char*> badDeletes[] = {
      {"", "no name"}, {"nobody", "no agent named 'nobody'"}, {"crate", "no agent named"}};
  for (const auto& [name, reason] : badDeletes) {
    const pfx::DeleteAgent::Response res = deleteAgent(name);
    EXPECT_FALSE(res.success) << name;
    EXPECT_NE(res.message.find(reason), std::string::npos) << name << ": " << res.message;
    std::printf("delete_agent '%s': %s\n", name, res.message.c_str());
  }
  // Loading a world file while agents live: the file cannot say who drives their bodies.
  pfx::WorldFile load;
  load.request.path = "/tmp/pfx_agents_test_absent.pfxw";
  load = call(kNode + "load_world", load);
  EXPECT_FALSE(load.response.success);
  EXPECT_NE(load.response.message.find("agents"), std::string::npos) << load.response.message;

  // NaN commands are dropped: the agent stands where it stood.
  ASSERT_TRUE(drive("stand", twist(kNaN, 0, 0), shared->clock->now() + 1.0));
  ASSERT_TRUE(drive("stand", twist(0, 0, kInf), shared->clock->now() + 0.5));

  // Nothing changed: no body was added, no frame appeared, the agent did not move and the
  // robot's crate is still the only body with its name.
  EXPECT_EQ(shared->bodies->next(), bodiesBefore);
  ASSERT_TRUE(shared->clock->waitUntil(shared->clock->now() + 0.5, 10));
  EXPECT_FALSE(shared->ros->tfBuffer._frameExists("agents/newcomer"));
  Pose2 standAfter;
  ASSERT_TRUE(latestPose("world", "agents/stand", standAfter));
  EXPECT_LT(distance(standBefore, standAfter), 0.002);
  EXPECT_NEAR(standAfter.yaw, standBefore.yaw, 1e-4);
  // And "newcomer" is still free.
  pfx::SpawnAgent good = call(kNode + "spawn_agent", makeAgent("newcomer", -6, 6));
  EXPECT_TRUE(good.response.success) << good.response.message;
}

TEST(Agents, ResetPutsAgentsBackAndWorldFilesLeaveAgentsOut) {
  std_srvs::Trigger reset;
  reset = call(kNode + "reset", reset);
  ASSERT_TRUE(reset.response.success) << reset.response.message;
  const double resetAt = shared->clock->now();
  Pose2 stand, newcomer, crate;
  ASSERT_TRUE(poseAt("world", "agents/stand", resetAt + 0.1, stand));
  ASSERT_TRUE(poseAt("world", "agents/newcomer", resetAt + 0.1, newcomer));
  ASSERT_TRUE(poseAt("world", "crate", resetAt + 0.1, crate));
  EXPECT_LT(distance(stand, {-4, -1.5, 0}), 0.005);
  EXPECT_LT(distance(newcomer, {-6, 6, 0}), 0.005);
  EXPECT_LT(distance(crate, {0, 0, 0}), 0.01);
  // The ground, the crate and the three agents left (walker, stand, newcomer).
  EXPECT_EQ(shared->bodies->next(), 5);

  // The world saves with agents in it; it loads only once they are deleted (the file does
  // not say who drives their bodies), and without the saved agents' bodies.
  pfx::WorldFile file;
  file.request.path = "/tmp/pfx_agents_test.pfxw";
  pfx::WorldFile saved = call(kNode + "save_world", file);
  EXPECT_TRUE(saved.response.success) << saved.response.message;
  pfx::WorldFile refused = call(kNode + "load_world", file);
  EXPECT_FALSE(refused.response.success);
  EXPECT_NE(refused.response.message.find("delete the agents first"), std::string::npos)
      << refused.response.message;
  for (const char* name : {"walker", "stand", "newcomer"}) EXPECT_TRUE(deleteAgent(name).success);
  // Deleted agents' bodies are gone at once, without a reset: the ground and the crate.
  EXPECT_EQ(shared->bodies->next(), 2);
  pfx::WorldFile loaded = call(kNode + "load_world", file);
  EXPECT_TRUE(loaded.response.success) << loaded.response.message;
  EXPECT_EQ(shared->bodies->next(), 2);
  const pfx::Raycast::Response hit =
      pfx_test::raycast(kNode + "raycast", newcomer.x - 2, newcomer.y, 1.0, 4, 0, 0);
  ASSERT_TRUE(hit.success) << hit.message;
  EXPECT_FALSE(hit.hit) << "the saved newcomer's body came back: " << hit.link;
  std::remove(file.request.path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_agents");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.clock = std::make_unique<pfx_test::ClockWatcher>(state.ros->nh);
  state.markers = std::make_unique<AgentMarkers>(state.ros->nh);
  state.bodies = std::make_unique<pfx_test::BodyCount>(state.ros->nh);
  shared = &state;
  if (!pfx_test::waitForServices({kNode + "spawn_agent", kNode + "delete_agent"}, 30.0)) {
    ROS_FATAL("the pfx_node services did not appear");
    return 1;
  }
  return RUN_ALL_TESTS();
}
