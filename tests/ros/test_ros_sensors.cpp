// Sensors of the real node (sensors.test): the TurtleBot3 burger's own laser (/scan, noisy,
// 5 Hz) and IMU (/imu) from its <gazebo> blocks, and from ~sensors a noiseless copy of the
// laser (/scan_exact), a 16-row lidar (/points), ground-truth odometry (/odom_truth) and a
// depth camera facing the scene's wall (/depth_cam/...).
// With the simulation paused, every beam is compared with the node's own raycast service;
// then pfx_node is started again with each kind of bad sensor configuration and must refuse
// it, saying why.
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>

#include <Eigen/Geometry>
#include <cstring>
#include <mutex>

#include "pfx/RaycastBatch.h"
#include "pfx_ros_test_util.h"

namespace {

const std::string kNode = "/pfx_node/";
pfx_test::RosClient* client = nullptr;

// The messages of a topic, newest last (at most `keep`).
template <typename Msg>
class Recorder {
 public:
  Recorder(const std::string& topic, std::size_t keep)
      : m_keep(keep), m_sub(client->nh.subscribe(topic, 100, &Recorder::onMessage, this)) {}
  std::vector<Msg> all() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_messages;
  }
  // Waits until at least `count` messages came; false after `wallSeconds`.
  bool waitFor(std::size_t count, double wallSeconds) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (received() < count) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
    return true;
  }
  Msg latest() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_messages.back();
  }

 private:
  std::size_t received() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_count;
  }
  void onMessage(const Msg& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_messages.push_back(msg);
    if (m_messages.size() > m_keep) m_messages.erase(m_messages.begin());
    ++m_count;
  }
  mutable std::mutex m_mutex;
  std::vector<Msg> m_messages;
  std::size_t m_count = 0;
  std::size_t m_keep;
  ros::Subscriber m_sub;
};

bool trigger(const std::string& name) {
  return pfx_test::call(kNode + name, std_srvs::Trigger()).response.success;
}

Eigen::Isometry3d sensorPose(const std::string& frame) {
  geometry_msgs::TransformStamped t;
  EXPECT_TRUE(pfx_test::lookup(client->tfBuffer, "world", frame, t));
  const auto& r = t.transform.rotation;
  const auto& p = t.transform.translation;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p.x, p.y, p.z);
  return pose;
}

// The range that the raycast service gives for a beam along `beam` (sensor frame; a unit
// vector gives metres) of a sensor at `pose` covering [rangeMin, rangeMax] beam lengths, as
// the node's scans cast it; +inf on a miss.
std::vector<double> raycastRanges(const Eigen::Isometry3d& pose,
                                  const std::vector<Eigen::Vector3d>& beams, double rangeMin,
                                  double rangeMax) {
  pfx::RaycastBatch srv;
  for (const Eigen::Vector3d& beam : beams) {
    const Eigen::Vector3d world = pose.linear() * beam;
    const Eigen::Vector3d start = pose.translation() + world * rangeMin;
    const Eigen::Vector3d span = world * (rangeMax - rangeMin);
    geometry_msgs::Point origin;
    origin.x = start.x();
    origin.y = start.y();
    origin.z = start.z();
    geometry_msgs::Vector3 direction;
    direction.x = span.x();
    direction.y = span.y();
    direction.z = span.z();
    srv.request.origins.push_back(origin);
    srv.request.directions.push_back(direction);
  }
  srv = pfx_test::call(kNode + "raycast_batch", srv);
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  std::vector<double> ranges;
  for (std::size_t i = 0; i < beams.size() && i < srv.response.hit.size(); ++i) {
    ranges.push_back(srv.response.hit[i]
                         ? rangeMin + srv.response.fractions[i] * (rangeMax - rangeMin)
                         : std::numeric_limits<double>::infinity());
  }
  return ranges;
}

