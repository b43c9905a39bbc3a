// Sensors of a robot description: the <sensor> elements of a URDF's Gazebo extension blocks
// (<gazebo reference="link"><sensor type="..." name="...">), read as SDFormat describes them,
// so that a description written for Gazebo declares its sensors to pfx unchanged. Which
// elements are honoured and which are passed over is listed in the README ("Sensors"); each
// one passed over is reported in a warning, so that nothing is dropped without a word.
// What the sensors compute is in pfx_range_sensor.h and pfx_imu_reading.h; publishing them
// is the ROS node's business.
#pragma once

#include <string>
#include <vector>

#include "pfx/high_level/pfx_depth_camera.h"
#include "pfx/high_level/pfx_range_sensor.h"

namespace pfx {

enum class PfxSensorType {
  kRay,          // laser or lidar: one vertical sample gives a scan, more a point cloud
  kImu,          // orientation, angular velocity, specific force
  kOdometry,     // ground-truth pose and twist (declared through the node's parameters only)
  kContact,      // the contact points of a link (a bumper)
  kForceTorque,  // the force and torque a joint transmits
  kDepthCamera,  // a depth image, its camera info and a point cloud
};

// Gaussian noise added to a value; stddev 0 adds `mean` only.
struct PfxSensorNoise {
  PfxFloat mean = 0;
  PfxFloat stddev = 0;
};

struct PfxSensorSpec {
  std::string name;
  PfxSensorType type = PfxSensorType::kRay;
  std::string link;   // force_torque: the joint's child link
  std::string joint;  // force_torque only
  // force_torque: true for the wrench the child exerts on the parent (Gazebo's default,
  // child_to_parent), false for the one the parent exerts on the child.
  bool childToParent = true;
  std::string topic;                               // empty: the sensor's name
  std::string frame;                               // empty: the link's name
  PfxTransform3 pose = PfxTransform3::Identity();  // of the sensor in the link's frame
  double updateRate = 0;                           // Hz of simulated time; 0: every step
  PfxRangeSensorParam ray;
  PfxSensorNoise rangeNoise;
  PfxSensorNoise angularVelocityNoise[3];  // per axis of the IMU frame
  PfxSensorNoise linearAccelerationNoise[3];
  PfxDepthCameraParam camera;
  PfxSensorNoise depthNoise;
  // A depth camera's three topics, under `topic`: as gazebo_ros_openni_kinect names them
  // unless its plugin says otherwise.
  std::string depthImageTopic = "depth/image_raw";
  std::string cameraInfoTopic = "depth/camera_info";
  std::string pointsTopic = "points";
};

// Empty when the spec is usable with a robot of these links, otherwise why not (naming the
// sensor and the value): an unknown link, an update rate that is negative or not finite, a
// range sensor that pfxCheckRangeSensorParam refuses (saying which bound), a noise whose
// mean or stddev is not finite or whose stddev is negative, a pose that is not finite.
// A force_torque sensor's joint is looked for in `joints`, every other sensor's link in `links`.
std::string pfxCheckSensorSpec(const PfxSensorSpec& spec, const std::vector<std::string>& links,
                               const std::vector<std::string>& joints = {});

struct PfxUrdfSensors {
  std::vector<PfxSensorSpec> sensors;
  std::vector<std::string> warnings;  // what was passed over, one line each
};

// Reads the sensors of URDF text; `fileName` only names the file in messages. On error
// returns PFX_ERR_INVALID_VALUE with *message naming the file, the <gazebo> block, the
// sensor and the element, and leaves `out` as it was. Errors: XML that does not parse, a
// <sensor> outside a <gazebo reference="..."> block or referring to no <link> (no <joint>
// for a force_torque sensor), a missing or repeated sensor name, a number that does not
// read, is not finite or is out of range (pfxCheckSensorSpec), an update rate <= 0 where one
// is given, zero samples, a noise type other than none, gaussian or gaussian_quantized, a
// measure_direction other than child_to_parent or parent_to_child. ray, gpu_ray, lidar and
// gpu_lidar are range sensors (their <ray> or <lidar>), imu an IMU, contact a bumper on the
// link, force_torque a sensor on the joint; sensors of other types (camera, depth, ...) are
// warnings, not errors.
PfxInt32 pfxLoadUrdfSensors(const std::string& urdfXml, const std::string& fileName,
                            PfxUrdfSensors& out, std::string* message);

}  // namespace pfx
