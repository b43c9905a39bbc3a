// The robots added to the node's world besides the robot of robot_description (README,
// "Models"): those declared in ~models at start-up, and the services ~spawn_model and
// ~delete_model (pfx/SpawnModel, pfx/DeleteModel) while it runs. Each lives in a model
// slot of the simulation and has its ROS side in a PfxNodeModel (pfx_node_model.h).
// ~delete_model deletes the robot of robot_description too, whose ROS side the node holds.

#pragma once

#include <ros/ros.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pfx/DeleteModel.h"
#include "pfx/SpawnModel.h"
#include "pfx_ros/pfx_node_model.h"
#include "pfx_ros/pfx_node_refusal_log.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

// What a spawn asks for: the simulation's spec (its URDF text already read) and the
// namespace of its topics.
struct PfxNodeModelRequest {
  PfxNodeModelSpec spec;
  std::string robotNamespace;  // empty: the model's name
};

// One entry of ~models (a dict: name, urdf_param or urdf_path, namespace, tf_prefix, pose
// [x, y, z, roll, pitch, yaw], fixed_base, allow_missing_meshes) into `request`, the URDF
// text read from the parameter (through `handle`) or the file; empty, or what is wrong.
std::string pfxReadModelParam(XmlRpc::XmlRpcValue& entry, const ros::NodeHandle& handle,
                              PfxNodeModelRequest& request);
// The URDF text of a spawn into `xml`: `text` when given, else the parameter `paramName`
// (resolved through `handle`), else the file `path`. Empty, or what is wrong: both text and
// parameter, neither nor a file, a parameter not set or not a string, a file that does
// not read.
std::string pfxReadModelUrdf(const std::string& text, const std::string& paramName,
                             const std::string& path, const ros::NodeHandle& handle,
                             std::string& xml);

class PfxNodeModels {
 public:
  // Deletes the robot of robot_description (model slot 0) with its topics: empty, or why
  // not (nothing changed then).
  using RobotRemover = std::function<std::string()>;

  PfxNodeModels(ros::NodeHandle& handle, ros::NodeHandle& privateHandle,
                PfxNodeSimulation& simulation, PfxNodeRefusalLog& refusals,
                const std::string& fixedFrame, bool useSimTime, RobotRemover robotRemover);
  ~PfxNodeModels();

  // Adds the models of ~models; false, with *message naming the entry and the reason, when
  // one is malformed or refused (the models before it stay).
  bool addDeclared(std::string* message);
  void beforeStep();
  void afterStep(const ros::Time& stamp);
  void publishState(const ros::Time& stamp);
  void rebind();
  // Ends the trajectories of the added model in `slot` that hold one of `joints`.
  void releaseFromTrajectories(PfxUInt32 slot, const std::vector<PfxUInt32>& joints);
  std::size_t getNumModels() const { return m_models.size(); }

 private:
  bool spawn(SpawnModel::Request& req, SpawnModel::Response& res);
  bool remove(DeleteModel::Request& req, DeleteModel::Response& res);
  // Empty, with the resolved namespace of a model's topics in `resolved`, or why the
  // namespace asked for (empty: the model's name) cannot be one: not a valid ROS name, a
  // private name, the node's or the robot of robot_description's, another model's.
  std::string resolveNamespace(const std::string& name, const std::string& robotNamespace,
                               std::string& resolved) const;
  // Checks the namespace, adds the model to the simulation and configures its ROS side;
  // on error nothing is left of it and *message says why.
  bool add(const PfxNodeModelRequest& request, std::string* message);

  ros::NodeHandle& m_handle;
  ros::NodeHandle& m_privateHandle;
  PfxNodeSimulation& m_simulation;
  PfxNodeRefusalLog& m_refusals;
  std::string m_fixedFrame;
  bool m_useSimTime;
  RobotRemover m_robotRemover;
  std::vector<ros::ServiceServer> m_servers;
  std::map<std::string, std::unique_ptr<PfxNodeModel>> m_models;  // by model name
};

}  // namespace pfx
