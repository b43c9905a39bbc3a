#include "pfx_ros/pfx_node_sensors.h"

#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "pfx/ContactsStamped.h"
#include "pfx/high_level/pfx_imu_reading.h"
#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

struct PfxNodeSensors::Sensor {
  PfxSensorSpec spec;
  PfxUInt32 linkIndex = 0;
  PfxUInt32 jointIndex = 0;  // force_torque: into the model's joints
  double period = 0;         // s of simulated time; 0: every step
  double nextTime = 0;       // simulated time when it is next due
  ros::Publisher publisher;
  // A depth camera's camera info and point cloud (its image goes to `publisher`).
  ros::Publisher infoPublisher;
  ros::Publisher pointsPublisher;
  std::mt19937 random;
  // The IMU's point velocity after the previous step (its acceleration is the difference).
  PfxVector3 previousVelocity = PfxVector3::Zero();
  bool hasPrevious = false;
  std::vector<PfxRayInput> rays;
  std::vector<PfxRayOutput> hits;
  std::vector<PfxFloat> ranges;
  // A contact sensor's points as last published.
  std::vector<PfxNodeContact> contacts;
  bool contactsPublished = false;
};

namespace {

PfxFloat draw(std::mt19937& random, const PfxSensorNoise& noise) {
  if (noise.stddev == 0) return noise.mean;
  return PfxFloat(std::normal_distribution<double>(noise.mean, noise.stddev)(random));
}

PfxVector3 noisy(std::mt19937& random, const PfxVector3& v, const PfxSensorNoise* noise) {
  return v + PfxVector3(draw(random, noise[0]), draw(random, noise[1]), draw(random, noise[2]));
}

void setDiagonal(boost::array<double, 9>& covariance, const PfxSensorNoise* noise) {
  std::fill(covariance.begin(), covariance.end(), 0.0);
  for (int axis = 0; axis < 3; ++axis) {
    covariance[axis * 4] = double(noise[axis].stddev) * double(noise[axis].stddev);
  }
}

// An organised cloud of width x height float x, y, z points, zeroed, with no point known to be
// finite (is_dense false): a beam or pixel that returned nothing is written as NaN.
sensor_msgs::PointCloud2 makeOrganisedCloud(const std_msgs::Header& header, PfxUInt32 width,
                                            PfxUInt32 height) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  cloud.height = height;
  cloud.width = width;
  for (const char* name : {"x", "y", "z"}) {
    sensor_msgs::PointField field;
    field.name = name;
    field.offset = std::uint32_t(cloud.fields.size() * sizeof(float));
    field.datatype = sensor_msgs::PointField::FLOAT32;
    field.count = 1;
    cloud.fields.push_back(field);
  }
  cloud.is_bigendian = false;
  cloud.point_step = 3 * sizeof(float);
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = false;
  cloud.data.resize(std::size_t(cloud.row_step) * cloud.height);
  return cloud;
}

}  // namespace

PfxNodeSensors::PfxNodeSensors(ros::NodeHandle& handle, const std::string& fixedFrame,
                               PfxUInt32 model)
    : m_handle(handle), m_fixedFrame(fixedFrame), m_model(model) {}

PfxNodeSensors::~PfxNodeSensors() = default;

