// One entry of the ~sensors parameter (README, "Sensors") into a PfxSensorSpec: which keys
// each type takes, their types and their defaults. Ranges and links are checked afterwards by
// pfxCheckSensorSpec, as for the sensors of the URDF's <gazebo> blocks.
#include <cmath>
#include <map>
#include <set>

#include "pfx_ros/pfx_node_sensors.h"
#include "pfx_ros/pfx_node_xmlrpc.h"

namespace pfx {

namespace {

const std::map<std::string, PfxSensorType> kTypes = {{"ray", PfxSensorType::kRay},
                                                     {"imu", PfxSensorType::kImu},
                                                     {"odometry", PfxSensorType::kOdometry},
                                                     {"contact", PfxSensorType::kContact},
                                                     {"force_torque", PfxSensorType::kForceTorque},
                                                     {"depth_camera", PfxSensorType::kDepthCamera}};

// The keys of a ~sensors entry that each type takes, besides the common ones.
const std::set<std::string> kCommonKeys = {"name", "type", "topic", "frame", "update_rate"};
// Every type but force_torque sits on a link, at a pose in it.
const std::set<std::string> kLinkKeys = {"link", "pose"};
const std::set<std::string> kForceTorqueKeys = {"joint", "measure_direction"};
const std::set<std::string> kRayKeys = {"horizontal_samples",
                                        "horizontal_min_angle",
                                        "horizontal_max_angle",
                                        "vertical_samples",
                                        "vertical_min_angle",
                                        "vertical_max_angle",
                                        "range_min",
                                        "range_max",
                                        "range_noise_mean",
                                        "range_noise_stddev"};
const std::set<std::string> kDepthCameraKeys = {
    "width", "height", "horizontal_fov", "near", "far", "depth_noise_mean", "depth_noise_stddev"};
const std::set<std::string> kImuKeys = {
    "angular_velocity_noise_mean", "angular_velocity_noise_stddev",
    "linear_acceleration_noise_mean", "linear_acceleration_noise_stddev"};

std::string readString(XmlRpc::XmlRpcValue& entry, const char* key, std::string& out) {
  if (!entry.hasMember(key)) return "";
  if (entry[key].getType() != XmlRpc::XmlRpcValue::TypeString) {
    return std::string(key) + " is not a string";
  }
  out = static_cast<std::string>(entry[key]);
  return "";
}

// A number of the entry into `out` if the key is there; empty or why not.
template <typename T>
std::string readOptional(XmlRpc::XmlRpcValue& entry, const char* key, T& out) {
  if (!entry.hasMember(key)) return "";
  double v;
  if (!pfxReadXmlRpcNumber(entry[key], v)) return std::string(key) + " is not a number";
  if (!std::isfinite(v)) return std::string(key) + " is not finite";
  out = T(v);
  return "";
}

std::string readSamples(XmlRpc::XmlRpcValue& entry, const char* key, PfxUInt32& out) {
  if (!entry.hasMember(key)) return "";
  if (entry[key].getType() != XmlRpc::XmlRpcValue::TypeInt || static_cast<int>(entry[key]) < 1) {
    return std::string(key) + " must be a whole number >= 1";
  }
  out = PfxUInt32(static_cast<int>(entry[key]));
  return "";
}

}  // namespace

std::string pfxReadSensorParam(XmlRpc::XmlRpcValue& entry, PfxSensorSpec& spec) {
  if (entry.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    return "is not a dict (name, type, link, ...)";
  }
  for (const char* key : {"name", "type"}) {
    if (!entry.hasMember(key) || entry[key].getType() != XmlRpc::XmlRpcValue::TypeString) {
      return std::string("needs ") + key + " (a string)";
    }
  }
  spec.name = static_cast<std::string>(entry["name"]);
  const std::string type = static_cast<std::string>(entry["type"]);
  const auto found = kTypes.find(type);
  if (found == kTypes.end()) {
    return "type '" + type + "' is none of ray, imu, odometry, contact, force_torque, depth_camera";
  }
  spec.type = found->second;
  const bool onJoint = spec.type == PfxSensorType::kForceTorque;
  std::set<std::string> own = onJoint ? kForceTorqueKeys : kLinkKeys;
  if (spec.type == PfxSensorType::kRay) own.insert(kRayKeys.begin(), kRayKeys.end());
  if (spec.type == PfxSensorType::kImu) own.insert(kImuKeys.begin(), kImuKeys.end());
  if (spec.type == PfxSensorType::kDepthCamera) {
    own.insert(kDepthCameraKeys.begin(), kDepthCameraKeys.end());
  }
  for (auto& [key, value] : entry) {
    if (kCommonKeys.count(key) == 0 && own.count(key) == 0) {
      return "key '" + key + "' is not one a " + type + " sensor takes";
    }
  }
  const char* target = onJoint ? "joint" : "link";
  if (!entry.hasMember(target) || entry[target].getType() != XmlRpc::XmlRpcValue::TypeString) {
    return std::string("needs ") + target + " (a string)";
  }
  (onJoint ? spec.joint : spec.link) = static_cast<std::string>(entry[target]);
  if (entry.hasMember("measure_direction")) {
    std::string direction;
    if (std::string why = readString(entry, "measure_direction", direction); !why.empty()) {
      return why;
    }
    if (direction != "child_to_parent" && direction != "parent_to_child") {
      return "measure_direction '" + direction + "' is neither child_to_parent nor parent_to_child";
    }
    spec.childToParent = direction == "child_to_parent";
  }
  std::string why;
  if (why = readString(entry, "topic", spec.topic); !why.empty()) return why;
  if (why = readString(entry, "frame", spec.frame); !why.empty()) return why;
  if (why = readOptional(entry, "update_rate", spec.updateRate); !why.empty()) return why;
  if (entry.hasMember("update_rate") && spec.updateRate <= 0) {
    return "update_rate must be > 0 Hz (leave it out for every step)";
  }
  if (entry.hasMember("pose")) {
    XmlRpc::XmlRpcValue& pose = entry["pose"];
    double v[6];
    if (pose.getType() != XmlRpc::XmlRpcValue::TypeArray || pose.size() != 6) {
      return "pose must be a list of six numbers: x, y, z, roll, pitch, yaw";
    }
    for (int i = 0; i < 6; ++i) {
      if (!pfxReadXmlRpcNumber(pose[i], v[i]) || !std::isfinite(v[i])) {
        return "pose must be a list of six finite numbers: x, y, z, roll, pitch, yaw";
      }
    }
    const PfxQuat rotation(Eigen::AngleAxis<PfxFloat>(PfxFloat(v[5]), PfxVector3::UnitZ()) *
                           Eigen::AngleAxis<PfxFloat>(PfxFloat(v[4]), PfxVector3::UnitY()) *
                           Eigen::AngleAxis<PfxFloat>(PfxFloat(v[3]), PfxVector3::UnitX()));
    spec.pose =
        pfxMakeTransform(rotation, PfxVector3(PfxFloat(v[0]), PfxFloat(v[1]), PfxFloat(v[2])));
  }
  if (spec.type == PfxSensorType::kRay) {
    PfxRangeSensorParam& r = spec.ray;
    if (!entry.hasMember("range_max")) return "a ray sensor needs range_max";
    const std::string errors[] = {
        readSamples(entry, "horizontal_samples", r.horizontalSamples),
        readSamples(entry, "vertical_samples", r.verticalSamples),
        readOptional(entry, "horizontal_min_angle", r.horizontalMinAngle),
        readOptional(entry, "horizontal_max_angle", r.horizontalMaxAngle),
        readOptional(entry, "vertical_min_angle", r.verticalMinAngle),
        readOptional(entry, "vertical_max_angle", r.verticalMaxAngle),
        readOptional(entry, "range_min", r.rangeMin),
        readOptional(entry, "range_max", r.rangeMax),
        readOptional(entry, "range_noise_mean", spec.rangeNoise.mean),
        readOptional(entry, "range_noise_stddev", spec.rangeNoise.stddev)};
    for (const std::string& e : errors) {
      if (!e.empty()) return e;
    }
  }
  if (spec.type == PfxSensorType::kDepthCamera) {
    PfxDepthCameraParam& c = spec.camera;
    const std::string errors[] = {
        readSamples(entry, "width", c.width),
        readSamples(entry, "height", c.height),
        readOptional(entry, "horizontal_fov", c.horizontalFov),
        readOptional(entry, "near", c.nearClip),
        readOptional(entry, "far", c.farClip),
        readOptional(entry, "depth_noise_mean", spec.depthNoise.mean),
        readOptional(entry, "depth_noise_stddev", spec.depthNoise.stddev)};
    for (const std::string& e : errors) {
      if (!e.empty()) return e;
    }
  }
  if (spec.type == PfxSensorType::kImu) {
    PfxSensorNoise gyro, accel;
    const std::string errors[] = {
        readOptional(entry, "angular_velocity_noise_mean", gyro.mean),
        readOptional(entry, "angular_velocity_noise_stddev", gyro.stddev),
        readOptional(entry, "linear_acceleration_noise_mean", accel.mean),
        readOptional(entry, "linear_acceleration_noise_stddev", accel.stddev)};
    for (const std::string& e : errors) {
      if (!e.empty()) return e;
    }
    for (int axis = 0; axis < 3; ++axis) {
      spec.angularVelocityNoise[axis] = gyro;
      spec.linearAccelerationNoise[axis] = accel;
    }
  }
  return "";
}

}  // namespace pfx
