// The <sensor> elements of URDF <gazebo> blocks (pfx_urdf_sensors.h): the TurtleBot3
// burger's description read unchanged, then each malformed value refused with the element
// that holds it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "pfx/loaders/pfx_urdf_sensors.h"

using namespace pfx;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A robot of two links whose laser block on link "head" holds `ray` in its <ray> and
// `extra` beside it.
std::string robotWithLaser(const std::string& ray, const std::string& extra = "",
                           const std::string& reference = "head") {
  return "<robot name='r'><link name='base'/><link name='head'/>"
         "<joint name='j' type='fixed'><parent link='base'/><child link='head'/></joint>"
         "<gazebo reference='" +
         reference + "'><sensor type='ray' name='laser'>" + extra + "<ray>" + ray +
         "</ray></sensor></gazebo></robot>";
}

const std::string kScan =
    "<scan><horizontal><samples>8</samples><min_angle>-1</min_angle><max_angle>1</max_angle>"
    "</horizontal></scan>";
const std::string kRange = "<range><min>0.1</min><max>5</max></range>";

// The load's error message, or "" when it loads.
std::string refusal(const std::string& urdf) {
  PfxUrdfSensors sensors;
  std::string message;
  return pfxLoadUrdfSensors(urdf, "robot.urdf", sensors, &message) == PFX_OK ? "" : message;
}

}  // namespace

TEST(UrdfSensors, TurtleBot3BurgerLoadsUnchanged) {
  const std::string urdf = readFile(PFX_SOURCE_DIR "/urdf/turtlebot3/turtlebot3_burger.urdf");
  ASSERT_FALSE(urdf.empty());
  PfxUrdfSensors out;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfSensors(urdf, "turtlebot3_burger.urdf", out, &message), PFX_OK) << message;
  ASSERT_EQ(out.sensors.size(), 2u);

  const PfxSensorSpec& imu = out.sensors[0];
  EXPECT_EQ(imu.name, "imu");
  EXPECT_EQ(imu.type, PfxSensorType::kImu);
  EXPECT_EQ(imu.link, "imu_link");
  EXPECT_EQ(imu.updateRate, 0);  // none given: every step
  EXPECT_EQ(imu.topic, "");      // the node's default: the sensor's name
  EXPECT_EQ(imu.angularVelocityNoise[0].stddev, 0);

  const PfxSensorSpec& laser = out.sensors[1];
  EXPECT_EQ(laser.name, "lds_lfcd_sensor");
  EXPECT_EQ(laser.type, PfxSensorType::kRay);
  EXPECT_EQ(laser.link, "base_scan");
  EXPECT_EQ(laser.topic, "scan");
  EXPECT_EQ(laser.frame, "base_scan");
  EXPECT_EQ(laser.updateRate, 5);
  EXPECT_EQ(laser.ray.horizontalSamples, 360u);
  EXPECT_EQ(laser.ray.verticalSamples, 1u);
  EXPECT_FLOAT_EQ(laser.ray.horizontalMinAngle, 0);
  EXPECT_FLOAT_EQ(laser.ray.horizontalMaxAngle, PfxFloat(6.28319));
  EXPECT_FLOAT_EQ(laser.ray.rangeMin, PfxFloat(0.12));
  EXPECT_FLOAT_EQ(laser.ray.rangeMax, PfxFloat(3.5));
  EXPECT_FLOAT_EQ(laser.rangeNoise.mean, 0);
  EXPECT_FLOAT_EQ(laser.rangeNoise.stddev, PfxFloat(0.01));
  EXPECT_TRUE(laser.pose.isApprox(PfxTransform3::Identity()));

  // What is not simulated is said, element by element.
  const std::string expected[] = {
      "<gazebo reference='imu_link'> <sensor name='imu'>: <sensor><always_on> is ignored",
      "<gazebo reference='imu_link'> <sensor name='imu'>: <sensor><visualize> is ignored",
      "<gazebo reference='base_scan'> <sensor name='lds_lfcd_sensor'>: "
      "<sensor><ray><range><resolution> "
      "is ignored",
      "<gazebo reference='base_scan'> <sensor name='lds_lfcd_sensor'>: <sensor><visualize> is "
      "ignored"};
  ASSERT_EQ(out.warnings.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(out.warnings[i], expected[i]);
}