bool PfxNodeSensors::configure(const std::string& urdfXml, const std::string& urdfName,
                               const ros::NodeHandle& privateHandle,
                               const PfxNodeSimulation& simulation, std::string* message) {
  int seed = 0;
  privateHandle.param("sensor_seed", seed, 0);
  PfxUrdfSensors declared;
  if (pfxLoadUrdfSensors(urdfXml, urdfName, declared, message) != PFX_OK) return false;
  for (const std::string& warning : declared.warnings) ROS_WARN_STREAM("pfx_node: " << warning);
  std::vector<PfxSensorSpec> specs = declared.sensors;

  XmlRpc::XmlRpcValue list;
  if (privateHandle.getParam("sensors", list)) {
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
      if (message) *message = "~sensors must be a list of dicts";
      return false;
    }
    for (int i = 0; i < list.size(); ++i) {
      PfxSensorSpec spec;
      if (const std::string why = pfxReadSensorParam(list[i], spec); !why.empty()) {
        if (message) *message = "~sensors[" + std::to_string(i) + "]: " + why;
        return false;
      }
      specs.push_back(spec);
    }
  }

  const PfxUrdfModel& model = simulation.getModel(m_model);
  std::vector<std::string> links, joints;
  for (const PfxUrdfLink& link : model.links) links.push_back(link.name);
  for (const PfxUrdfJoint& joint : model.joints) joints.push_back(joint.name);
  std::set<std::string> names, topics;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    PfxSensorSpec& spec = specs[i];
    std::string why = pfxCheckSensorSpec(spec, links, joints);
    if (why.empty() && spec.type == PfxSensorType::kForceTorque) {
      // The wrench is the world joint's: a fixed joint is lumped into one body and a
      // floating or planar one has no single joint, so they transmit nothing to measure.
      const PfxUrdfJoint& joint = model.joints[PfxUInt32(simulation.findJoint(spec.joint, m_model))];
      spec.link = joint.childLink;
      if (joint.jointId == kPfxUrdfNoJoint || joint.collapsed) {
        why = "sensor '" + spec.name + "': joint '" + spec.joint +
              "' is not a revolute, continuous or prismatic joint of its own in the world "
              "(fixed joints are lumped), so it reports no force";
      }
    }
    if (spec.topic.empty()) spec.topic = spec.name;
    // The link is known once the spec passed its check.
    if (why.empty() && spec.frame.empty()) {
      spec.frame = simulation.getLinkName(PfxUInt32(simulation.findLink(spec.link, m_model)),
                                          m_model);
    } else if (why.empty() && m_model != 0) {
      // A frame the URDF names is one of the robot's: an added model's frames carry its prefix.
      spec.frame = simulation.getModelSpec(m_model).framePrefix + "/" + spec.frame;
    }
    if (why.empty() && !names.insert(spec.name).second) {
      why = "sensor '" + spec.name + "': another sensor has this name already";
    }
    if (why.empty() && !topics.insert(spec.topic).second) {
      why = "sensor '" + spec.name + "': another sensor publishes on topic '" + spec.topic + "'";
    }
    if (!why.empty()) {
      if (message) *message = why;
      return false;
    }
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const PfxSensorSpec& spec = specs[i];
    auto sensor = std::make_unique<Sensor>();
    sensor->spec = spec;
    sensor->linkIndex = PfxUInt32(simulation.findLink(spec.link, m_model));
    sensor->period = spec.updateRate > 0 ? 1.0 / spec.updateRate : 0;
    sensor->nextTime = simulation.getTime();
    sensor->random.seed(std::uint32_t(seed) + std::uint32_t(i));
    const char* kind = "";
    switch (spec.type) {
      case PfxSensorType::kRay: {
        const PfxUInt32 n = pfxGetRangeSensorNumRays(spec.ray);
        sensor->rays.resize(n);
        sensor->hits.resize(n);
        sensor->ranges.resize(n);
        if (spec.ray.verticalSamples == 1) {
          sensor->publisher = m_handle.advertise<sensor_msgs::LaserScan>(spec.topic, 10);
          kind = "sensor_msgs/LaserScan";
        } else {
          sensor->publisher = m_handle.advertise<sensor_msgs::PointCloud2>(spec.topic, 10);
          kind = "sensor_msgs/PointCloud2";
        }
        break;
      }
      case PfxSensorType::kImu:
        sensor->publisher = m_handle.advertise<sensor_msgs::Imu>(spec.topic, 10);
        kind = "sensor_msgs/Imu";
        break;
      case PfxSensorType::kOdometry:
        sensor->publisher = m_handle.advertise<nav_msgs::Odometry>(spec.topic, 10);
        kind = "nav_msgs/Odometry";
        break;
      case PfxSensorType::kContact:
        // Latched: a contact sensor publishes only on change, so a late subscriber would
        // otherwise not learn what the link touches until it changes.
        sensor->publisher = m_handle.advertise<pfx::ContactsStamped>(spec.topic, 10, true);
        kind = "pfx/ContactsStamped";
        break;
      case PfxSensorType::kDepthCamera: {
        const PfxUInt32 n = pfxGetDepthCameraNumRays(spec.camera);
        sensor->rays.resize(n);
        sensor->hits.resize(n);
        sensor->ranges.resize(n);
        ros::NodeHandle camera(m_handle, spec.topic);
        sensor->publisher = camera.advertise<sensor_msgs::Image>(spec.depthImageTopic, 2);
        sensor->infoPublisher = camera.advertise<sensor_msgs::CameraInfo>(spec.cameraInfoTopic, 2);
        sensor->pointsPublisher = camera.advertise<sensor_msgs::PointCloud2>(spec.pointsTopic, 2);
        kind = "sensor_msgs/Image (32FC1), CameraInfo and PointCloud2";
        break;
      }
      case PfxSensorType::kForceTorque:
        sensor->publisher = m_handle.advertise<geometry_msgs::WrenchStamped>(spec.topic, 10);
        sensor->jointIndex = PfxUInt32(simulation.findJoint(spec.joint, m_model));
        kind = "geometry_msgs/WrenchStamped";
        break;
    }
    if (spec.updateRate > 0) {
      ROS_INFO("pfx_node: sensor '%s' on link '%s': %s on %s at %g Hz", spec.name.c_str(),
               spec.link.c_str(), kind, sensor->publisher.getTopic().c_str(), spec.updateRate);
    } else {
      ROS_INFO("pfx_node: sensor '%s' on link '%s': %s on %s every step", spec.name.c_str(),
               spec.link.c_str(), kind, sensor->publisher.getTopic().c_str());
    }
    m_sensors.push_back(std::move(sensor));
  }
  return true;
}