std::vector<Eigen::Vector3d> scanBeams(const sensor_msgs::LaserScan& scan) {
  std::vector<Eigen::Vector3d> beams;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double angle = scan.angle_min + double(i) * scan.angle_increment;
    beams.emplace_back(std::cos(angle), std::sin(angle), 0);
  }
  return beams;
}

// Runs pfx_node in namespace `ns` (its parameters set there beforehand) and returns what it
// logged; it must exit by itself, refusing its configuration, within 30 s.
std::string runRefusedNode(const std::string& ns, int& status) {
  return pfx_test::runCommand(
      "timeout 30 " PFX_NODE " __ns:=" + ns + " __name:=pfx_node 2>&1", status);
}

}  // namespace

// Runs first, while the simulation runs: rates and stamps in simulated time.
TEST(Sensors, TheTurtleBotsLaserScansAtFiveHertzOfSimulatedTime) {
  Recorder<sensor_msgs::LaserScan> scans("/scan", 10);
  ASSERT_TRUE(scans.waitFor(4, 30));
  const std::vector<sensor_msgs::LaserScan> got = scans.all();
  const sensor_msgs::LaserScan& scan = got.back();
  EXPECT_EQ(scan.header.frame_id, "base_scan");
  EXPECT_EQ(scan.ranges.size(), 360u);
  EXPECT_FLOAT_EQ(scan.range_min, 0.12f);
  EXPECT_FLOAT_EQ(scan.range_max, 3.5f);
  EXPECT_FLOAT_EQ(scan.angle_min, 0.0f);
  EXPECT_FLOAT_EQ(scan.angle_max, 6.28319f);
  EXPECT_NEAR(scan.angle_increment, 6.28319 / 359, 1e-6);
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_NEAR((got[i].header.stamp - got[i - 1].header.stamp).toSec(), 0.2, 1e-6)
        << "scans " << i - 1 << " and " << i;
  }
  // Stamps are the simulated times of steps (dt 0.004 s).
  const double stamp = scan.header.stamp.toSec();
  EXPECT_NEAR(stamp / 0.004, std::round(stamp / 0.004), 1e-3);
}

