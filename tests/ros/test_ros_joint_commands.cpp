// rostest (joint_commands.test): the joint bench (tests/ros/data/joint_bench.urdf) in the
// namespace "bench", driven by topics as ros_control's controllers are: a position command
// reaches its target, a velocity command gives the carriage its speed, an effort command
// turns the wheel up at torque over inertia (and at the effort limit over inertia when
// asked for more), the group topic moves two joints at once, a three-point trajectory is
// followed against its interpolated reference, a command beyond a limit stops at the limit,
// and every bad command is dropped with a warning naming what was wrong, moving nothing.
// Names are relative: the test runs in the node's namespace.
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>

#include "pfx/SetJointCommand.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
// Tolerances asserted (the README gives the figures measured).
const double kReached = 0.01;         // rad or m from a position target
const double kSpeed = 0.02;           // relative, of a commanded velocity or acceleration
const double kTrackingError = 0.01;   // rad or m from a trajectory's reference
const double kWheelInertia = 0.02;    // kg m^2, the URDF's izz of the wheel
const double kWheelEffortLimit = 2;   // N m

struct JointSample {
  double stamp;
  std::map<std::string, double> positions;
  std::map<std::string, double> velocities;
};

// The latest joint_states, and every message while recording.
class JointWatcher {
 public:
  explicit JointWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("joint_states", 1000, &JointWatcher::onState, this)) {}
  bool connected() const { return m_sub.getNumPublishers() > 0; }
  JointSample latest() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_latest;
  }
  void record(bool on) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_recording = on;
    if (on) m_recorded.clear();
  }
  std::vector<JointSample> recorded() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_recorded;
  }

 private:
  void onState(const sensor_msgs::JointState& msg) {
    JointSample sample;
    sample.stamp = msg.header.stamp.toSec();
    for (std::size_t i = 0; i < msg.name.size(); ++i) {
      sample.positions[msg.name[i]] = msg.position[i];
      sample.velocities[msg.name[i]] = msg.velocity[i];
    }
    std::lock_guard<std::mutex> lock(m_mutex);
    m_latest = sample;
    if (m_recording) m_recorded.push_back(sample);
  }
  mutable std::mutex m_mutex;
  JointSample m_latest{-1, {}, {}};
  bool m_recording = false;
  std::vector<JointSample> m_recorded;
  ros::Subscriber m_sub;
};

// The node's warnings, from /rosout. Whether the node's /rosout reaches it is known only once
// one of them has been heard: the subscription counts this program's own /rosout publisher
// among its publishers from the start.
class WarningWatcher {
 public:
  explicit WarningWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/rosout", 1000, &WarningWatcher::onLog, this)) {}
  void clear() {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_warnings.clear();
  }
  // Waits for a warning holding `text` since the last clear().
  bool seen(const std::string& text, double wallSeconds = 10) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (ros::WallTime::now() < deadline) {
      if (!holding(text).empty()) return true;
      ros::WallDuration(0.02).sleep();
    }
    return false;
  }
  // The warnings holding `text` since the last clear(), in the order heard.
  std::vector<std::string> holding(const std::string& text) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    std::vector<std::string> found;
    for (const std::string& warning : m_warnings) {
      if (warning.find(text) != std::string::npos) found.push_back(warning);
    }
    return found;
  }

 private:
  void onLog(const rosgraph_msgs::Log& log) {
    if (log.level != rosgraph_msgs::Log::WARN) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    m_warnings.push_back(log.msg);
  }
  mutable std::mutex m_mutex;
  std::vector<std::string> m_warnings;
  ros::Subscriber m_sub;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::ClockWatcher> clock;
  std::unique_ptr<JointWatcher> joints;
  std::unique_ptr<WarningWatcher> warnings;
  std::map<std::string, ros::Publisher> commands;  // by joint
  ros::Publisher group;
  ros::Publisher trajectory;
};
Shared* shared = nullptr;

// Lets `seconds` of simulated time pass.
void waitSimulated(double seconds) {
  ASSERT_TRUE(shared->clock->waitUntil(shared->clock->now() + seconds, 10 * seconds + 10))
      << "the clock stopped";
}