void PfxNodeSensors::restart() {
  for (auto& sensor : m_sensors) {
    sensor->hasPrevious = false;
    sensor->nextTime = -std::numeric_limits<double>::infinity();
  }
}

void PfxNodeSensors::update(PfxNodeSimulation& simulation, const ros::Time& stamp) {
  const double time = simulation.getTime();
  const double dt = simulation.getTimeStep();
  const PfxWorld& world = simulation.getWorld();
  bool contactsRead = false;  // read once per step, for all contact sensors
  for (auto& owned : m_sensors) {
    Sensor& sensor = *owned;
    const PfxUrdfLink& link = simulation.getModel(m_model).links[sensor.linkIndex];
    const PfxTransform3 pose =
        simulation.getLinkPose(sensor.linkIndex, m_model) * sensor.spec.pose;
    const PfxRigidState& state = world.getRigidState(link.bodyId);
    const PfxVector3 pointVelocity = pfxGetPointVelocity(state, pose.translation());
    // Half a step of slack: a rate that divides the step exactly must not slip a step
    // through rounding of the clock.
    const bool due = time + 0.5 * dt >= sensor.nextTime;
    if (due) {
      switch (sensor.spec.type) {
        case PfxSensorType::kRay:
          publishScan(sensor, simulation, pose, stamp);
          break;
        case PfxSensorType::kImu:
          publishImu(sensor, pose, state, pointVelocity, PfxFloat(dt), world.getParam().gravity,
                     stamp);
          break;
        case PfxSensorType::kOdometry:
          publishOdometry(sensor, pose, state, pointVelocity, stamp);
          break;
        case PfxSensorType::kContact:
          if (!contactsRead) {
            simulation.getContacts(m_contacts);
            contactsRead = true;
          }
          publishContacts(sensor, simulation, stamp);
          break;
        case PfxSensorType::kForceTorque:
          publishWrench(sensor, simulation, pose, stamp);
          break;
        case PfxSensorType::kDepthCamera:
          publishDepth(sensor, simulation, pose, stamp);
          break;
      }
      sensor.nextTime += sensor.period;
      // Behind (a restart, or a rate above the step's): the schedule starts again from now.
      if (sensor.nextTime < time + 0.5 * dt) sensor.nextTime = time + sensor.period;
    }
    sensor.previousVelocity = pointVelocity;
    sensor.hasPrevious = true;
  }
}