TEST(Sensors, RangeSensorsAndDepthCameraEqualTheRaycastServiceAndTheNoiseIsAsDeclared) {
  Recorder<sensor_msgs::LaserScan> exact("/scan_exact", 200);
  Recorder<sensor_msgs::LaserScan> noisy("/scan", 10);
  Recorder<sensor_msgs::PointCloud2> clouds("/points", 2);
  Recorder<sensor_msgs::Image> depthImages("/depth_cam/depth/image_raw", 2);
  Recorder<sensor_msgs::CameraInfo> cameraInfos("/depth_cam/depth/camera_info", 2);
  Recorder<sensor_msgs::PointCloud2> depthClouds("/depth_cam/points", 2);
  pfx_test::ClockWatcher clock(client->nh);
  // The ball of the scene has fallen and everything lies still.
  ASSERT_TRUE(clock.waitUntil(3.0, 60));
  ASSERT_TRUE(noisy.waitFor(1, 10));
  ASSERT_TRUE(trigger("pause"));
  ros::WallDuration(1.0).sleep();  // what was published before the pause arrives
  const double pausedAt = clock.now();

  // The exact laser is cast every step: its last scan is of the paused world.
  const sensor_msgs::LaserScan scan = exact.latest();
  EXPECT_NEAR(scan.header.stamp.toSec(), pausedAt, 1e-6);
  const Eigen::Isometry3d pose = sensorPose("base_scan");
  // One ~raycast call per beam, as a user would cast it.
  std::vector<double> expected;
  for (const Eigen::Vector3d& beam : scanBeams(scan)) {
    const Eigen::Vector3d world = pose.linear() * beam;
    const Eigen::Vector3d start = pose.translation() + world * double(scan.range_min);
    const Eigen::Vector3d span = world * double(scan.range_max - scan.range_min);
    const pfx::Raycast::Response hit = pfx_test::raycast(kNode + "raycast", start.x(), start.y(),
                                                         start.z(), span.x(), span.y(), span.z());
    ASSERT_TRUE(hit.success) << hit.message;
    expected.push_back(hit.hit ? scan.range_min + hit.distance
                               : std::numeric_limits<double>::infinity());
  }
  ASSERT_EQ(expected.size(), scan.ranges.size());
  double maxDifference = 0;
  int hits = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::isinf(expected[i])) {
      EXPECT_TRUE(std::isinf(scan.ranges[i]) && scan.ranges[i] > 0) << "beam " << i;
      continue;
    }
    ++hits;
    maxDifference = std::max(maxDifference, std::abs(scan.ranges[i] - expected[i]));
    EXPECT_NEAR(scan.ranges[i], expected[i], 1e-4) << "beam " << i;
  }
  EXPECT_GT(hits, 40);  // the wall, the crate and the ball
  std::printf("scan_exact: %d of %zu beams hit; largest difference from raycast %.3g m\n", hits,
              expected.size(), maxDifference);

  // The lidar: every point of its organised cloud against one batch of the same rays.
  const sensor_msgs::PointCloud2 cloud = clouds.latest();
  ASSERT_EQ(cloud.height, 16u);
  ASSERT_EQ(cloud.width, 64u);
  ASSERT_EQ(cloud.point_step, 12u);
  EXPECT_EQ(cloud.header.frame_id, "base_scan");
  std::vector<Eigen::Vector3d> beams;
  for (int v = 0; v < 16; ++v) {
    const double pitch = -0.26 + 0.52 * v / 15;
    for (int h = 0; h < 64; ++h) {
      const double yaw = -3.0 + 6.0 * h / 63;
      beams.emplace_back(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                         std::sin(pitch));
    }
  }
  const std::vector<double> lidarExpected = raycastRanges(pose, beams, 0.12, 10.0);
  ASSERT_EQ(lidarExpected.size(), 1024u);
  double lidarMax = 0;
  int lidarHits = 0;
  for (std::size_t i = 0; i < 1024; ++i) {
    float xyz[3];
    std::memcpy(xyz, &cloud.data[i * 12], sizeof(xyz));
    if (std::isinf(lidarExpected[i])) {
      EXPECT_TRUE(std::isnan(xyz[0])) << "point " << i;
      continue;
    }
    ++lidarHits;
    const Eigen::Vector3d point(xyz[0], xyz[1], xyz[2]);
    EXPECT_NEAR(point.norm(), lidarExpected[i], 1e-4) << "point " << i;
    EXPECT_LT((point.normalized() - beams[i]).norm(), 1e-5) << "point " << i;
    lidarMax = std::max(lidarMax, std::abs(point.norm() - lidarExpected[i]));
  }
  EXPECT_GT(lidarHits, 300);  // the lower rows all see the ground
  std::printf("lidar: %d of 1024 beams hit; largest difference from raycast %.3g m\n", lidarHits,
              lidarMax);

  // The TurtleBot's /scan: the same beams as scan_exact plus N(0, 0.01) on each return. Its
  // last scan (at most 0.2 s before the pause) is compared with scan_exact of the same step.
  const sensor_msgs::LaserScan noisyScan = noisy.latest();
  const std::vector<sensor_msgs::LaserScan> exacts = exact.all();
  const sensor_msgs::LaserScan* twin = nullptr;
  for (const auto& e : exacts) {
    if (e.header.stamp == noisyScan.header.stamp) twin = &e;
  }
  ASSERT_NE(twin, nullptr) << "no scan_exact at " << noisyScan.header.stamp;
  double sum = 0, sumSquares = 0;
  int n = 0;
  for (std::size_t i = 0; i < twin->ranges.size(); ++i) {
    // Returns near the limits may be clamped; the others show the noise as it is.
    if (!std::isfinite(twin->ranges[i]) || twin->ranges[i] > 3.4 || twin->ranges[i] < 0.2) {
      continue;
    }
    const double d = noisyScan.ranges[i] - twin->ranges[i];
    sum += d;
    sumSquares += d * d;
    ++n;
  }
  ASSERT_GT(n, 40);
  const double mean = sum / n, stddev = std::sqrt(sumSquares / n - mean * mean);
  std::printf("/scan noise over %d returns: mean %.4f m, stddev %.4f m (declared 0, 0.01)\n", n,
              mean, stddev);
  EXPECT_LT(std::abs(mean), 0.004);
  EXPECT_GT(stddev, 0.007);
  EXPECT_LT(stddev, 0.013);

  // The depth camera, turned a quarter turn to face the wall: every pixel's depth against the
  // raycast service along the line of sight that its camera info gives, and its cloud point.
  const sensor_msgs::Image image = depthImages.latest();
  const sensor_msgs::CameraInfo info = cameraInfos.latest();
  const sensor_msgs::PointCloud2 depthCloud = depthClouds.latest();
  ASSERT_EQ(image.encoding, "32FC1");
  ASSERT_EQ(image.width, 40u);
  ASSERT_EQ(image.height, 30u);
  ASSERT_EQ(info.width, 40u);
  ASSERT_EQ(depthCloud.width * depthCloud.height, 1200u);
  EXPECT_EQ(image.header.stamp, info.header.stamp);
  EXPECT_NEAR(image.header.stamp.toSec(), pausedAt, 1e-6);
  const double fx = info.K[0], cx = info.K[2], fy = info.K[4], cy = info.K[5];
  EXPECT_NEAR(fx, 20 / std::tan(0.6), 1e-4);
  EXPECT_EQ(fx, fy);
  const Eigen::Isometry3d camera = pose * Eigen::AngleAxisd(1.5707963, Eigen::Vector3d::UnitZ());
  std::vector<Eigen::Vector3d> sights;  // depth 1 along each pixel's line of sight
  for (int v = 0; v < 30; ++v) {
    for (int u = 0; u < 40; ++u) sights.emplace_back(1, -(u - cx) / fx, -(v - cy) / fy);
  }
  // Along a sight of depth 1 per unit, the "range" raycastRanges measures is the depth.
  const std::vector<double> depths = raycastRanges(camera, sights, 0.1, 8.0);
  ASSERT_EQ(depths.size(), 1200u);
  double depthMax = 0;
  int depthHits = 0;
  for (std::size_t i = 0; i < 1200; ++i) {
    float depth, xyz[3];
    std::memcpy(&depth, &image.data[i * 4], 4);
    std::memcpy(xyz, &depthCloud.data[i * 12], sizeof(xyz));
    if (std::isinf(depths[i])) {
      EXPECT_TRUE(std::isinf(depth)) << "pixel " << i;
      continue;
    }
    ++depthHits;
    const double expectedDepth = depths[i];
    EXPECT_NEAR(depth, expectedDepth, 1e-4) << "pixel " << i;
    EXPECT_NEAR(xyz[2], depth, 1e-6) << "pixel " << i;
    EXPECT_NEAR(xyz[0], (int(i % 40) - cx) / fx * depth, 1e-5) << "pixel " << i;
    depthMax = std::max(depthMax, std::abs(depth - expectedDepth));
  }
  EXPECT_GT(depthHits, 600);
  // The wall's face (y = 1.9) is square to the camera's axis, 1.9 m ahead: a pixel just above
  // the centre sees it at that depth, whatever the pixel.
  float centre;
  std::memcpy(&centre, &image.data[(14 * 40 + 20) * 4], 4);
  EXPECT_NEAR(centre, 1.9 - camera.translation().y(), 1e-4);
  std::printf("depth camera: %d of 1200 pixels hit; largest difference from raycast %.3g m\n",
              depthHits, depthMax);
  ASSERT_TRUE(trigger("unpause"));
}

