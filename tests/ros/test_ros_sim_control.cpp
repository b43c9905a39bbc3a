// rostest (sim_control.test): a node started paused takes exactly the steps ~step asks for
// and no more, /clock, /joint_states and TF carrying the time after them; ~step is refused
// while running and for a count out of 1 .. 10000. ~set_physics refuses every bad value,
// naming the field, with nothing changed (as ~get_physics and the clock show), and its good
// values take effect from the next step: the time step of the steps, the pace of the clock
// (real-time factor), the gravity the robot falls in; ~reset keeps them. After ~reset the
// clock goes on: TF carries no stamp twice, and a world saved after it holds the time since
// the start.
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <limits>
#include <mutex>
#include <set>

#include "pfx/GetPhysics.h"
#include "pfx/SetPhysics.h"
#include "pfx/Step.h"
#include "pfx/WorldFile.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// The stamp of the latest /joint_states, in seconds (negative before the first).
class JointStampWatcher {
 public:
  explicit JointStampWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/joint_states", 100, &JointStampWatcher::onState, this)) {}
  double stamp() const { return m_stamp.load(); }
  bool connected() const { return m_sub.getNumPublishers() > 0; }

 private:
  void onState(const sensor_msgs::JointState& msg) { m_stamp.store(msg.header.stamp.toSec()); }
  ros::Subscriber m_sub;
  std::atomic<double> m_stamp{-1.0};
};

// Every stamp /tf has carried for one frame since the last clear().
class TfStamps {
 public:
  TfStamps(ros::NodeHandle& nh, const std::string& frame)
      : m_frame(frame), m_sub(nh.subscribe("/tf", 100, &TfStamps::onTf, this)) {}
  bool connected() const { return m_sub.getNumPublishers() > 0; }
  void clear() {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stamps.clear();
  }
  std::vector<double> stamps() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_stamps;
  }

 private:
  void onTf(const tf2_msgs::TFMessage& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const geometry_msgs::TransformStamped& t : msg.transforms) {
      if (t.child_frame_id == m_frame) m_stamps.push_back(t.header.stamp.toSec());
    }
  }
  std::string m_frame;
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::vector<double> m_stamps;
};

struct Shared {
  std::unique_ptr<pfx_test::RosClient> ros;
  std::unique_ptr<pfx_test::ClockWatcher> clock;
  std::unique_ptr<JointStampWatcher> joints;
  std::unique_ptr<TfStamps> armStamps;
};
Shared* shared = nullptr;

pfx::Step::Response step(int steps) {
  pfx::Step srv;
  srv.request.steps = steps;
  return call(kNode + "step", srv).response;
}

pfx::Physics getPhysics() { return call(kNode + "get_physics", pfx::GetPhysics()).response.physics; }

pfx::SetPhysics::Response setPhysics(const pfx::Physics& physics) {
  pfx::SetPhysics srv;
  srv.request.physics = physics;
  return call(kNode + "set_physics", srv).response;
}

bool trigger(const std::string& service) {
  return call(kNode + service, std_srvs::Trigger()).response.success;
}

void expectSamePhysics(const pfx::Physics& a, const pfx::Physics& b, const std::string& what) {
  EXPECT_EQ(a.dt, b.dt) << what;
  EXPECT_EQ(a.substeps, b.substeps) << what;
  EXPECT_EQ(a.iterations, b.iterations) << what;
  EXPECT_EQ(a.gravity.x, b.gravity.x) << what;
  EXPECT_EQ(a.gravity.y, b.gravity.y) << what;
  EXPECT_EQ(a.gravity.z, b.gravity.z) << what;
  EXPECT_EQ(a.real_time_factor, b.real_time_factor) << what;
}

// The clock, /joint_states and the robot's TF all reach `time` (s), within wallSeconds.
void expectStateAt(double time, double wallSeconds = 5) {
  EXPECT_TRUE(shared->clock->waitUntil(time - 1e-9, wallSeconds));
  EXPECT_NEAR(shared->clock->now(), time, 1e-9);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
  while (shared->joints->stamp() < time - 1e-9 && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.01).sleep();
  }
  EXPECT_NEAR(shared->joints->stamp(), time, 1e-9);
  geometry_msgs::TransformStamped arm;
  bool atTime = false;
  while (!atTime && ros::WallTime::now() < deadline) {
    atTime = pfx_test::lookup(shared->ros->tfBuffer, "world", "arm", arm, 1) &&
             std::abs(arm.header.stamp.toSec() - time) < 1e-9;
    if (!atTime) ros::WallDuration(0.01).sleep();
  }
  EXPECT_TRUE(atTime) << "TF of arm at " << arm.header.stamp.toSec() << " s, not " << time;
}