void PfxNodeSensors::publishScan(Sensor& sensor, PfxNodeSimulation& simulation,
                                 const PfxTransform3& pose, const ros::Time& stamp) {
  const PfxRangeSensorParam& r = sensor.spec.ray;
  const PfxUInt32 n = pfxGetRangeSensorNumRays(r);
  pfxMakeRangeSensorRays(r, pose, sensor.rays.data());
  if (const PfxInt32 err = simulation.castRays(sensor.rays.data(), sensor.hits.data(), n);
      err != PFX_OK) {
    ROS_ERROR_THROTTLE(1.0, "pfx_node: sensor '%s': cast failed: %s", sensor.spec.name.c_str(),
                       pfxErrorString(err));
    return;
  }
  pfxGetRangeSensorRanges(r, sensor.hits.data(), sensor.ranges.data());
  const PfxSensorNoise& noise = sensor.spec.rangeNoise;
  if (noise.stddev > 0 || noise.mean != 0) {
    // A noisy return stays a return within the sensor's limits; a miss stays a miss.
    for (PfxFloat& range : sensor.ranges) {
      if (std::isfinite(range)) {
        range = std::clamp(range + draw(sensor.random, noise), r.rangeMin, r.rangeMax);
      }
    }
  }
  if (r.verticalSamples == 1) {
    sensor_msgs::LaserScan scan;
    scan.header.stamp = stamp;
    scan.header.frame_id = sensor.spec.frame;
    scan.angle_min = r.horizontalMinAngle;
    scan.angle_max = r.horizontalMaxAngle;
    scan.angle_increment = r.horizontalSamples > 1 ? (r.horizontalMaxAngle - r.horizontalMinAngle) /
                                                         PfxFloat(r.horizontalSamples - 1)
                                                   : 0;
    scan.time_increment = 0;  // all beams of a scan are cast at one instant
    scan.scan_time = float(sensor.period > 0 ? sensor.period : simulation.getTimeStep());
    scan.range_min = r.rangeMin;
    scan.range_max = r.rangeMax;
    scan.ranges.assign(sensor.ranges.begin(), sensor.ranges.end());
    sensor.publisher.publish(scan);
    return;
  }
  // An organised cloud in the sensor's frame: row v holds vertical sample v, and a beam that
  // returned nothing is a NaN point (is_dense false), as PCL's organised clouds have it.
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = sensor.spec.frame;
  sensor_msgs::PointCloud2 cloud =
      makeOrganisedCloud(header, r.horizontalSamples, r.verticalSamples);
  for (PfxUInt32 v = 0; v < r.verticalSamples; ++v) {
    const PfxFloat pitch =
        pfxGetRangeSensorAngle(r.verticalMinAngle, r.verticalMaxAngle, r.verticalSamples, v);
    for (PfxUInt32 h = 0; h < r.horizontalSamples; ++h) {
      const PfxFloat yaw = pfxGetRangeSensorAngle(r.horizontalMinAngle, r.horizontalMaxAngle,
                                                  r.horizontalSamples, h);
      const PfxUInt32 i = v * r.horizontalSamples + h;
      float xyz[3] = {std::numeric_limits<float>::quiet_NaN(),
                      std::numeric_limits<float>::quiet_NaN(),
                      std::numeric_limits<float>::quiet_NaN()};
      if (std::isfinite(sensor.ranges[i])) {
        const double range = sensor.ranges[i];
        xyz[0] = float(range * std::cos(pitch) * std::cos(yaw));
        xyz[1] = float(range * std::cos(pitch) * std::sin(yaw));
        xyz[2] = float(range * std::sin(pitch));
      }
      std::memcpy(&cloud.data[std::size_t(i) * cloud.point_step], xyz, sizeof(xyz));
    }
  }
  sensor.publisher.publish(cloud);
}

void PfxNodeSensors::publishImu(Sensor& sensor, const PfxTransform3& pose,
                                const PfxRigidState& state, const PfxVector3& pointVelocity,
                                PfxFloat dt, const PfxVector3& gravity, const ros::Time& stamp) {
  // The first reading after a start or reset has no previous velocity: it takes the point
  // as unaccelerated rather than invent a jump.
  const PfxVector3 previous = sensor.hasPrevious ? sensor.previousVelocity : pointVelocity;
  const PfxImuReading reading = pfxGetImuReading(pose, state, pointVelocity, previous, dt, gravity);
  sensor_msgs::Imu imu;
  imu.header.stamp = stamp;
  imu.header.frame_id = sensor.spec.frame;
  imu.orientation = pfxToQuaternionMsg(reading.orientation);
  imu.angular_velocity = pfxToVector3Msg(
      noisy(sensor.random, reading.angularVelocity, sensor.spec.angularVelocityNoise));
  imu.linear_acceleration = pfxToVector3Msg(
      noisy(sensor.random, reading.linearAcceleration, sensor.spec.linearAccelerationNoise));
  std::fill(imu.orientation_covariance.begin(), imu.orientation_covariance.end(), 0.0);
  setDiagonal(imu.angular_velocity_covariance, sensor.spec.angularVelocityNoise);
  setDiagonal(imu.linear_acceleration_covariance, sensor.spec.linearAccelerationNoise);
  sensor.publisher.publish(imu);
}