TEST(UrdfSensors, LidarImuNoiseAndPoseAreRead) {
  const std::string urdf =
      "<robot name='r'><link name='base'/>"
      "<gazebo reference='base'><sensor type='gpu_ray' name='velo'><update_rate>10</update_rate>"
      "<pose>0.1 0 0.2 0 0 1.5</pose><ray><scan><horizontal><samples>100</samples>"
      "<min_angle>-3</min_angle><max_angle>3</max_angle></horizontal><vertical>"
      "<samples>16</samples><min_angle>-0.26</min_angle><max_angle>0.26</max_angle></vertical>"
      "</scan><range><min>0.3</min><max>100</max></range></ray></sensor>"
      "<sensor type='imu' name='imu'><imu><angular_velocity><z><noise type='gaussian'>"
      "<mean>0.1</mean><stddev>0.02</stddev><bias_mean>1</bias_mean></noise></z>"
      "</angular_velocity><linear_acceleration><x><noise type='gaussian'><stddev>0.3</stddev>"
      "</noise></x></linear_acceleration></imu>"
      "<plugin name='p' filename='libgazebo_ros_imu_sensor.so'><topicName>imu/data</topicName>"
      "<frameName>imu_frame</frameName><updateRateHZ>50</updateRateHZ></plugin>"
      "</sensor></gazebo></robot>";
  PfxUrdfSensors out;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfSensors(urdf, "r.urdf", out, &message), PFX_OK) << message;
  ASSERT_EQ(out.sensors.size(), 2u);
  const PfxSensorSpec& velo = out.sensors[0];
  EXPECT_EQ(velo.ray.horizontalSamples, 100u);
  EXPECT_EQ(velo.ray.verticalSamples, 16u);
  EXPECT_FLOAT_EQ(velo.ray.verticalMinAngle, PfxFloat(-0.26));
  EXPECT_FLOAT_EQ(velo.ray.rangeMax, 100);
  EXPECT_EQ(velo.updateRate, 10);
  EXPECT_LT((velo.pose.translation() - PfxVector3(PfxFloat(0.1), 0, PfxFloat(0.2))).norm(), 1e-6);
  EXPECT_NEAR(PfxFloat(Eigen::AngleAxis<PfxFloat>(velo.pose.linear()).angle()), 1.5, 1e-5);
  const PfxSensorSpec& imu = out.sensors[1];
  EXPECT_EQ(imu.topic, "imu/data");
  EXPECT_EQ(imu.frame, "imu_frame");
  EXPECT_FLOAT_EQ(imu.angularVelocityNoise[2].mean, PfxFloat(0.1));
  EXPECT_FLOAT_EQ(imu.angularVelocityNoise[2].stddev, PfxFloat(0.02));
  EXPECT_FLOAT_EQ(imu.angularVelocityNoise[0].stddev, 0);
  EXPECT_FLOAT_EQ(imu.linearAccelerationNoise[0].stddev, PfxFloat(0.3));
  // The bias and the plugin's own rate are not simulated, and say so.
  bool biasWarned = false, rateWarned = false;
  for (const std::string& w : out.warnings) {
    biasWarned = biasWarned || w.find("<noise><bias_mean> is ignored") != std::string::npos;
    rateWarned =
        rateWarned || w.find("<sensor><plugin><updateRateHZ> is ignored") != std::string::npos;
  }
  EXPECT_TRUE(biasWarned);
  EXPECT_TRUE(rateWarned);
}

TEST(UrdfSensors, SdformatSevenLidarIsARangeSensor) {
  const std::string urdf =
      "<robot name='r'><link name='base'/><gazebo reference='base'>"
      "<sensor type='gpu_lidar' name='l'><lidar><scan><horizontal><samples>3</samples>"
      "</horizontal></scan><range><min>0.2</min><max>30</max></range></lidar></sensor>"
      "</gazebo></robot>";
  PfxUrdfSensors out;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfSensors(urdf, "r.urdf", out, &message), PFX_OK) << message;
  ASSERT_EQ(out.sensors.size(), 1u);
  EXPECT_EQ(out.sensors[0].type, PfxSensorType::kRay);
  EXPECT_EQ(out.sensors[0].ray.horizontalSamples, 3u);
  EXPECT_FLOAT_EQ(out.sensors[0].ray.rangeMax, 30);
  EXPECT_TRUE(out.warnings.empty());
}