TEST(Sensors, TheImuAtRestReadsGravityUpwardsAndNoRate) {
  Recorder<sensor_msgs::Imu> imus("/imu", 5);
  ASSERT_TRUE(imus.waitFor(5, 20));
  const sensor_msgs::Imu imu = imus.latest();
  EXPECT_EQ(imu.header.frame_id, "imu_link");
  std::printf(
      "imu at rest: linear_acceleration (%.6f, %.6f, %.6f), angular_velocity (%.2g, %.2g, "
      "%.2g)\n",
      imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z,
      imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z);
  EXPECT_NEAR(imu.linear_acceleration.x, 0, 1e-4);
  EXPECT_NEAR(imu.linear_acceleration.y, 0, 1e-4);
  EXPECT_NEAR(imu.linear_acceleration.z, 9.80665, 1e-4);
  EXPECT_NEAR(imu.angular_velocity.x, 0, 1e-6);
  EXPECT_NEAR(imu.angular_velocity.y, 0, 1e-6);
  EXPECT_NEAR(imu.angular_velocity.z, 0, 1e-6);
  EXPECT_NEAR(std::abs(imu.orientation.w), 1, 1e-6);
}

TEST(Sensors, OdometryIsTheLinksGroundTruth) {
  Recorder<nav_msgs::Odometry> odometry("/odom_truth", 10);
  ASSERT_TRUE(odometry.waitFor(3, 20));
  const std::vector<nav_msgs::Odometry> got = odometry.all();
  const nav_msgs::Odometry& odom = got.back();
  EXPECT_EQ(odom.header.frame_id, "world");
  EXPECT_EQ(odom.child_frame_id, "base_footprint");
  const Eigen::Isometry3d pose = sensorPose("base_footprint");
  EXPECT_NEAR(odom.pose.pose.position.x, pose.translation().x(), 1e-6);
  EXPECT_NEAR(odom.pose.pose.position.y, pose.translation().y(), 1e-6);
  EXPECT_NEAR(odom.pose.pose.position.z, 0, 1e-6);
  EXPECT_NEAR(odom.twist.twist.linear.x, 0, 1e-6);
  EXPECT_NEAR(odom.twist.twist.angular.z, 0, 1e-6);
  EXPECT_NEAR((got[got.size() - 1].header.stamp - got[got.size() - 2].header.stamp).toSec(), 0.02,
              1e-6);
}