namespace {

// Whether a contact sensor's points changed enough to be published again: another set of
// links touched, another number of points, or a point moved by more than a millimetre. The
// impulses of resting contacts vary a little every step; that alone is not news.
bool sameContacts(const std::vector<PfxNodeContact>& a, const std::vector<PfxNodeContact>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].bodyA != b[i].bodyA || a[i].bodyB != b[i].bodyB || a[i].shapeA != b[i].shapeA ||
        a[i].shapeB != b[i].shapeB || a[i].particleGroupA != b[i].particleGroupA ||
        a[i].particleGroupB != b[i].particleGroupB ||
        (a[i].position - b[i].position).norm() > PfxFloat(1e-3)) {
      return false;
    }
  }
  return true;
}

}  // namespace

void PfxNodeSensors::publishContacts(Sensor& sensor, const PfxNodeSimulation& simulation,
                                     const ros::Time& stamp) {
  // The points on the sensor's link, turned so that the link is side A; named as rays and
  // contacts name it (with an added model's frame prefix).
  const std::string& link = simulation.getLinkName(sensor.linkIndex, m_model);
  std::vector<PfxNodeContact> mine;
  for (const PfxNodeContact& c : m_contacts) {
    if (simulation.getContactNameA(c) == link) {
      mine.push_back(c);
    } else if (simulation.getContactNameB(c) == link) {
      PfxNodeContact turned = c;
      std::swap(turned.bodyA, turned.bodyB);
      std::swap(turned.shapeA, turned.shapeB);
      std::swap(turned.particleGroupA, turned.particleGroupB);
      turned.normal = -c.normal;
      mine.push_back(turned);
    }
  }
  if (sensor.contactsPublished && sameContacts(mine, sensor.contacts)) return;
  pfx::ContactsStamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = m_fixedFrame;
  msg.link = link;
  for (const PfxNodeContact& c : mine) {
    pfx::Contact contact;
    contact.link_a = link;
    contact.link_b = simulation.getContactNameB(c);
    contact.position = pfxToPointMsg(c.position);
    contact.normal = pfxToVector3Msg(c.normal);
    contact.depth = c.depth;
    contact.impulse = c.impulse;
    msg.contacts.push_back(contact);
  }
  sensor.publisher.publish(msg);
  sensor.contacts = std::move(mine);
  sensor.contactsPublished = true;
}

void PfxNodeSensors::publishWrench(Sensor& sensor, const PfxNodeSimulation& simulation,
                                   const PfxTransform3& pose, const ros::Time& stamp) {
  const PfxWorld& world = simulation.getWorld();
  const PfxJoint& joint = world.getJoint(simulation.getModel(m_model).joints[sensor.jointIndex].jointId);
  // The solver's impulses are those of the last sub-step.
  const PfxFloat subStep = world.getParam().timeStep / PfxFloat(world.getParam().subStep);
  // What the parent exerts on the child (body B), the torque about the joint's origin.
  PfxVector3 force = joint.getAppliedForce(subStep);
  PfxVector3 torque = joint.getAppliedTorque(subStep);
  if (sensor.spec.childToParent) {
    force = -force;
    torque = -torque;
  }
  const PfxMatrix3 toChild = pose.linear().transpose();
  geometry_msgs::WrenchStamped wrench;
  wrench.header.stamp = stamp;
  wrench.header.frame_id = sensor.spec.frame;
  wrench.wrench.force = pfxToVector3Msg(toChild * force);
  wrench.wrench.torque = pfxToVector3Msg(toChild * torque);
  sensor.publisher.publish(wrench);
}