TEST(UrdfSensors, OtherSensorTypesAreWarningsNotErrors) {
  const std::string urdf =
      "<robot name='r'><link name='base'/><gazebo reference='base'>"
      "<sensor type='camera' name='cam'/></gazebo></robot>";
  PfxUrdfSensors out;
  ASSERT_EQ(pfxLoadUrdfSensors(urdf, "r.urdf", out, nullptr), PFX_OK);
  EXPECT_TRUE(out.sensors.empty());
  ASSERT_EQ(out.warnings.size(), 1u);
  EXPECT_EQ(out.warnings[0],
            "<gazebo reference='base'> <sensor name='cam'>: type 'camera' is not simulated; "
            "ignored");
}

TEST(UrdfSensors, EachBadValueIsRefusedWithItsElement) {
  const std::string head = "robot.urdf: <gazebo reference='head'> <sensor name='laser'>: ";
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange)), "");
  EXPECT_EQ(refusal(robotWithLaser(kScan + "<range><min>-0.1</min><max>5</max></range>")),
            head + "<sensor><ray><range><min>: must not be negative");
  EXPECT_EQ(refusal(robotWithLaser(kScan + "<range><min>6</min><max>5</max></range>")),
            head + "<sensor><ray><range><max>: must be above <min>");
  EXPECT_EQ(refusal(robotWithLaser(kScan + "<range><min>nan</min><max>5</max></range>")),
            head + "<sensor><ray><range><min>: is not a finite number");
  EXPECT_EQ(refusal(robotWithLaser(kScan + "<range><min>0.1</min><max>far</max></range>")),
            head + "<sensor><ray><range><max>: 'far' is not a number");
  EXPECT_EQ(refusal(robotWithLaser(kScan + "<range><min>0.1</min></range>")),
            head + "<sensor><ray><range>: needs both <min> and <max>");
  EXPECT_EQ(refusal(robotWithLaser(kScan)),
            head + "<sensor><ray>: has no <range> (its <min> and <max> are required)");
  EXPECT_EQ(
      refusal(
          robotWithLaser("<scan><horizontal><samples>0</samples></horizontal></scan>" + kRange)),
      head + "<sensor><ray><scan><horizontal><samples>: must be a whole number from 1 to 1000000");
  EXPECT_EQ(
      refusal(robotWithLaser("<scan><vertical><samples>2.5</samples></vertical></scan>" + kRange)),
      head + "<sensor><ray><scan><vertical><samples>: must be a whole number from 1 to 1000000");
  EXPECT_EQ(refusal(robotWithLaser("<scan><horizontal><samples>4</samples><min_angle>1</min_angle>"
                                   "<max_angle>-1</max_angle></horizontal></scan>" +
                                   kRange)),
            head + "<sensor><ray><scan><horizontal><min_angle>: is above <max_angle>");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange, "<update_rate>0</update_rate>")),
            head + "<sensor><update_rate>: must be > 0 Hz (leave it out for every step)");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange, "<update_rate>-5</update_rate>")),
            head + "<sensor><update_rate>: must be > 0 Hz (leave it out for every step)");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange, "<update_rate>inf</update_rate>")),
            head + "<sensor><update_rate>: is not a finite number");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange, "<pose>0 0 0 0 0</pose>")),
            head + "<sensor><pose>: must be six finite numbers: x y z roll pitch yaw");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange +
                                   "<noise><type>gaussian</type><stddev>-1</stddev></noise>")),
            head + "<sensor><ray><noise><stddev>: must not be negative");
  EXPECT_EQ(
      refusal(robotWithLaser(kScan + kRange + "<noise><type>perlin</type></noise>")),
      head + "<sensor><ray><noise><type>: 'perlin' is not a noise type pfx knows (none, gaussian)");
  EXPECT_EQ(refusal(robotWithLaser(kScan + kRange, "", "tail")),
            "robot.urdf: <gazebo reference='tail'> <sensor name='laser'>: sensor 'laser': no "
            "link named 'tail'");
  EXPECT_EQ(refusal("<robot name='r'><link name='a'/><gazebo><sensor type='imu' name='i'/>"
                    "</gazebo></robot>"),
            "robot.urdf: <gazebo> <sensor name='i'>: a sensor belongs to a link: <gazebo "
            "reference='link'>");
  EXPECT_EQ(refusal("<robot name='r'><link name='a'/><gazebo reference='a'><sensor type='imu'/>"
                    "</gazebo></robot>"),
            "robot.urdf: <gazebo reference='a'>: a <sensor> has no name attribute");
  EXPECT_EQ(refusal("<robot name='r'><link name='a'/><gazebo reference='a'><sensor type='imu' "
                    "name='i'/><sensor type='imu' name='i'/></gazebo></robot>"),
            "robot.urdf: <gazebo reference='a'> <sensor name='i'>: another sensor has this name "
            "already");
  EXPECT_EQ(refusal("<robot name='r'><link name='a'/><gazebo reference='a'><sensor type='imu' "
                    "name='i'><imu><angular_velocity><x><noise type='gaussian'><stddev>-2"
                    "</stddev></noise></x></angular_velocity></imu></sensor></gazebo></robot>"),
            "robot.urdf: <gazebo reference='a'> <sensor name='i'>: "
            "<sensor><imu><angular_velocity><x><noise><stddev>: must not be negative");
  EXPECT_EQ(refusal("<robot").rfind("robot.urdf: line 1: not well-formed XML (", 0), 0u);
}