TEST(Sensors, BadSensorConfigurationsAreRefusedWithTheirReason) {
  const std::string urdf = pfx_test::readText(PFX_SOURCE_DIR "/urdf/turtlebot3/turtlebot3_burger.urdf");
  ASSERT_FALSE(urdf.empty());
  auto ray = [](const std::string& extra) {
    return "[{name: bad, type: ray, link: base_scan, range_max: 2.0" + extra + "}]";
  };
  const struct {
    std::string sensors;   // YAML for ~sensors, or empty
    std::string from, to;  // a replacement in the URDF text, or empty
    std::string reason;
  } cases[] = {
      {ray(", range_min: -1.0"), "", "", "sensor 'bad': range min must not be negative"},
      {ray(", range_min: 3.0"), "", "", "sensor 'bad': range max must be above range min"},
      {ray(", horizontal_samples: 0"), "", "",
       "~sensors[0]: horizontal_samples must be a whole number >= 1"},
      {ray(", update_rate: 0"), "", "",
       "~sensors[0]: update_rate must be > 0 Hz (leave it out for every step)"},
      {ray(", horizontal_min_angle: 1.0, horizontal_max_angle: -1.0"), "", "",
       "sensor 'bad': a minimum scan angle is above its maximum"},
      {ray(", range_noise_stddev: -0.1"), "", "",
       "sensor 'bad': range noise stddev must not be negative"},
      {ray(", samples: 5"), "", "", "~sensors[0]: key 'samples' is not one a ray sensor takes"},
      {"[{name: bad, type: ray, link: tail, range_max: 2.0}]", "", "",
       "sensor 'bad': no link named 'tail'"},
      {"[{name: bad, type: camera, link: base_scan}]", "", "",
       "~sensors[0]: type 'camera' is none of ray, imu, odometry"},
      {"[{name: imu, type: imu, link: base_link}]", "", "",
       "sensor 'imu': another sensor has this name already"},
      {"[{name: other, type: imu, link: base_link, topic: scan}]", "", "",
       "sensor 'other': another sensor publishes on topic 'scan'"},
      {"[{name: ft, type: force_torque, joint: scan_joint}]", "", "",
       "sensor 'ft': joint 'scan_joint' is not a revolute, continuous or prismatic joint of its "
       "own in the world (fixed joints are lumped), so it reports no force"},
      {"[{name: cam, type: depth_camera, link: base_scan, horizontal_fov: 3.2}]", "", "",
       "sensor 'cam': the camera needs 1 to 4096 pixels each way, a field of view between 0 and "
       "pi, and 0 <= near < far, all finite"},
      {"[{name: ft, type: force_torque, joint: elbow}]", "", "",
       "sensor 'ft': no joint named 'elbow'"},
      {"[{name: ft, type: force_torque, joint: wheel_left_joint, measure_direction: up}]", "", "",
       "~sensors[0]: measure_direction 'up' is neither child_to_parent nor parent_to_child"},
      {"[{name: ft, type: force_torque, link: base_link}]", "", "",
       "~sensors[0]: key 'link' is not one a force_torque sensor takes"},
      {"", "<min>0.120</min>", "<min>-0.5</min>",
       "<gazebo reference='base_scan'> <sensor name='lds_lfcd_sensor'>: <sensor><ray><range><min>: "
       "must not be negative"},
      {"", "<max>3.5</max>", "<max>0.1</max>", "<sensor><ray><range><max>: must be above <min>"},
      {"", "<samples>360</samples>", "<samples>0</samples>",
       "<sensor><ray><scan><horizontal><samples>: must be a whole number from 1 to 1000000"},
      {"", "<update_rate>5</update_rate>", "<update_rate>0</update_rate>",
       "<sensor><update_rate>: must be > 0 Hz (leave it out for every step)"},
      {"", "<update_rate>5</update_rate>", "<update_rate>nan</update_rate>",
       "<sensor><update_rate>: is not a finite number"},
      {"", "<gazebo reference=\"base_scan\">", "<gazebo reference=\"base_scanner\">",
       "sensor 'lds_lfcd_sensor': no link named 'base_scanner'"},
  };
  int index = 0;
  for (const auto& c : cases) {
    const std::string ns = "/bad_sensors_" + std::to_string(index++);
    std::string text = urdf;
    if (!c.from.empty()) {
      const std::size_t at = text.find(c.from);
      ASSERT_NE(at, std::string::npos) << c.from;
      text.replace(at, c.from.size(), c.to);
    }
    ros::param::set(ns + "/robot_description", text);
    if (!c.sensors.empty()) {
      // rosparam reads YAML as the launch file's <rosparam> does.
      const std::string command = "rosparam set " + ns + "/pfx_node/sensors '" + c.sensors + "'";
      ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    int status = 0;
    const std::string output = runRefusedNode(ns, status);
    EXPECT_NE(status, 0) << ns << " was not refused:\n" << output;
    EXPECT_NE(output.find(c.reason), std::string::npos)
        << ns << ": expected '" << c.reason << "' in:\n"
        << output;
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_sensors");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  if (!pfx_test::waitForServices({kNode + "raycast_batch", kNode + "pause"}, 60)) {
    ADD_FAILURE() << "pfx_node's services did not come up";
    return 1;
  }
  return RUN_ALL_TESTS();
}