TEST(SimControl, StepTakesExactlyTheStepsAskedFor) {
  const pfx::Physics physics = getPhysics();
  EXPECT_NEAR(physics.dt, 0.004, 1e-9);
  EXPECT_EQ(physics.substeps, 1);
  EXPECT_EQ(physics.iterations, 10);
  EXPECT_NEAR(physics.gravity.z, -9.80665, 1e-5);
  EXPECT_EQ(physics.real_time_factor, 1.0);

  const pfx::Step::Response first = step(1);
  ASSERT_TRUE(first.success) << first.message;
  EXPECT_EQ(first.steps_done, 1);
  EXPECT_NEAR(first.time, physics.dt, 1e-12);
  expectStateAt(first.time);

  const pfx::Step::Response more = step(25);
  ASSERT_TRUE(more.success) << more.message;
  EXPECT_EQ(more.steps_done, 25);
  EXPECT_NEAR(more.time - first.time, 25 * physics.dt, 1e-9);
  expectStateAt(more.time);
  // Paused: nothing moves after the answer.
  ros::WallDuration(0.3).sleep();
  EXPECT_NEAR(shared->clock->now(), more.time, 1e-9);

  for (const int bad : {0, -1, 10001}) {
    const pfx::Step::Response refused = step(bad);
    EXPECT_FALSE(refused.success) << bad;
    EXPECT_NE(refused.message.find("steps " + std::to_string(bad)), std::string::npos)
        << refused.message;
    EXPECT_EQ(refused.steps_done, 0);
    EXPECT_NEAR(refused.time, more.time, 1e-12);
  }
  const pfx::Step::Response most = step(10000);
  ASSERT_TRUE(most.success) << most.message;
  EXPECT_NEAR(most.time - more.time, 10000 * physics.dt, 1e-6);
  expectStateAt(most.time);

  ASSERT_TRUE(trigger("unpause"));
  const pfx::Step::Response running = step(1);
  EXPECT_FALSE(running.success);
  EXPECT_NE(running.message.find("running"), std::string::npos) << running.message;
  ASSERT_TRUE(trigger("pause"));
}

TEST(SimControl, SetPhysicsRefusesEveryBadValueAndChangesNothing) {
  const pfx::Physics before = getPhysics();
  const double timeBefore = step(1).time;
  struct Case {
    const char* field;
    void (*spoil)(pfx::Physics&);
  };
  const Case cases[] = {
      {"dt", [](pfx::Physics& p) { p.dt = kNaN; }},
      {"dt", [](pfx::Physics& p) { p.dt = kInf; }},
      {"dt", [](pfx::Physics& p) { p.dt = 0; }},
      {"dt", [](pfx::Physics& p) { p.dt = -0.004; }},
      {"dt", [](pfx::Physics& p) { p.dt = 0.2; }},
      {"substeps", [](pfx::Physics& p) { p.substeps = 0; }},
      {"substeps", [](pfx::Physics& p) { p.substeps = -2; }},
      {"substeps", [](pfx::Physics& p) { p.substeps = 101; }},
      {"iterations", [](pfx::Physics& p) { p.iterations = 0; }},
      {"iterations", [](pfx::Physics& p) { p.iterations = -3; }},
      {"iterations", [](pfx::Physics& p) { p.iterations = 1000000; }},
      {"gravity", [](pfx::Physics& p) { p.gravity.x = kNaN; }},
      {"gravity", [](pfx::Physics& p) { p.gravity.z = -kInf; }},
      {"gravity", [](pfx::Physics& p) { p.gravity.y = 2000; }},
      {"real_time_factor", [](pfx::Physics& p) { p.real_time_factor = -1; }},
      {"real_time_factor", [](pfx::Physics& p) { p.real_time_factor = kNaN; }},
      {"real_time_factor", [](pfx::Physics& p) { p.real_time_factor = kInf; }},
  };
  // Every other field changed to a good value, so that a partial change would show.
  pfx::Physics good = before;
  good.dt = 0.002;
  good.substeps = 3;
  good.iterations = 7;
  good.gravity.z = -1.62;
  good.real_time_factor = 2;
  for (const Case& c : cases) {
    pfx::Physics asked = good;
    c.spoil(asked);
    const pfx::SetPhysics::Response res = setPhysics(asked);
    EXPECT_FALSE(res.success) << c.field;
    EXPECT_EQ(res.message.rfind(c.field, 0), 0u) << "names " << c.field << ": " << res.message;
    expectSamePhysics(res.physics, before, res.message);
    expectSamePhysics(getPhysics(), before, res.message);
  }
  // The clock still runs at the old time step.
  const pfx::Step::Response after = step(10);
  EXPECT_NEAR(after.time - timeBefore, 10 * before.dt, 1e-9);
}