TEST(UrdfSensors, CheckRefusesSpecsFromParameters) {
  PfxSensorSpec spec;
  spec.name = "s";
  spec.link = "base";
  spec.ray.rangeMax = 2;
  const std::vector<std::string> links = {"base"};
  EXPECT_EQ(pfxCheckSensorSpec(spec, links), "");
  PfxSensorSpec bad = spec;
  bad.ray.rangeMin = -1;
  EXPECT_EQ(pfxCheckSensorSpec(bad, links), "sensor 's': range min must not be negative");
  bad = spec;
  bad.ray.rangeMin = 3;
  EXPECT_EQ(pfxCheckSensorSpec(bad, links), "sensor 's': range max must be above range min");
  bad = spec;
  bad.ray.horizontalSamples = 0;
  EXPECT_EQ(pfxCheckSensorSpec(bad, links), "sensor 's': samples must be at least 1");
  bad = spec;
  bad.updateRate = -1;
  EXPECT_EQ(pfxCheckSensorSpec(bad, links),
            "sensor 's': update rate must be a finite number of Hz > 0 (0: every step)");
  bad = spec;
  bad.link = "arm";
  EXPECT_EQ(pfxCheckSensorSpec(bad, links), "sensor 's': no link named 'arm'");
  bad = spec;
  bad.type = PfxSensorType::kImu;
  bad.linearAccelerationNoise[1].stddev = NAN;
  EXPECT_EQ(pfxCheckSensorSpec(bad, links), "sensor 's': linear acceleration noise is not finite");
}

TEST(UrdfSensors, ForceTorqueOnAJointAndContactOnALink) {
  const std::string urdf = readFile(PFX_SOURCE_DIR "/tests/ros/data/ft_bumper.urdf");
  ASSERT_FALSE(urdf.empty());
  PfxUrdfSensors out;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfSensors(urdf, "ft_bumper.urdf", out, &message), PFX_OK) << message;
  ASSERT_EQ(out.sensors.size(), 2u);
  const PfxSensorSpec& ft = out.sensors[0];
  EXPECT_EQ(ft.type, PfxSensorType::kForceTorque);
  EXPECT_EQ(ft.joint, "hinge");
  EXPECT_EQ(ft.link, "pendulum");
  EXPECT_FALSE(ft.childToParent);
  EXPECT_EQ(ft.topic, "hinge_wrench");
  EXPECT_EQ(ft.updateRate, 50);
  const PfxSensorSpec& bumper = out.sensors[1];
  EXPECT_EQ(bumper.type, PfxSensorType::kContact);
  EXPECT_EQ(bumper.link, "pad");
  EXPECT_EQ(bumper.topic, "pad_contacts");
  EXPECT_EQ(bumper.frame, "world");

  auto withFt = [&](const std::string& reference, const std::string& inside) {
    return "<robot name='r'><link name='a'/><link name='b'/><joint name='j' type='revolute'>"
           "<parent link='a'/><child link='b'/><axis xyz='0 0 1'/></joint><gazebo reference='" +
           reference + "'><sensor type='force_torque' name='ft'>" + inside +
           "</sensor></gazebo></robot>";
  };
  EXPECT_EQ(refusal(withFt("j", "")), "");
  EXPECT_EQ(refusal(withFt("b", "")),
            "robot.urdf: <gazebo reference='b'> <sensor name='ft'>: sensor 'ft': no joint named "
            "'b'");
  EXPECT_EQ(refusal(withFt("j",
                           "<force_torque><measure_direction>sideways</measure_direction>"
                           "</force_torque>")),
            "robot.urdf: <gazebo reference='j'> <sensor name='ft'>: "
            "<sensor><force_torque><measure_direction>: 'sideways' is neither child_to_parent nor "
            "parent_to_child");
  // The wrench is given in the child's frame only: another frame is a warning.
  PfxUrdfSensors frames;
  ASSERT_EQ(pfxLoadUrdfSensors(withFt("j", "<force_torque><frame>sensor</frame></force_torque>"),
                               "r.urdf", frames, nullptr),
            PFX_OK);
  ASSERT_EQ(frames.warnings.size(), 1u);
  EXPECT_EQ(frames.warnings[0],
            "<gazebo reference='j'> <sensor name='ft'>: <sensor><force_torque><frame> is ignored");
}