void PfxNodeSensors::publishDepth(Sensor& sensor, PfxNodeSimulation& simulation,
                                  const PfxTransform3& pose, const ros::Time& stamp) {
  const PfxDepthCameraParam& c = sensor.spec.camera;
  const PfxUInt32 n = pfxGetDepthCameraNumRays(c);
  pfxMakeDepthCameraRays(c, pose, sensor.rays.data());
  if (const PfxInt32 err = simulation.castRays(sensor.rays.data(), sensor.hits.data(), n);
      err != PFX_OK) {
    ROS_ERROR_THROTTLE(1.0, "pfx_node: sensor '%s': cast failed: %s", sensor.spec.name.c_str(),
                       pfxErrorString(err));
    return;
  }
  std::vector<PfxFloat>& depths = sensor.ranges;
  pfxGetDepthCameraDepths(c, sensor.hits.data(), depths.data());
  const PfxSensorNoise& noise = sensor.spec.depthNoise;
  if (noise.stddev > 0 || noise.mean != 0) {
    for (PfxFloat& depth : depths) {
      if (std::isfinite(depth)) {
        depth = std::clamp(depth + draw(sensor.random, noise), c.nearClip, c.farClip);
      }
    }
  }
  const double focal = pfxGetDepthCameraFocalLength(c);
  const double cx = (c.width - 1) / 2.0, cy = (c.height - 1) / 2.0;

  // REP 118: 32-bit float metres along the optical axis, +inf beyond the far plane. The
  // image, the camera info and the cloud are in the optical frame (x right, y down, z
  // forward) that `frame` names.
  sensor_msgs::Image image;
  image.header.stamp = stamp;
  image.header.frame_id = sensor.spec.frame;
  image.height = c.height;
  image.width = c.width;
  image.encoding = "32FC1";
  image.is_bigendian = false;
  image.step = c.width * sizeof(float);
  image.data.resize(std::size_t(image.step) * c.height);
  for (PfxUInt32 i = 0; i < n; ++i) {
    const float depth = float(depths[i]);
    std::memcpy(&image.data[std::size_t(i) * sizeof(float)], &depth, sizeof(float));
  }

  sensor_msgs::CameraInfo info;
  info.header = image.header;
  info.height = c.height;
  info.width = c.width;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {focal, 0, cx, 0, focal, cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {focal, 0, cx, 0, 0, focal, cy, 0, 0, 0, 1, 0};

  sensor_msgs::PointCloud2 cloud = makeOrganisedCloud(image.header, c.width, c.height);
  for (PfxUInt32 v = 0; v < c.height; ++v) {
    for (PfxUInt32 u = 0; u < c.width; ++u) {
      const PfxUInt32 i = v * c.width + u;
      const double z = depths[i];
      const float nan = std::numeric_limits<float>::quiet_NaN();
      const float xyz[3] = {std::isfinite(z) ? float((u - cx) / focal * z) : nan,
                            std::isfinite(z) ? float((v - cy) / focal * z) : nan,
                            std::isfinite(z) ? float(z) : nan};
      std::memcpy(&cloud.data[std::size_t(i) * cloud.point_step], xyz, sizeof(xyz));
    }
  }
  sensor.publisher.publish(image);
  sensor.infoPublisher.publish(info);
  sensor.pointsPublisher.publish(cloud);
}

void PfxNodeSensors::publishOdometry(Sensor& sensor, const PfxTransform3& pose,
                                     const PfxRigidState& state, const PfxVector3& pointVelocity,
                                     const ros::Time& stamp) {
  // nav_msgs/Odometry: the pose in the fixed frame, the twist in the child frame.
  const PfxMatrix3 toChild = pose.linear().transpose();
  nav_msgs::Odometry odometry;
  odometry.header.stamp = stamp;
  odometry.header.frame_id = m_fixedFrame;
  odometry.child_frame_id = sensor.spec.frame;
  odometry.pose.pose.position = pfxToPointMsg(pose.translation());
  odometry.pose.pose.orientation = pfxToQuaternionMsg(PfxQuat(pose.linear()).normalized());
  odometry.twist.twist.linear = pfxToVector3Msg(toChild * pointVelocity);
  odometry.twist.twist.angular = pfxToVector3Msg(toChild * state.getAngularVelocity());
  sensor.publisher.publish(odometry);
}

}  // namespace pfx
