// Contact and force-torque sensors of the real node (sensor_joints.test): the hinge holding
// a 2 kg pendulum at rest transmits its weight, the 3 kg pad resting on the ground touches it
// with its weight's impulse per step, its contacts are published when they change (not every
// step while it rests), and lifting the pad empties them; an IMU on the pad reads +g while it
// rests and the lift's force over its mass while it rises.
#include <geometry_msgs/WrenchStamped.h>
#include <sensor_msgs/Imu.h>

#include <mutex>

#include "pfx/ApplyBodyWrench.h"
#include "pfx/ContactsStamped.h"
#include "pfx_ros_test_util.h"

namespace {

const std::string kNode = "/pfx_node/";
const double kG = 9.80665;
const double kDt = 0.004;
pfx_test::RosClient* client = nullptr;

template <typename Msg>
class Recorder {
 public:
  explicit Recorder(const std::string& topic)
      : m_sub(client->nh.subscribe(topic, 1000, &Recorder::onMessage, this)) {}
  std::vector<Msg> all() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_messages;
  }
  bool waitFor(std::size_t count, double wallSeconds) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (all().size() < count) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
    return true;
  }

 private:
  void onMessage(const Msg& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_messages.push_back(msg);
  }
  mutable std::mutex m_mutex;
  std::vector<Msg> m_messages;
  ros::Subscriber m_sub;
};

double totalImpulse(const pfx::ContactsStamped& msg) {
  double sum = 0;
  for (const pfx::Contact& c : msg.contacts) sum += c.impulse;
  return sum;
}

}  // namespace

TEST(SensorJoints, TheHingeTransmitsThePendulumsWeight) {
  pfx_test::ClockWatcher clock(client->nh);
  ASSERT_TRUE(clock.waitUntil(1.0, 30));  // the pendulum has settled
  Recorder<geometry_msgs::WrenchStamped> down("/hinge_wrench");
  Recorder<geometry_msgs::WrenchStamped> up("/hinge_on_post");
  ASSERT_TRUE(down.waitFor(5, 20));
  ASSERT_TRUE(up.waitFor(5, 20));
  const std::vector<geometry_msgs::WrenchStamped> got = down.all();
  const geometry_msgs::WrenchStamped& w = got.back();
  EXPECT_EQ(w.header.frame_id, "pendulum");
  std::printf(
      "hinge_wrench (parent on child): force (%.4f, %.4f, %.4f) N, torque (%.2g, %.2g, "
      "%.2g) N m\n",
      w.wrench.force.x, w.wrench.force.y, w.wrench.force.z, w.wrench.torque.x, w.wrench.torque.y,
      w.wrench.torque.z);
  // The post holds the pendulum up with its weight, 2 kg x g, and no torque about the hinge.
  EXPECT_NEAR(w.wrench.force.z, 2 * kG, 0.02 * 2 * kG);
  EXPECT_NEAR(w.wrench.force.x, 0, 0.05);
  EXPECT_NEAR(w.wrench.force.y, 0, 0.05);
  EXPECT_NEAR(w.wrench.torque.x, 0, 0.02);
  EXPECT_NEAR(w.wrench.torque.y, 0, 0.02);
  // 50 Hz of simulated time.
  EXPECT_NEAR((got[got.size() - 1].header.stamp - got[got.size() - 2].header.stamp).toSec(), 0.02,
              1e-6);
  // child_to_parent reads the same wrench the other way.
  const geometry_msgs::WrenchStamped u = up.all().back();
  EXPECT_NEAR(u.wrench.force.z, -2 * kG, 0.02 * 2 * kG);
}

