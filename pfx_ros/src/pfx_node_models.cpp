#include "pfx_ros/pfx_node_models.h"

#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

PfxNodeModels::PfxNodeModels(ros::NodeHandle& handle, ros::NodeHandle& privateHandle,
                             PfxNodeSimulation& simulation, PfxNodeRefusalLog& refusals,
                             const std::string& fixedFrame, bool useSimTime,
                             RobotRemover robotRemover)
    : m_handle(handle),
      m_privateHandle(privateHandle),
      m_simulation(simulation),
      m_refusals(refusals),
      m_fixedFrame(fixedFrame),
      m_useSimTime(useSimTime),
      m_robotRemover(std::move(robotRemover)) {
  m_servers.push_back(privateHandle.advertiseService("spawn_model", &PfxNodeModels::spawn, this));
  m_servers.push_back(privateHandle.advertiseService("delete_model", &PfxNodeModels::remove, this));
}

PfxNodeModels::~PfxNodeModels() = default;

std::string PfxNodeModels::resolveNamespace(const std::string& name,
                                            const std::string& robotNamespace,
                                            std::string& resolved) const {
  const std::string asked = robotNamespace.empty() ? name : robotNamespace;
  std::string why;
  if (asked.front() == '~' || !ros::names::validate(asked, why)) {
    return "robot_namespace: '" + asked + "' is not a ROS namespace" +
           (why.empty() ? std::string(" (no private names)") : ": " + why);
  }
  resolved = m_handle.resolveName(asked);
  // The robot of robot_description's topics are in the node's namespace, its private
  // ones (joint_trajectory) in the private namespace.
  if (resolved == m_handle.getNamespace() || resolved == m_privateHandle.getNamespace()) {
    return "robot_namespace: '" + resolved +
           "' is the namespace of the robot of robot_description or of the node";
  }
  for (const auto& [other, model] : m_models) {
    if (model->getNamespace() == resolved) {
      return "robot_namespace: '" + resolved + "' is model '" + other + "''s already";
    }
  }
  return "";
}

bool PfxNodeModels::add(const PfxNodeModelRequest& request, std::string* message) {
  const PfxNodeModelSpec& spec = request.spec;
  std::string why = m_simulation.checkModelSpec(spec);
  std::string robotNamespace;
  if (why.empty()) why = resolveNamespace(spec.name, request.robotNamespace, robotNamespace);
  PfxUInt32 slot = 0;
  if (why.empty()) m_simulation.addModel(spec, &slot, &why);
  if (!why.empty()) {
    if (message) *message = why;
    return false;
  }
  auto model = std::make_unique<PfxNodeModel>(m_simulation, slot, robotNamespace, m_fixedFrame,
                                              m_useSimTime, m_refusals);
  if (!model->configure(message)) {
    model.reset();  // its topics go before its bodies
    m_simulation.removeModel(slot, nullptr);
    return false;
  }
  ROS_INFO("pfx_node: model '%s' added (%zu links, %zu joints, %zu sensors), topics in %s, "
           "frames %s/<link>",
           spec.name.c_str(), m_simulation.getModel(slot).links.size(),
           m_simulation.getModel(slot).joints.size(), model->getNumSensors(),
           robotNamespace.c_str(), spec.framePrefix.c_str());
  m_models[spec.name] = std::move(model);
  return true;
}

bool PfxNodeModels::addDeclared(std::string* message) {
  XmlRpc::XmlRpcValue list;
  if (!m_privateHandle.getParam("models", list)) return true;
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    if (message) *message = "~models must be a list of dicts";
    return false;
  }
  for (int i = 0; i < list.size(); ++i) {
    PfxNodeModelRequest request;
    std::string why = pfxReadModelParam(list[i], m_handle, request);
    if (why.empty()) add(request, &why);  // which says why when it refuses
    if (!why.empty()) {
      if (message) *message = "~models[" + std::to_string(i) + "]: " + why;
      return false;
    }
  }
  return true;
}

bool PfxNodeModels::spawn(SpawnModel::Request& req, SpawnModel::Response& res) {
  PfxNodeModelRequest request;
  PfxNodeModelSpec& spec = request.spec;
  spec.name = req.name;
  spec.urdfPath = req.urdf_path;
  spec.framePrefix = req.tf_prefix.empty() ? req.name : req.tf_prefix;
  spec.position = pfxFromMsg(req.pose.position);
  // Not normalised here: a quaternion that is not unit is refused, not silently mended.
  spec.orientation = PfxQuat(PfxFloat(req.pose.orientation.w), PfxFloat(req.pose.orientation.x),
                             PfxFloat(req.pose.orientation.y), PfxFloat(req.pose.orientation.z));
  spec.fixedBase = req.fixed_base;
  spec.allowMissingMeshes = req.allow_missing_meshes;
  request.robotNamespace = req.robot_namespace;
  std::string why = pfxReadModelUrdf(req.urdf, req.param_name, req.urdf_path, m_handle, spec.urdfXml);
  if (why.empty()) add(request, &why);
  if (!why.empty()) return pfxRejectRequest(m_refusals, res, "spawn_model", why);
  res.success = true;
  res.message = "model '" + spec.name + "' added: topics in " +
                m_models[spec.name]->getNamespace() + ", frames " + spec.framePrefix + "/<link>";
  return true;
}

bool PfxNodeModels::remove(DeleteModel::Request& req, DeleteModel::Response& res) {
  const auto it = m_models.find(req.name);
  if (it == m_models.end()) {
    res.success = false;
    if (req.name.empty()) {
      res.message = "no name given";
    } else if (m_simulation.findModel(req.name) == 0) {
      res.message = m_robotRemover();
      res.success = res.message.empty();
      if (res.success) {
        res.message = "model '" + req.name + "' (the robot of robot_description) deleted";
        return true;
      }
      res.message = "model '" + req.name + "': " + res.message;
    } else {
      res.message = "no model named '" + req.name + "'";
    }
    m_refusals.refused("delete_model", res.message);
    return true;
  }
  const PfxUInt32 slot = it->second->getSlot();
  m_models.erase(it);  // its topics go before its bodies
  std::string why;
  m_simulation.removeModel(slot, &why);
  res.success = true;
  res.message = "model '" + req.name + "' deleted";
  return true;
}

void PfxNodeModels::beforeStep() {
  for (auto& entry : m_models) entry.second->beforeStep();
}

void PfxNodeModels::afterStep(const ros::Time& stamp) {
  for (auto& entry : m_models) entry.second->afterStep(stamp);
}

void PfxNodeModels::publishState(const ros::Time& stamp) {
  for (auto& entry : m_models) entry.second->publishState(stamp);
}

void PfxNodeModels::releaseFromTrajectories(PfxUInt32 slot, const std::vector<PfxUInt32>& joints) {
  for (auto& entry : m_models) {
    if (entry.second->getSlot() == slot) entry.second->releaseFromTrajectories(joints);
  }
}

void PfxNodeModels::rebind() {
  for (auto& entry : m_models) entry.second->rebind();
}

}  // namespace pfx