void publish(const std::string& joint, double value) {
  std_msgs::Float64 msg;
  msg.data = value;
  shared->commands.at(joint).publish(msg);
}

void publishGroup(std::vector<double> values) {
  std_msgs::Float64MultiArray msg;
  msg.data = std::move(values);
  shared->group.publish(msg);
}

double position(const std::string& joint) { return shared->joints->latest().positions.at(joint); }

trajectory_msgs::JointTrajectoryPoint point(double time, std::vector<double> positions,
                                            std::vector<double> velocities = {}) {
  trajectory_msgs::JointTrajectoryPoint p;
  p.time_from_start = ros::Duration(time);
  p.positions = std::move(positions);
  p.velocities = std::move(velocities);
  return p;
}

trajectory_msgs::JointTrajectory trajectory(std::vector<std::string> joints,
                                            std::vector<trajectory_msgs::JointTrajectoryPoint> points,
                                            double start = 0) {
  trajectory_msgs::JointTrajectory msg;
  msg.header.stamp = ros::Time(start);
  msg.joint_names = std::move(joints);
  msg.points = std::move(points);
  return msg;
}

// The reference the node follows: from (t0, p0, v0) to (t1, p1, v1), a cubic when both
// carry velocities, else a straight line. The test's own arithmetic, not the node's.
double reference(double t, double t0, double p0, double v0, double t1, double p1, double v1,
                 bool cubic) {
  const double T = t1 - t0, s = (t - t0) / T;
  if (!cubic) return p0 + s * (p1 - p0);
  const double a = p0, b = v0 * T, c = 3 * (p1 - p0) - (2 * v0 + v1) * T,
               d = -2 * (p1 - p0) + (v0 + v1) * T;
  return a + s * (b + s * (c + s * d));
}

// The largest distance of the recorded positions of `joint` from the piecewise reference
// through `knots` (time, position, velocity) over [first knot, last knot + 0.5 s], where the
// last is held; also counts the samples.
double trackingError(const std::vector<JointSample>& samples, const std::string& joint,
                     const std::vector<std::array<double, 3>>& knots, bool cubic, int* count) {
  double worst = 0;
  *count = 0;
  for (const JointSample& sample : samples) {
    const double t = sample.stamp;
    if (t < knots.front()[0] || t > knots.back()[0] + 0.5) continue;
    double expected = knots.back()[1];
    for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
      if (t <= knots[k + 1][0]) {
        expected = reference(t, knots[k][0], knots[k][1], knots[k][2], knots[k + 1][0],
                             knots[k + 1][1], knots[k + 1][2], cubic);
        break;
      }
    }
    worst = std::max(worst, std::abs(sample.positions.at(joint) - expected));
    ++*count;
  }
  return worst;
}

// The wheel's acceleration over `seconds` of simulated time, from two joint_states.
double wheelAcceleration(double seconds) {
  const JointSample before = shared->joints->latest();
  waitSimulated(seconds);
  const JointSample after = shared->joints->latest();
  return (after.velocities.at("wheel_joint") - before.velocities.at("wheel_joint")) /
         (after.stamp - before.stamp);
}

}  // namespace

TEST(JointCommands, PositionCommandReachesItsTargetAndStopsAtTheLimit) {
  publish("shoulder", 0.5);
  waitSimulated(1.5);
  EXPECT_NEAR(position("shoulder"), 0.5, kReached);
  std::printf("shoulder at %.6f rad for 0.5\n", position("shoulder"));
  // Beyond the upper limit (1 rad): it drives to the limit and stops there.
  publish("shoulder", 2.0);
  EXPECT_TRUE(shared->warnings->seen("position target 2 cut to its upper limit 1"));
  waitSimulated(1.5);
  EXPECT_NEAR(position("shoulder"), 1.0, kReached);
  EXPECT_LE(position("shoulder"), 1.0 + 1e-3);
  std::printf("shoulder at %.6f rad for 2 (limit 1)\n", position("shoulder"));
}