TEST(SimControl, SetPhysicsTakesEffectFromTheNextStep) {
  const pfx::Physics before = getPhysics();
  pfx::Physics asked = before;
  asked.dt = 0.002;
  asked.substeps = 2;
  asked.iterations = 20;
  asked.gravity.x = 0;
  asked.gravity.y = 0;
  asked.gravity.z = 0;
  asked.real_time_factor = 0.5;
  const pfx::SetPhysics::Response res = setPhysics(asked);
  ASSERT_TRUE(res.success) << res.message;
  // dt may be rounded to the library's float.
  EXPECT_NEAR(res.physics.dt, 0.002, 1e-9);
  EXPECT_EQ(res.physics.substeps, 2);
  EXPECT_EQ(res.physics.iterations, 20);
  EXPECT_EQ(res.physics.gravity.z, 0.0);
  EXPECT_EQ(res.physics.real_time_factor, 0.5);
  expectSamePhysics(getPhysics(), res.physics, "get after set");

  const double t0 = step(1).time;
  const pfx::Step::Response tenMore = step(10);
  ASSERT_TRUE(tenMore.success);
  EXPECT_NEAR(tenMore.time - t0, 10 * res.physics.dt, 1e-9);
  expectStateAt(tenMore.time);

  // Half the real-time factor: about 0.5 s of simulated time per second of wall time.
  const double simStart = shared->clock->now();
  ASSERT_TRUE(trigger("unpause"));
  const ros::WallTime wallStart = ros::WallTime::now();
  ros::WallDuration(2.0).sleep();
  ASSERT_TRUE(trigger("pause"));
  const double wall = (ros::WallTime::now() - wallStart).toSec();
  ros::WallDuration(0.2).sleep();
  const double pace = (shared->clock->now() - simStart) / wall;
  std::printf("real-time factor asked 0.5, reached %.3f over %.2f s of wall time\n", pace, wall);
  EXPECT_GT(pace, 0.35);
  EXPECT_LT(pace, 0.55);

  // Gravity up: the robot, asleep on the ground, wakes and leaves it.
  geometry_msgs::TransformStamped start, end;
  asked.gravity.z = 9.80665;
  asked.real_time_factor = 1;
  ASSERT_TRUE(setPhysics(asked).success);
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "world", "base", start));
  const pfx::Step::Response up = step(250);  // 0.5 s
  ASSERT_TRUE(up.success);
  expectStateAt(up.time);
  ASSERT_TRUE(pfx_test::lookup(shared->ros->tfBuffer, "world", "base", end));
  // z = g t^2 / 2 = 1.2 m after 0.5 s.
  EXPECT_GT(end.transform.translation.z - start.transform.translation.z, 0.8);

  // ~reset puts the bodies back, not the physics.
  const pfx::Physics set = getPhysics();
  ASSERT_TRUE(trigger("reset"));
  expectSamePhysics(getPhysics(), set, "after reset");
  const double t1 = step(1).time;
  EXPECT_NEAR(step(4).time - t1, 4 * set.dt, 1e-9);
}

pfx::WorldFile::Response worldFile(const std::string& service, const std::string& path) {
  pfx::WorldFile srv;
  srv.request.path = path;
  return call(kNode + service, srv).response;
}

TEST(SimControl, ResetRepeatsNoTfStampAndTheWorldsClockGoesOn) {
  const double dt = getPhysics().dt;
  shared->armStamps->clear();
  const double before = step(10).time;
  expectStateAt(before);
  ASSERT_TRUE(trigger("reset"));
  // Paused: a reset state published at once would carry the stamp already sent.
  ros::WallDuration(0.3).sleep();
  const pfx::Step::Response after = step(1);
  ASSERT_TRUE(after.success) << after.message;
  EXPECT_NEAR(after.time - before, dt, 1e-9);
  expectStateAt(after.time);
  const std::vector<double> stamps = shared->armStamps->stamps();
  EXPECT_EQ(std::set<double>(stamps.begin(), stamps.end()).size(), stamps.size())
      << "TF sent one stamp of arm twice (TF_REPEATED_DATA): " << stamps.size() << " stamps";

  // Saved one step after the reset, the world holds the node's time, not one step.
  const std::string path = "/tmp/pfx_sim_control_" + std::to_string(::getpid()) + ".pfxw";
  const pfx::WorldFile::Response saved = worldFile("save_world", path);
  ASSERT_TRUE(saved.success) << saved.message;
  step(5);
  const pfx::WorldFile::Response loaded = worldFile("load_world", path);
  ASSERT_TRUE(loaded.success) << loaded.message;
  EXPECT_NEAR(step(1).time, after.time + dt, 1e-6) << loaded.message;
  std::remove(path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_sim_control");
  Shared state;
  state.ros = std::make_unique<pfx_test::RosClient>();
  state.clock = std::make_unique<pfx_test::ClockWatcher>(state.ros->nh);
  state.joints = std::make_unique<JointStampWatcher>(state.ros->nh);
  state.armStamps = std::make_unique<TfStamps>(state.ros->nh, "arm");
  shared = &state;
  if (!pfx_test::waitForServices(
          {kNode + "step", kNode + "set_physics", kNode + "get_physics", kNode + "reset"}, 30.0)) {
    ROS_FATAL("the pfx_node services did not appear");
    return 1;
  }
  // The node publishes nothing while paused: the first ~step's state is seen only by
  // subscribers connected before it.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (!(state.joints->connected() && state.clock->connected() &&
           state.armStamps->connected())) {
    if (ros::WallTime::now() > deadline) {
      ROS_FATAL("no connection to the node's /joint_states, /clock or /tf");
      return 1;
    }
    ros::WallDuration(0.02).sleep();
  }
  const int result = RUN_ALL_TESTS();
  shared = nullptr;
  return result;
}