TEST(UrdfSensors, DepthCameraAsGazeboKinectDescriptionsDeclareIt) {
  auto withCamera = [](const std::string& camera) {
    return "<robot name='r'><link name='cam'/><gazebo reference='cam'>"
           "<sensor type='depth' name='kinect'><update_rate>20</update_rate><camera>" +
           camera +
           "</camera><plugin name='k' filename='libgazebo_ros_openni_kinect.so'>"
           "<cameraName>kinect</cameraName><depthImageTopicName>depth/image</depthImageTopicName>"
           "<pointCloudTopicName>depth/points</pointCloudTopicName>"
           "<frameName>cam_optical</frameName><pointCloudCutoff>0.4</pointCloudCutoff></plugin>"
           "</sensor></gazebo></robot>";
  };
  const std::string good =
      "<horizontal_fov>1.047</horizontal_fov><image><width>64</width><height>48</height>"
      "<format>R8G8B8</format></image><clip><near>0.05</near><far>5</far></clip>";
  PfxUrdfSensors out;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfSensors(withCamera(good), "r.urdf", out, &message), PFX_OK) << message;
  ASSERT_EQ(out.sensors.size(), 1u);
  const PfxSensorSpec& s = out.sensors[0];
  EXPECT_EQ(s.type, PfxSensorType::kDepthCamera);
  EXPECT_EQ(s.camera.width, 64u);
  EXPECT_EQ(s.camera.height, 48u);
  EXPECT_FLOAT_EQ(s.camera.horizontalFov, PfxFloat(1.047));
  EXPECT_FLOAT_EQ(s.camera.nearClip, PfxFloat(0.05));
  EXPECT_FLOAT_EQ(s.camera.farClip, 5);
  EXPECT_EQ(s.topic, "kinect");
  EXPECT_EQ(s.depthImageTopic, "depth/image");
  EXPECT_EQ(s.cameraInfoTopic, "depth/camera_info");
  EXPECT_EQ(s.pointsTopic, "depth/points");
  EXPECT_EQ(s.frame, "cam_optical");
  const std::string expected[] = {
      "<gazebo reference='cam'> <sensor name='kinect'>: <sensor><camera><image><format> is "
      "ignored",
      "<gazebo reference='cam'> <sensor name='kinect'>: <sensor><plugin><pointCloudCutoff> is "
      "ignored"};
  ASSERT_EQ(out.warnings.size(), 2u);
  EXPECT_EQ(out.warnings[0], expected[0]);
  EXPECT_EQ(out.warnings[1], expected[1]);

  const std::string where = "robot.urdf: <gazebo reference='cam'> <sensor name='kinect'>: ";
  EXPECT_EQ(refusal(withCamera("<horizontal_fov>3.5</horizontal_fov>")),
            where + "<sensor><camera><horizontal_fov>: must be between 0 and pi");
  EXPECT_EQ(refusal(withCamera("<image><width>0</width></image>")),
            where + "<sensor><camera><image><width>: must be a whole number from 1 to 4096");
  EXPECT_EQ(refusal(withCamera("<clip><near>2</near><far>1</far></clip>")),
            where + "<sensor><camera><clip><far>: must be above <near>");
  EXPECT_EQ(refusal(withCamera("<clip><near>-1</near></clip>")),
            where + "<sensor><camera><clip><near>: must not be negative");
}