TEST(JointCommands, VelocityCommandGivesTheCarriageItsSpeed) {
  publish("slide", 0.1);  // ~joint_interfaces: slide is velocity
  waitSimulated(0.3);
  const JointSample before = shared->joints->latest();
  waitSimulated(1.0);
  const JointSample after = shared->joints->latest();
  const double speed = (after.positions.at("slide") - before.positions.at("slide")) /
                       (after.stamp - before.stamp);
  std::printf("carriage at %.6f m/s for 0.1 (joint_states: %.6f)\n", speed,
              after.velocities.at("slide"));
  EXPECT_NEAR(speed, 0.1, kSpeed * 0.1);
  EXPECT_NEAR(after.velocities.at("slide"), 0.1, kSpeed * 0.1);
  // The follower mimics it.
  EXPECT_NEAR(after.positions.at("slide_follower"), after.positions.at("slide"), 1e-3);
  publish("slide", 0);
}

TEST(JointCommands, EffortTurnsTheWheelUpAtTorqueOverInertiaWithinItsLimit) {
  publish("wheel_joint", 0.1);  // ~joint_interfaces: the wheel is effort
  waitSimulated(0.2);
  const double alpha = wheelAcceleration(1.0);
  std::printf("wheel: %.4f rad/s^2 under 0.1 N m (tau / I = %.4f)\n", alpha, 0.1 / kWheelInertia);
  EXPECT_NEAR(alpha, 0.1 / kWheelInertia, kSpeed * 0.1 / kWheelInertia);
  publish("wheel_joint", -10);  // beyond the 2 N m effort limit
  EXPECT_TRUE(shared->warnings->seen("effort target -10 cut to its lower effort limit -2"));
  waitSimulated(0.2);
  const double limited = wheelAcceleration(0.3);
  std::printf("wheel: %.4f rad/s^2 under -10 N m (limit / I = %.4f)\n", limited,
              -kWheelEffortLimit / kWheelInertia);
  EXPECT_NEAR(limited, -kWheelEffortLimit / kWheelInertia,
              kSpeed * kWheelEffortLimit / kWheelInertia);
  // The service takes efforts too: none, and the wheel spins on at a steady speed.
  pfx::SetJointCommand srv;
  srv.request.names = {"wheel_joint"};
  srv.request.mode = pfx::SetJointCommand::Request::EFFORT;
  srv.request.targets = {0};
  EXPECT_TRUE(call("pfx_node/set_joint_command", srv).response.success);
  waitSimulated(0.1);
  EXPECT_NEAR(wheelAcceleration(0.3), 0, 0.05);
}

TEST(JointCommands, GroupTopicCommandsSeveralJoints) {
  publishGroup({-0.3, 0.1});  // shoulder, slide as positions
  waitSimulated(1.5);
  EXPECT_NEAR(position("shoulder"), -0.3, kReached);
  EXPECT_NEAR(position("slide"), 0.1, kReached);
}

