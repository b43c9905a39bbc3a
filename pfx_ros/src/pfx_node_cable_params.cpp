#include "pfx_ros/pfx_node_cable_params.h"

#include <set>

namespace pfx {

namespace {

using Value = XmlRpc::XmlRpcValue;

bool readNumber(Value& value, double& out) {
  switch (value.getType()) {
    case Value::TypeDouble:
      out = static_cast<double>(value);
      return true;
    case Value::TypeInt:
      out = static_cast<int>(value);
      return true;
    default:
      return false;
  }
}

// The fields of one entry, read into a spec: each read* returns "" or "<key>: <why>".
class EntryReader {
 public:
  explicit EntryReader(Value& entry) : m_entry(entry) {}

  std::string checkKeys(const std::set<std::string>& keys) {
    for (auto& [key, value] : m_entry) {
      if (keys.count(key) == 0) return "unknown key '" + key + "'";
    }
    return "";
  }
  std::string readString(const char* key, std::string& out) {
    if (!m_entry.hasMember(key)) return "";
    if (m_entry[key].getType() != Value::TypeString) return std::string(key) + ": not a string";
    out = static_cast<std::string>(m_entry[key]);
    return "";
  }
  std::string readNumber(const char* key, PfxFloat& out) {
    if (!m_entry.hasMember(key)) return "";
    double x = 0;
    if (!pfx::readNumber(m_entry[key], x)) return std::string(key) + ": not a number";
    out = PfxFloat(x);
    return "";
  }
  // A whole number; negative and fractional values are refused here, huge ones by the check.
  std::string readCount(const char* key, PfxUInt32& out) {
    if (!m_entry.hasMember(key)) return "";
    if (m_entry[key].getType() != Value::TypeInt || static_cast<int>(m_entry[key]) < 0) {
      return std::string(key) + ": not a whole number >= 0";
    }
    out = PfxUInt32(static_cast<int>(m_entry[key]));
    return "";
  }
  std::string readPoint(const char* key, PfxVector3& out) {
    if (!m_entry.hasMember(key)) return "";
    Value& list = m_entry[key];
    double xyz[3];
    bool valid = list.getType() == Value::TypeArray && list.size() == 3;
    for (int i = 0; valid && i < 3; ++i) valid = pfx::readNumber(list[i], xyz[i]);
    if (!valid) return std::string(key) + ": not a list [x, y, z] of numbers";
    out = PfxVector3(PfxFloat(xyz[0]), PfxFloat(xyz[1]), PfxFloat(xyz[2]));
    return "";
  }
  std::string readResolution(const char* key, PfxUInt32& u, PfxUInt32& v) {
    if (!m_entry.hasMember(key)) return "";
    Value& list = m_entry[key];
    if (list.getType() != Value::TypeArray || list.size() != 2) {
      return std::string(key) + ": not a list [u, v] of whole numbers";
    }
    PfxUInt32 counts[2];
    for (int i = 0; i < 2; ++i) {
      if (list[i].getType() != Value::TypeInt || static_cast<int>(list[i]) < 0) {
        return std::string(key) + "[" + std::to_string(i) + "]: not a whole number >= 0";
      }
      counts[i] = PfxUInt32(static_cast<int>(list[i]));
    }
    u = counts[0];
    v = counts[1];
    return "";
  }
  std::string readStrings(const char* key, std::vector<std::string>& out) {
    if (!m_entry.hasMember(key)) return "";
    Value& list = m_entry[key];
    if (list.getType() != Value::TypeArray) return std::string(key) + ": not a list of strings";
    for (int i = 0; i < list.size(); ++i) {
      if (list[i].getType() != Value::TypeString) {
        return std::string(key) + "[" + std::to_string(i) + "]: not a string";
      }
      out.push_back(static_cast<std::string>(list[i]));
    }
    return "";
  }

 private:
  Value& m_entry;
};

std::string readCable(Value& entry, PfxNodeCableSpec& spec) {
  EntryReader r(entry);
  return pfxFirstReason({r.checkKeys({"name", "start_link", "start_point", "end_link", "end_point",
                               "length", "radius", "mass_per_metre", "stiffness", "segments",
                               "iterations"}),
                  r.readString("start_link", spec.startLink),
                  r.readPoint("start_point", spec.startPoint),
                  r.readString("end_link", spec.endLink), r.readPoint("end_point", spec.endPoint),
                  r.readNumber("length", spec.length), r.readNumber("radius", spec.radius),
                  r.readNumber("mass_per_metre", spec.massPerMetre),
                  r.readNumber("stiffness", spec.stiffness), r.readCount("segments", spec.segments),
                  r.readCount("iterations", spec.iterations)});
}

std::string readCloth(Value& entry, PfxNodeClothSpec& spec) {
  EntryReader r(entry);
  return pfxFirstReason({r.checkKeys({"name", "corner", "edge_u", "edge_v", "resolution",
                               "mass_per_area", "radius", "stiffness", "iterations", "pinned",
                               "pin_link"}),
                  r.readPoint("corner", spec.corner), r.readPoint("edge_u", spec.edgeU),
                  r.readPoint("edge_v", spec.edgeV),
                  r.readResolution("resolution", spec.resolutionU, spec.resolutionV),
                  r.readNumber("mass_per_area", spec.massPerArea),
                  r.readNumber("radius", spec.radius), r.readNumber("stiffness", spec.stiffness),
                  r.readCount("iterations", spec.iterations), r.readStrings("pinned", spec.pinned),
                  r.readString("pin_link", spec.pinLink)});
}

// Reads ~<list> and adds each entry with add(spec, &why); returns the entries refused.
template <typename Spec, typename Read, typename Add>
PfxUInt32 addDeclared(const ros::NodeHandle& nh, const char* list, Read read, Add add) {
  Value entries;
  if (!nh.getParam(list, entries)) return 0;
  if (entries.getType() != Value::TypeArray) {
    ROS_ERROR("pfx_node: ~%s must be a list of dicts; none added", list);
    return 1;
  }
  PfxUInt32 refused = 0;
  for (int i = 0; i < entries.size(); ++i) {
    Spec spec;
    std::string why;
    if (entries[i].getType() != Value::TypeStruct) {
      why = "not a dict";
    } else if (!entries[i].hasMember("name") ||
               entries[i]["name"].getType() != Value::TypeString) {
      why = "name: missing, or not a string";
    } else {
      spec.name = static_cast<std::string>(entries[i]["name"]);
      why = read(entries[i], spec);
      if (why.empty()) add(spec, &why);  // which says why when it refuses
    }
    if (!why.empty()) {
      ROS_ERROR("pfx_node: ~%s[%d] '%s' refused, left out: %s", list, i, spec.name.c_str(),
                why.c_str());
      ++refused;
      continue;
    }
    ROS_INFO("pfx_node: ~%s[%d] '%s' added", list, i, spec.name.c_str());
  }
  return refused;
}

}  // namespace

PfxUInt32 pfxAddDeclaredCablesAndCloths(const ros::NodeHandle& privateHandle,
                                        PfxNodeSimulation& simulation) {
  const PfxUInt32 refusedCables = addDeclared<PfxNodeCableSpec>(
      privateHandle, "cables", readCable,
      [&](const PfxNodeCableSpec& spec, std::string* why) { simulation.addCable(spec, why); });
  const PfxUInt32 refusedCloths = addDeclared<PfxNodeClothSpec>(
      privateHandle, "cloths", readCloth,
      [&](const PfxNodeClothSpec& spec, std::string* why) { simulation.addCloth(spec, why); });
  return refusedCables + refusedCloths;
}

}  // namespace pfx
