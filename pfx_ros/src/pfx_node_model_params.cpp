// ~models entries and the URDF source of a spawn (pfx_node_models.h).
#include <fstream>
#include <set>
#include <sstream>

#include "pfx_ros/pfx_node_models.h"
#include "pfx_ros/pfx_node_xmlrpc.h"

namespace pfx {

std::string pfxReadModelUrdf(const std::string& text, const std::string& paramName,
                             const std::string& path, const ros::NodeHandle& handle,
                             std::string& xml) {
  if (!text.empty() && !paramName.empty()) {
    return "give the URDF as text (urdf) or as a parameter (param_name), not both";
  }
  if (!text.empty()) {
    xml = text;
    return "";
  }
  if (!paramName.empty()) {
    std::string why;
    if (!ros::names::validate(paramName, why)) {
      return "param_name: '" + paramName + "' is not a ROS name: " + why;
    }
    XmlRpc::XmlRpcValue value;
    if (!handle.getParam(paramName, value)) {
      return "param_name: no parameter '" + handle.resolveName(paramName) + "' is set";
    }
    if (value.getType() != XmlRpc::XmlRpcValue::TypeString) {
      return "param_name: parameter '" + handle.resolveName(paramName) +
             "' does not hold a string (the URDF text)";
    }
    xml = static_cast<std::string>(value);
    return "";
  }
  if (path.empty()) return "no URDF given: urdf (the text), param_name or urdf_path";
  std::ifstream in(path);
  if (!in) return "urdf_path: cannot open '" + path + "'";
  std::stringstream read;
  read << in.rdbuf();
  xml = read.str();
  return "";
}

std::string pfxReadModelParam(XmlRpc::XmlRpcValue& entry, const ros::NodeHandle& handle,
                              PfxNodeModelRequest& request) {
  using Value = XmlRpc::XmlRpcValue;
  if (entry.getType() != Value::TypeStruct) {
    return "is not a dict (name, urdf_param, urdf_path, namespace, tf_prefix, pose, fixed_base, "
           "allow_missing_meshes)";
  }
  static const std::set<std::string> kKeys = {"name",      "urdf_param", "urdf_path",
                                              "namespace", "tf_prefix",  "pose",
                                              "fixed_base", "allow_missing_meshes"};
  for (auto& [key, value] : entry) {
    if (kKeys.count(key) == 0) return "unknown key '" + key + "'";
  }
  PfxNodeModelSpec& spec = request.spec;
  std::string urdfParam;
  const std::pair<const char*, std::string*> strings[] = {{"name", &spec.name},
                                                          {"urdf_param", &urdfParam},
                                                          {"urdf_path", &spec.urdfPath},
                                                          {"namespace", &request.robotNamespace},
                                                          {"tf_prefix", &spec.framePrefix}};
  for (const auto& [key, field] : strings) {
    if (!entry.hasMember(key)) continue;
    if (entry[key].getType() != Value::TypeString) return std::string(key) + " is not a string";
    *field = static_cast<std::string>(entry[key]);
  }
  if (spec.name.empty()) return "has no name";
  if (spec.framePrefix.empty()) spec.framePrefix = spec.name;
  const std::pair<const char*, bool*> flags[] = {{"fixed_base", &spec.fixedBase},
                                                 {"allow_missing_meshes", &spec.allowMissingMeshes}};
  for (const auto& [key, field] : flags) {
    if (!entry.hasMember(key)) continue;
    if (entry[key].getType() != Value::TypeBoolean) return std::string(key) + " is not true or false";
    *field = static_cast<bool>(entry[key]);
  }
  if (entry.hasMember("pose")) {
    Value& pose = entry["pose"];
    double xyzrpy[6] = {0, 0, 0, 0, 0, 0};
    bool valid = pose.getType() == Value::TypeArray && pose.size() == 6;
    for (int i = 0; valid && i < 6; ++i) valid = pfxReadXmlRpcNumber(pose[i], xyzrpy[i]);
    if (!valid) return "pose is not a list [x, y, z, roll, pitch, yaw] of numbers";
    spec.position = PfxVector3(PfxFloat(xyzrpy[0]), PfxFloat(xyzrpy[1]), PfxFloat(xyzrpy[2]));
    using Turn = Eigen::AngleAxis<PfxFloat>;
    spec.orientation = Turn(PfxFloat(xyzrpy[5]), PfxVector3::UnitZ()) *
                       Turn(PfxFloat(xyzrpy[4]), PfxVector3::UnitY()) *
                       Turn(PfxFloat(xyzrpy[3]), PfxVector3::UnitX());
  }
  return pfxReadModelUrdf("", urdfParam, spec.urdfPath, handle, spec.urdfXml);
}

}  // namespace pfx