TEST(JointCommands, TrajectoriesAreFollowedInSimulatedTime) {
  publishGroup({-0.3, 0.1});
  waitSimulated(1.0);
  const double p0 = position("shoulder"), s0 = position("slide");
  // Three points with velocities (cubics), starting 0.3 s from now.
  const double start = shared->clock->now() + 0.3;
  shared->joints->record(true);
  shared->trajectory.publish(trajectory(
      {"shoulder", "slide"},
      {point(1, {0.4, 0.25}, {0.5, 0}), point(2, {-0.5, -0.1}, {0, -0.1}),
       point(3, {0.2, 0.0}, {0, 0})},
      start));
  ASSERT_TRUE(shared->clock->waitUntil(start + 3.6, 60));
  int count = 0;
  const double shoulderError =
      trackingError(shared->joints->recorded(), "shoulder",
                    {{{start, p0, 0}}, {{start + 1, 0.4, 0.5}}, {{start + 2, -0.5, 0}},
                     {{start + 3, 0.2, 0}}},
                    true, &count);
  EXPECT_GT(count, 100);
  int slideCount = 0;
  const double slideError =
      trackingError(shared->joints->recorded(), "slide",
                    {{{start, s0, 0}}, {{start + 1, 0.25, 0}}, {{start + 2, -0.1, -0.1}},
                     {{start + 3, 0.0, 0}}},
                    true, &slideCount);
  std::printf("cubic trajectory: %d samples, largest error shoulder %.2e rad, slide %.2e m\n",
              count, shoulderError, slideError);
  EXPECT_LT(shoulderError, kTrackingError);
  EXPECT_LT(slideError, kTrackingError);
  // Held at the last point.
  EXPECT_NEAR(position("shoulder"), 0.2, kReached);
  EXPECT_NEAR(position("slide"), 0.0, kReached);

  // Points without velocities: straight lines, starting now (stamp 0).
  const double from = position("shoulder");
  shared->joints->record(true);
  shared->trajectory.publish(trajectory({"shoulder"}, {point(0.5, {0.0}), point(1.0, {0.3})}));
  waitSimulated(1.6);
  // Its start is the first step after it arrived: the samples where the joint has left.
  const std::vector<JointSample> samples = shared->joints->recorded();
  double begin = -1;
  for (const JointSample& sample : samples) {
    if (std::abs(sample.positions.at("shoulder") - from) > 1e-3) {
      begin = sample.stamp;
      break;
    }
  }
  ASSERT_GT(begin, 0) << "the straight-line trajectory did not move the shoulder";
  // It started at the last step before it arrived, which the test does not see: the
  // start is fitted among the steps (4 ms) of the 40 ms before the first sample that moved
  // (joint_states come every 20 ms of simulated time here).
  double best = std::numeric_limits<double>::max();
  for (double t0 = begin - 0.04; t0 <= begin + 1e-9; t0 += 0.004) {
    best = std::min(best, trackingError(samples, "shoulder",
                                        {{{t0, from, 0}}, {{t0 + 0.5, 0.0, 0}}, {{t0 + 1, 0.3, 0}}},
                                        false, &count));
  }
  std::printf("straight-line trajectory: %d samples, largest error %.2e rad\n", count, best);
  EXPECT_LT(best, kTrackingError);
}

// A trajectory stamped later replaces the one being followed from its own start, which it
// leaves from where the first meant the joint to be; a service command ends it.
TEST(JointCommands, ALaterTrajectoryTakesOverAtItsStartAndACommandEndsIt) {
  publishGroup({0.0, 0.05});
  waitSimulated(1.0);
  const double start = shared->clock->now() + 0.2;
  shared->trajectory.publish(trajectory({"shoulder"}, {point(2, {0.8})}, start));
  ASSERT_TRUE(shared->clock->waitUntil(start + 0.1, 30));
  shared->trajectory.publish(trajectory({"shoulder"}, {point(1, {-0.4})}, start + 1));
  ASSERT_TRUE(shared->clock->waitUntil(start + 0.9, 30));
  // Still the first: 0.8 * 0.9 / 2.
  EXPECT_NEAR(position("shoulder"), 0.36, 0.02);
  ASSERT_TRUE(shared->clock->waitUntil(start + 2.2, 30));
  // The second, from 0.4 at start + 1 to -0.4 at start + 2, then held.
  EXPECT_NEAR(position("shoulder"), -0.4, kReached);

  const double next = shared->clock->now();
  shared->trajectory.publish(trajectory({"shoulder"}, {point(3, {0.9})}));
  ASSERT_TRUE(shared->clock->waitUntil(next + 0.5, 30));
  pfx::SetJointCommand srv;
  srv.request.names = {"shoulder"};
  srv.request.mode = pfx::SetJointCommand::Request::POSITION;
  srv.request.targets = {-0.1};
  EXPECT_TRUE(call("pfx_node/set_joint_command", srv).response.success);
  waitSimulated(1.5);
  EXPECT_NEAR(position("shoulder"), -0.1, kReached);
}

