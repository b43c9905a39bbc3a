// The node's sensors (README, "Sensors"): those that the robot description declares in its
// <gazebo reference="link"><sensor> blocks (pfx_urdf_sensors.h) and those of the ~sensors
// parameter, each published on its topic in the node's namespace:
//   ray, one vertical sample   sensor_msgs/LaserScan
//   ray, several               sensor_msgs/PointCloud2 (organised: one row per vertical sample)
//   imu                        sensor_msgs/Imu
//   odometry                   nav_msgs/Odometry (ground truth of the link)
//   contact                    pfx/ContactsStamped (the link's contacts, when they change)
//   force_torque               geometry_msgs/WrenchStamped (what the joint transmits)
//   depth_camera               sensor_msgs/Image (32FC1 depth), sensor_msgs/CameraInfo and
//                              sensor_msgs/PointCloud2, under the sensor's topic
// A sensor runs at its update rate in simulated time, looked at after every step; a scan is
// one batch of rays through the world's batch raycast. Messages carry the node's stamp of the
// step (the simulated time under use_sim_time). Noise is Gaussian, drawn from one generator
// per sensor seeded from ~sensor_seed and the sensor's place in the list, so runs repeat.
#pragma once

#include <ros/ros.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "pfx/loaders/pfx_urdf_sensors.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

// One entry of ~sensors (a dict: README, "Sensors") into `spec`; empty, or what is wrong with
// it (an unknown type or key, a key the type does not take, a value of the wrong type).
std::string pfxReadSensorParam(XmlRpc::XmlRpcValue& entry, PfxSensorSpec& spec);

class PfxNodeSensors {
 public:
  // `model`: the simulation's model slot whose links carry the sensors (0: the robot of
  // robot_description); a sensor's frame defaults to its link's name there
  // (PfxNodeSimulation::getLinkName, with an added model's frame prefix).
  PfxNodeSensors(ros::NodeHandle& handle, const std::string& fixedFrame, PfxUInt32 model = 0);
  ~PfxNodeSensors();

  // Reads the sensors of the URDF text (`urdfName` names it in messages), then ~sensors and
  // ~sensor_seed, and advertises their topics. False, with *message naming the sensor, the
  // element or key and the reason, when one is malformed; warnings (what the URDF's blocks
  // hold that is not simulated) are logged.
  bool configure(const std::string& urdfXml, const std::string& urdfName,
                 const ros::NodeHandle& privateHandle, const PfxNodeSimulation& simulation,
                 std::string* message);
  // After a reset or a loaded world: velocities start afresh and every sensor is due now.
  void restart();
  // Called after every step: publishes what is due at the simulation's time.
  void update(PfxNodeSimulation& simulation, const ros::Time& stamp);

  std::size_t getNumSensors() const { return m_sensors.size(); }

 private:
  struct Sensor;
  bool add(const PfxSensorSpec& spec, const PfxNodeSimulation& simulation, PfxUInt32 seed,
           std::string* message);
  void publishScan(Sensor& sensor, PfxNodeSimulation& simulation, const PfxTransform3& pose,
                   const ros::Time& stamp);
  void publishImu(Sensor& sensor, const PfxTransform3& pose, const PfxRigidState& state,
                  const PfxVector3& pointVelocity, PfxFloat dt, const PfxVector3& gravity,
                  const ros::Time& stamp);
  void publishOdometry(Sensor& sensor, const PfxTransform3& pose, const PfxRigidState& state,
                       const PfxVector3& pointVelocity, const ros::Time& stamp);
  void publishDepth(Sensor& sensor, PfxNodeSimulation& simulation, const PfxTransform3& pose,
                    const ros::Time& stamp);
  void publishContacts(Sensor& sensor, const PfxNodeSimulation& simulation, const ros::Time& stamp);
  void publishWrench(Sensor& sensor, const PfxNodeSimulation& simulation, const PfxTransform3& pose,
                     const ros::Time& stamp);

  ros::NodeHandle& m_handle;
  std::string m_fixedFrame;
  PfxUInt32 m_model;
  std::vector<std::unique_ptr<Sensor>> m_sensors;
  std::vector<PfxNodeContact> m_contacts;  // the world's, read once per step when needed
};

}  // namespace pfx