TEST(SensorJoints, ThePadsBumperAndImuFollowItsRestAndLift) {
  pfx_test::ClockWatcher clock(client->nh);
  ASSERT_TRUE(clock.waitUntil(1.0, 30));
  // Latched: the last message comes at once, whenever it was published.
  Recorder<pfx::ContactsStamped> contacts("/pad_contacts");
  Recorder<sensor_msgs::Imu> imu("/pad_imu");
  ASSERT_TRUE(contacts.waitFor(1, 10));
  const pfx::ContactsStamped resting = contacts.all().back();
  EXPECT_EQ(resting.link, "pad");
  ASSERT_FALSE(resting.contacts.empty());
  for (const pfx::Contact& c : resting.contacts) {
    EXPECT_EQ(c.link_a, "pad");
    EXPECT_EQ(c.link_b, "ground");
    EXPECT_NEAR(c.normal.z, -1, 1e-3);  // from the pad down into the ground
  }
  std::printf("pad at rest: %zu points, impulse %.5f N s in a step (3 kg x g x dt = %.5f)\n",
              resting.contacts.size(), totalImpulse(resting), 3 * kG * kDt);
  EXPECT_NEAR(totalImpulse(resting), 3 * kG * kDt, 0.05 * 3 * kG * kDt);

  // Resting, the points stay put: over 1 s of simulated time (250 steps) few messages come.
  const double start = clock.now();
  ASSERT_TRUE(clock.waitUntil(start + 1.0, 30));
  const std::size_t whileResting = contacts.all().size() - 1;
  std::printf("messages while resting for 1 s: %zu\n", whileResting);
  EXPECT_LT(whileResting, 10u);

  // On the ground the pad's IMU reads the ground's push: +g.
  ASSERT_TRUE(imu.waitFor(50, 10));
  const std::vector<sensor_msgs::Imu> restingImu = imu.all();
  double restZ = 0;
  for (std::size_t i = restingImu.size() - 50; i < restingImu.size(); ++i) {
    restZ += restingImu[i].linear_acceleration.z / 50;
    EXPECT_NEAR(restingImu[i].linear_acceleration.x, 0, 0.01);
    EXPECT_NEAR(restingImu[i].linear_acceleration.y, 0, 0.01);
  }
  std::printf("pad IMU at rest on the ground: mean z %.5f m/s^2 over 50 steps\n", restZ);
  EXPECT_NEAR(restZ, kG, 0.01);
  const std::size_t beforeLift = imu.all().size();

  // Lifted by 60 N against its 29.4 N weight for 0.5 s, the pad leaves the ground, and an
  // empty list says so. Meanwhile the IMU reads the lift's force over the mass, 20 m/s^2
  // (the free slider pushes nothing along its axis).
  pfx::ApplyBodyWrench lift;
  lift.request.link = "pad";
  lift.request.force.z = 60;
  lift.request.duration = 0.5;
  lift = pfx_test::call(kNode + "apply_body_wrench", lift);
  ASSERT_TRUE(lift.response.success) << lift.response.message;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20);
  bool emptied = false;
  while (!emptied && ros::WallTime::now() < deadline) {
    for (const auto& msg : contacts.all()) emptied = emptied || msg.contacts.empty();
    ros::WallDuration(0.01).sleep();
  }
  EXPECT_TRUE(emptied) << "no empty contact list after the lift";
  ASSERT_TRUE(clock.waitUntil(clock.now() + 0.6, 30));
  const std::vector<sensor_msgs::Imu> lifted = imu.all();
  double sum = 0;
  int rising = 0;
  for (std::size_t i = beforeLift; i < lifted.size(); ++i) {
    if (lifted[i].linear_acceleration.z < 15) continue;
    sum += lifted[i].linear_acceleration.z;
    ++rising;
  }
  ASSERT_GT(rising, 50);  // of the lift's 125 steps
  std::printf("pad IMU while lifted: mean z %.4f m/s^2 over %d steps (60 N / 3 kg = 20)\n",
              sum / rising, rising);
  EXPECT_NEAR(sum / rising, 20, 0.2);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_sensor_joints");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  if (!pfx_test::waitForServices({kNode + "apply_body_wrench"}, 60)) {
    ADD_FAILURE() << "pfx_node's services did not come up";
    return 1;
  }
  return RUN_ALL_TESTS();
}