TEST(JointCommands, BadCommandsAreDroppedWithAWarningAndMoveNothing) {
  publishGroup({0.2, 0.05});
  waitSimulated(1.0);
  const JointSample before = shared->joints->latest();

  publish("shoulder", kNaN);
  EXPECT_TRUE(shared->warnings->seen("shoulder/command dropped: the value is not finite"));
  publishGroup({0.1});
  EXPECT_TRUE(shared->warnings->seen("joint_group_command dropped: 1 values for 2 joints"));
  publishGroup({kInf, 0.0});
  EXPECT_TRUE(shared->warnings->seen("the value of joint 'shoulder' is not finite"));
  struct Bad {
    trajectory_msgs::JointTrajectory msg;
    const char* warning;
  };
  const std::vector<Bad> bad = {
      {trajectory({"elbow"}, {point(1, {0})}), "unknown joint 'elbow'"},
      {trajectory({"slide_follower"}, {point(1, {0})}),
       "joint 'slide_follower' mimics 'slide': command the leader"},
      {trajectory({"tool_mount"}, {point(1, {0})}), "joint 'tool_mount' has no coordinate"},
      {trajectory({}, {point(1, {})}), "no joint_names"},
      {trajectory({"shoulder", "shoulder"}, {point(1, {0, 0})}), "joint 'shoulder' named twice"},
      {trajectory({"shoulder"}, {}), "no points"},
      {trajectory({"shoulder"}, {point(1, {0}), point(0.5, {0.1})}),
       "point 1: time_from_start 0.5 s is not after 1 s"},
      {trajectory({"shoulder"}, {point(1, {0}), point(1, {0.1})}),
       "point 1: time_from_start 1 s is not after 1 s"},
      {trajectory({"shoulder"}, {point(-0.5, {0})}),
       "point 0: time_from_start -0.5 s is not at least 0 s"},
      {trajectory({"shoulder"}, {point(1, {kNaN})}),
       "point 0: a position or velocity is NaN or infinite"},
      {trajectory({"shoulder"}, {point(1, {0}, {kInf})}),
       "point 0: a position or velocity is NaN or infinite"},
      {trajectory({"shoulder", "slide"}, {point(1, {0})}),
       "point 0: positions are not one per joint"},
      {trajectory({"shoulder"}, {point(1, {0}, {1, 2})}),
       "point 0: velocities are neither empty nor one per joint"},
  };
  for (const Bad& b : bad) {
    shared->warnings->clear();
    shared->trajectory.publish(b.msg);
    EXPECT_TRUE(shared->warnings->seen(std::string("joint_trajectory dropped: ") + b.warning))
        << b.warning;
  }
  waitSimulated(0.5);
  const JointSample after = shared->joints->latest();
  for (const char* joint : {"shoulder", "slide", "slide_follower"}) {
    EXPECT_NEAR(after.positions.at(joint), before.positions.at(joint), 1e-3) << joint;
  }
  // No command topic for a mimic follower or a fixed joint: nobody listens there.
  for (const char* topic : {"slide_follower/command", "tool_mount/command"}) {
    ros::Publisher unheard = shared->ros->nh.advertise<std_msgs::Float64>(topic, 1);
    ros::WallDuration(0.5).sleep();
    EXPECT_EQ(unheard.getNumSubscribers(), 0u) << topic;
  }
}

// A client repeating a refused request: every answer says why, while the log does not get a
// line per call. Each refusal is in the log either as a line with its reason or in a count of
// refusals not logged ("N more set_joint_command requests refused"), which the node sends
// once a second has passed since the service's last line. No other test here has
// set_joint_command refused, so every refusal of the service counted is one of these.
TEST(JointCommands, RefusedRequestsAreAllAnsweredButNotLoggedOneLineEach) {
  const int kRequests = 200;
  shared->warnings->clear();
  pfx::SetJointCommand srv;
  srv.request.names = {"nope"};
  srv.request.mode = pfx::SetJointCommand::Request::POSITION;
  srv.request.targets = {0.1};
  int answered = 0;
  for (int i = 0; i < kRequests; ++i) {
    const pfx::SetJointCommand::Response res = call("pfx_node/set_joint_command", srv).response;
    EXPECT_FALSE(res.success);
    if (res.message == "unknown joint 'nope'") ++answered;
  }
  EXPECT_EQ(answered, kRequests);
  // Until every refusal is accounted for by a line or a count; /rosout carries the node's
  // lines in order, so nothing is still to come after that.
  const std::string service = "set_joint_command";
  auto countOf = [&](const std::string& line) {
    const std::string::size_type more = line.find(" more " + service + " requests refused");
    if (more == std::string::npos) return 0L;
    const std::string::size_type start = line.find_last_not_of("0123456789", more - 1) + 1;
    return std::stol(line.substr(start, more - start));
  };
  long logged = 0, counted = 0;
  std::vector<std::string> lines;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (logged + counted < kRequests && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.1).sleep();
    lines = shared->warnings->holding(service);
    logged = counted = 0;
    for (const std::string& line : lines) {
      if (line.find(service + " rejected: unknown joint 'nope'") != std::string::npos) ++logged;
      counted += countOf(line);
    }
  }
  std::printf("%d refused requests: %ld logged with their reason, %ld counted, in %zu lines\n",
              kRequests, logged, counted, lines.size());
  EXPECT_EQ(logged + counted, kRequests);
  EXPECT_GE(logged, 1);
  EXPECT_LT(lines.size(), std::size_t(kRequests));
}

// A publisher of bad messages at 100 Hz: each is dropped, and the log has its warning once a
// second with the count of its repeats, not a line each.
TEST(JointCommands, RepeatedBadMessagesAreWarnedOfOnceASecondWithACount) {
  const int kMessages = 100;
  const std::string warning = "joint_trajectory dropped: no points";
  shared->warnings->clear();
  for (int i = 0; i < kMessages; ++i) {
    shared->trajectory.publish(trajectory({"shoulder"}, {}));
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(shared->warnings->seen(warning));
  // Once the second after the last message is over, its repeats have been counted too.
  ros::WallDuration(2.0).sleep();
  const std::vector<std::string> lines = shared->warnings->holding(warning);
  // A line is one message, or a count of the repeats since the last line.
  long logged = 0, counted = 0;
  for (const std::string& line : lines) {
    const std::string::size_type more = line.find(" more time");
    if (more == std::string::npos) {
      ++logged;
      continue;
    }
    const std::string::size_type start = line.find_last_not_of("0123456789", more - 1) + 1;
    counted += std::stol(line.substr(start, more - start));
  }
  std::printf("%d bad trajectories in 1 s: %zu lines, %ld logged, %ld repeats counted\n",
              kMessages, lines.size(), logged, counted);
  // About two seconds of lines; the transport may drop a message when the node falls behind.
  EXPECT_LE(lines.size(), 4u);
  EXPECT_GE(logged, 1);
  EXPECT_LE(logged + counted, kMessages);
  EXPECT_GE(logged + counted, kMessages / 2);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_joint_commands");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.clock = std::make_unique<pfx_test::ClockWatcher>(state.ros->nh);
  state.joints = std::make_unique<JointWatcher>(state.ros->nh);
  state.warnings = std::make_unique<WarningWatcher>(state.ros->nh);
  ros::NodeHandle& nh = state.ros->nh;
  for (const char* joint : {"shoulder", "slide", "wheel_joint"}) {
    state.commands[joint] = nh.advertise<std_msgs::Float64>(std::string(joint) + "/command", 1);
  }
  state.group = nh.advertise<std_msgs::Float64MultiArray>("pfx_node/joint_group_command", 1);
  state.trajectory = nh.advertise<trajectory_msgs::JointTrajectory>("pfx_node/joint_trajectory", 10);
  shared = &state;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  auto connected = [&] {
    for (const auto& [joint, publisher] : state.commands) {
      if (publisher.getNumSubscribers() == 0) return false;
    }
    return state.group.getNumSubscribers() > 0 && state.trajectory.getNumSubscribers() > 0 &&
           state.joints->connected() && state.clock->connected() &&
           state.joints->latest().stamp > 0 &&
           pfx_test::waitForServices({"pfx_node/set_joint_command"}, 1);
  };
  while (!connected()) {
    if (ros::WallTime::now() > deadline) {
      ROS_FATAL("no connection to the node's command topics, joint_states or /clock");
      return 1;
    }
    ros::WallDuration(0.02).sleep();
  }
  // A trajectory naming no joint is dropped, changing nothing, with a warning every time:
  // asked for until it is heard, it shows that the node's /rosout reaches the test.
  while (!state.warnings->seen("joint_trajectory dropped: no joint_names", 0.2)) {
    if (ros::WallTime::now() > deadline) {
      ROS_FATAL("no warning of the node heard on /rosout");
      return 1;
    }
    state.trajectory.publish(trajectory({}, {}));
  }
  state.warnings->clear();
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
