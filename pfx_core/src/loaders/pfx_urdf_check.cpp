// Checks of a URDF's text before urdfdom reads it. urdfdom reports many of these problems
// only to its log, in words that do not always name the element, and accepts others
// (negative masses, limits the wrong way round, a cycle beside the tree); here each one is
// an error that names the element and says what is wrong.
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "loaders/pfx_urdf_internal.h"

namespace pfx {

std::string pfxUrdfQuoted(const std::string& name) { return "'" + name + "'"; }

std::string pfxUrdfNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

namespace {

PfxInt32 fail(PfxUrdfError& error, PfxInt32 code, const std::string& text) {
  error.code = code;
  error.text = text;
  return code;
}

// A number as URDF writes it; NaN and infinities parse so that they can be named.
bool parseNumber(const std::string& text, double& value) {
  const char* begin = text.c_str();
  char* end = nullptr;
  value = std::strtod(begin, &end);
  if (end == begin) return false;
  while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r') ++end;
  return *end == '\0';
}

// Space-separated numbers, exactly `count` of them.
bool parseNumbers(const std::string& text, int count, double* values) {
  std::istringstream words(text);
  std::string word;
  int n = 0;
  while (words >> word) {
    if (n == count || !parseNumber(word, values[n])) return false;
    ++n;
  }
  return n == count;
}

// The element a check is about, for the messages: "link 'forearm'".
struct Subject {
  std::string kind;
  std::string name;
  std::string describe() const { return kind + " " + pfxUrdfQuoted(name); }
};

// Reads attribute `attribute` of `element` as `count` finite numbers. A missing attribute
// is fine (urdfdom supplies the default) and leaves `values` as they were.
bool readFinite(const TiXmlElement* element, const char* attribute, int count, double* values,
                const Subject& subject, const std::string& what, PfxUrdfError& error) {
  const char* text = element->Attribute(attribute);
  if (!text) return true;
  if (!parseNumbers(text, count, values)) {
    fail(error, PFX_ERR_INVALID_VALUE,
         subject.describe() + ": " + what + " " + pfxUrdfQuoted(text) + " is not " +
             (count == 1 ? "a number" : std::to_string(count) + " numbers"));
    return false;
  }
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite(values[i])) {
      fail(error, PFX_ERR_INVALID_VALUE,
           subject.describe() + ": " + what + " " + pfxUrdfQuoted(text) + " is not finite");
      return false;
    }
  }
  return true;
}

PfxInt32 checkInertial(const TiXmlElement* link, const Subject& subject, PfxUrdfError& error) {
  const TiXmlElement* inertial = link->FirstChildElement("inertial");
  if (!inertial) return PFX_OK;
  double mass = 0;
  if (const TiXmlElement* massElement = inertial->FirstChildElement("mass")) {
    if (!massElement->Attribute("value")) {
      return fail(error, PFX_ERR_INVALID_VALUE, subject.describe() + ": <mass> has no value");
    }
    if (!readFinite(massElement, "value", 1, &mass, subject, "mass", error)) return error.code;
  }
  if (mass < 0) {
    return fail(error, PFX_ERR_INVALID_VALUE,
                subject.describe() + ": mass " + pfxUrdfNumber(mass) + " is negative");
  }
  const TiXmlElement* inertia = inertial->FirstChildElement("inertia");
  static const char* const kNames[6] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
  double moments[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; inertia && i < 6; ++i) {
    if (!readFinite(inertia, kNames[i], 1, &moments[i], subject,
                    std::string("inertia ") + kNames[i], error)) {
      return error.code;
    }
  }
  // A link without mass has no inertia to speak of (a fixed base often says mass 0).
  if (mass == 0) return PFX_OK;
  Eigen::Matrix3d tensor;
  tensor << moments[0], moments[1], moments[2], moments[1], moments[3], moments[4], moments[2],
      moments[4], moments[5];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(tensor, Eigen::EigenvaluesOnly);
  if (!(eigen.eigenvalues().minCoeff() > 0)) {
    const Eigen::Vector3d principal = eigen.eigenvalues();
    return fail(error, PFX_ERR_INVALID_VALUE,
                subject.describe() + ": inertia is not positive definite (principal moments " +
                    pfxUrdfNumber(principal[0]) + ", " + pfxUrdfNumber(principal[1]) + ", " +
                    pfxUrdfNumber(principal[2]) + ")");
  }
  return PFX_OK;
}

// Reads `attribute`, which the geometry needs, as `count` finite numbers.
bool readRequired(const TiXmlElement* element, const char* attribute, int count, double* values,
                  const Subject& subject, const std::string& what, PfxUrdfError& error) {
  if (!element->Attribute(attribute)) {
    fail(error, PFX_ERR_INVALID_VALUE,
         subject.describe() + ": <" + element->ValueStr() + "> on line " +
             std::to_string(element->Row()) + " has no " + attribute);
    return false;
  }
  return readFinite(element, attribute, count, values, subject, what, error);
}

// The link's <collision> elements: their origins and the numbers of the geometries pfx
// knows (box, sphere, cylinder, capsule, mesh). Another geometry, or none, is kept by name
// for the builder to warn about.
PfxInt32 readCollisions(const TiXmlElement* link, const Subject& subject,
                        std::vector<PfxUrdfCollision>& out, PfxUrdfError& error) {
  for (const TiXmlElement* element = link->FirstChildElement("collision"); element;
       element = element->NextSiblingElement("collision")) {
    PfxUrdfCollision collision;
    collision.line = element->Row();
    if (const TiXmlElement* origin = element->FirstChildElement("origin")) {
      double xyz[3] = {0, 0, 0}, rpy[3] = {0, 0, 0};
      if (!readFinite(origin, "xyz", 3, xyz, subject, "collision origin xyz", error) ||
          !readFinite(origin, "rpy", 3, rpy, subject, "collision origin rpy", error)) {
        return error.code;
      }
      collision.origin.position = urdf::Vector3(xyz[0], xyz[1], xyz[2]);
      collision.origin.rotation.setFromRPY(rpy[0], rpy[1], rpy[2]);
    }
    const TiXmlElement* geometry = element->FirstChildElement("geometry");
    const TiXmlElement* shape = geometry ? geometry->FirstChildElement() : nullptr;
    if (shape) collision.geometry = shape->ValueStr();
    bool read = true;
    if (collision.geometry == "box") {
      read = readRequired(shape, "size", 3, collision.size, subject, "box size", error);
    } else if (collision.geometry == "sphere") {
      read = readRequired(shape, "radius", 1, &collision.radius, subject, "sphere radius", error);
    } else if (collision.geometry == "cylinder" || collision.geometry == "capsule") {
      read = readRequired(shape, "radius", 1, &collision.radius, subject,
                          collision.geometry + " radius", error) &&
             readRequired(shape, "length", 1, &collision.length, subject,
                          collision.geometry + " length", error);
    } else if (collision.geometry == "mesh") {
      if (const char* filename = shape->Attribute("filename")) collision.filename = filename;
      if (const char* scale = shape->Attribute("scale")) {
        double uniform = 1;
        if (parseNumbers(scale, 1, &uniform)) {
          std::fill(collision.scale, collision.scale + 3, uniform);
        } else {
          read = readFinite(shape, "scale", 3, collision.scale, subject, "mesh scale", error);
        }
      }
    }
    if (!read) return error.code;
    out.push_back(collision);
  }
  return PFX_OK;
}

// xacro's macros, properties and substitutions left in the text: urdfdom would answer
// "Unable to parse component" or take "${...}" for a name.
PfxInt32 checkNoXacro(const TiXmlElement* element, PfxUrdfError& error) {
  const std::string tag = element->ValueStr();
  std::string found;
  if (tag.compare(0, 6, "xacro:") == 0) {
    found = "element <" + tag + ">";
  } else {
    for (const TiXmlAttribute* a = element->FirstAttribute(); a && found.empty(); a = a->Next()) {
      const std::string value = a->ValueStr();
      if (value.find("${") != std::string::npos || value.find("$(") != std::string::npos) {
        found = "<" + tag + "> " + a->Name() + "=" + pfxUrdfQuoted(value);
      }
    }
  }
  if (!found.empty()) {
    return fail(error, PFX_ERR_INVALID_VALUE,
                "line " + std::to_string(element->Row()) + ": unexpanded xacro (" + found +
                    "); this is a xacro file: expand it into a URDF first (xacro robot.urdf.xacro "
                    "> robot.urdf, or rosrun xacro xacro ...)");
  }
  for (const TiXmlElement* child = element->FirstChildElement(); child;
       child = child->NextSiblingElement()) {
    if (checkNoXacro(child, error) != PFX_OK) return error.code;
  }
  return PFX_OK;
}

bool isKnownJointType(const std::string& type) {
  return type == "revolute" || type == "continuous" || type == "prismatic" || type == "fixed" ||
         type == "floating" || type == "planar";
}

struct JointText {
  std::string name;
  std::string type;
  std::string parent;
  std::string child;
  std::string mimic;  // leader, or empty
};

PfxInt32 checkJoint(const TiXmlElement* joint, JointText& out, PfxUrdfError& error) {
  const Subject subject{"joint", out.name};
  const char* type = joint->Attribute("type");
  if (!type) return fail(error, PFX_ERR_INVALID_VALUE, subject.describe() + ": no type");
  out.type = type;
  if (!isKnownJointType(out.type)) {
    return fail(error, PFX_ERR_INVALID_FLAG,
                subject.describe() + ": unknown type " + pfxUrdfQuoted(out.type) +
                    " (URDF knows revolute, continuous, prismatic, fixed, floating, planar)");
  }
  for (const char* end : {"parent", "child"}) {
    const TiXmlElement* element = joint->FirstChildElement(end);
    const char* link = element ? element->Attribute("link") : nullptr;
    if (!link || !*link) {
      return fail(error, PFX_ERR_INVALID_VALUE, subject.describe() + ": no " + end + " link");
    }
    (std::string(end) == "parent" ? out.parent : out.child) = link;
  }
  const bool hasAxis = out.type == "revolute" || out.type == "continuous" ||
                       out.type == "prismatic" || out.type == "planar";
  if (const TiXmlElement* axis = joint->FirstChildElement("axis"); axis && hasAxis) {
    double xyz[3] = {1, 0, 0};
    if (!readFinite(axis, "xyz", 3, xyz, subject, "axis", error)) return error.code;
    if (xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0) {
      return fail(error, PFX_ERR_DEGENERATE, subject.describe() + ": axis is zero");
    }
  }
  if (const TiXmlElement* limit = joint->FirstChildElement("limit")) {
    double values[4] = {0, 0, 0, 0};
    static const char* const kNames[4] = {"lower", "upper", "effort", "velocity"};
    for (int i = 0; i < 4; ++i) {
      if (!readFinite(limit, kNames[i], 1, &values[i], subject, std::string(kNames[i]) + " limit",
                      error)) {
        return error.code;
      }
    }
    if ((out.type == "revolute" || out.type == "prismatic") && values[0] > values[1]) {
      return fail(error, PFX_ERR_INVALID_VALUE,
                  subject.describe() + ": lower limit " + pfxUrdfNumber(values[0]) +
                      " is above upper limit " + pfxUrdfNumber(values[1]));
    }
    if (values[2] < 0 || values[3] < 0) {
      return fail(error, PFX_ERR_INVALID_VALUE,
                  subject.describe() + ": effort and velocity limits must not be negative");
    }
  }
  if (const TiXmlElement* dynamics = joint->FirstChildElement("dynamics")) {
    for (const char* name : {"damping", "friction"}) {
      double value = 0;
      if (!readFinite(dynamics, name, 1, &value, subject, name, error)) return error.code;
      if (value < 0) {
        return fail(error, PFX_ERR_INVALID_VALUE,
                    subject.describe() + ": " + name + " must not be negative");
      }
    }
  }
  if (const TiXmlElement* mimic = joint->FirstChildElement("mimic")) {
    const char* leader = mimic->Attribute("joint");
    if (!leader || !*leader) {
      return fail(error, PFX_ERR_INVALID_VALUE, subject.describe() + ": <mimic> names no joint");
    }
    out.mimic = leader;
    for (const char* name : {"multiplier", "offset"}) {
      double value = 0;
      if (!readFinite(mimic, name, 1, &value, subject, std::string("mimic ") + name, error)) {
        return error.code;
      }
    }
  }
  return PFX_OK;
}

// Each link has at most one parent joint, so following parents from any link either ends at
// a root or runs into a cycle.
PfxInt32 checkTree(const std::vector<std::string>& links, const std::vector<JointText>& joints,
                   PfxUrdfError& error) {
  std::map<std::string, std::size_t> parentJoint;  // child link -> joint index
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const JointText& joint = joints[j];
    if (joint.parent == joint.child) {
      return fail(error, PFX_ERR_INVALID_VALUE,
                  "joint " + pfxUrdfQuoted(joint.name) + ": link " + pfxUrdfQuoted(joint.parent) +
                      " is both its parent and its child (a cycle)");
    }
    const auto [it, inserted] = parentJoint.emplace(joint.child, j);
    if (!inserted) {
      return fail(error, PFX_ERR_INVALID_VALUE,
                  "link " + pfxUrdfQuoted(joint.child) + ": child of two joints, " +
                      pfxUrdfQuoted(joints[it->second].name) + " and " + pfxUrdfQuoted(joint.name) +
                      " (a URDF is a tree)");
    }
  }
  for (const std::string& start : links) {
    std::vector<std::string> path{start};
    for (auto it = parentJoint.find(start); it != parentJoint.end();
         it = parentJoint.find(path.back())) {
      const std::string& parent = joints[it->second].parent;
      if (parent == start) {
        std::string through;
        for (const std::string& link : path)
          through += (through.empty() ? "" : ", ") + pfxUrdfQuoted(link);
        return fail(error, PFX_ERR_INVALID_VALUE,
                    "joint " + pfxUrdfQuoted(joints[it->second].name) +
                        ": closes a cycle through links " + through);
      }
      if (path.size() > links.size()) break;  // a cycle above `start`, found from one of its links
      path.push_back(parent);
    }
  }
  std::vector<std::string> roots;
  for (const std::string& link : links) {
    if (parentJoint.count(link) == 0) roots.push_back(link);
  }
  if (roots.size() > 1) {
    return fail(error, PFX_ERR_INVALID_VALUE,
                "links " + pfxUrdfQuoted(roots[0]) + " and " + pfxUrdfQuoted(roots[1]) +
                    " are both roots (no joint leads to either): the robot must be one tree");
  }
  return PFX_OK;
}

PfxInt32 checkMimics(const std::vector<JointText>& joints, PfxUrdfError& error) {
  std::map<std::string, const JointText*> byName;
  for (const JointText& joint : joints) byName[joint.name] = &joint;
  for (const JointText& joint : joints) {
    if (joint.mimic.empty()) continue;
    const auto leader = byName.find(joint.mimic);
    if (leader == byName.end()) {
      return fail(error, PFX_ERR_INVALID_VALUE,
                  "joint " + pfxUrdfQuoted(joint.name) + ": mimics joint " +
                      pfxUrdfQuoted(joint.mimic) + ", which is not defined");
    }
    for (const JointText* j : {&joint, leader->second}) {
      if (j->type != "revolute" && j->type != "continuous" && j->type != "prismatic") {
        return fail(error, PFX_ERR_INVALID_VALUE,
                    "joint " + pfxUrdfQuoted(joint.name) +
                        ": <mimic> needs two revolute, continuous or "
                        "prismatic joints, and " +
                        pfxUrdfQuoted(j->name) + " is " + j->type);
      }
    }
    const JointText* step = &joint;
    for (std::size_t n = 0; n <= joints.size() && !step->mimic.empty(); ++n) {
      step = byName[step->mimic];
      if (step == &joint) {
        return fail(error, PFX_ERR_INVALID_VALUE,
                    "joint " + pfxUrdfQuoted(joint.name) + ": its <mimic> chain comes back to it");
      }
    }
  }
  return PFX_OK;
}

// The name of a <link> or <joint>, which must be there and must not repeat an earlier
// one (`lines` holds the line of each name so far).
PfxInt32 readName(const TiXmlElement* element, std::map<std::string, int>& lines, std::string& name,
                  PfxUrdfError& error) {
  const std::string kind = element->ValueStr();
  const char* text = element->Attribute("name");
  if (!text || !*text) {
    return fail(error, PFX_ERR_INVALID_VALUE,
                kind + " on line " + std::to_string(element->Row()) + ": no name");
  }
  name = text;
  if (const auto [it, inserted] = lines.emplace(name, element->Row()); !inserted) {
    return fail(error, PFX_ERR_INVALID_VALUE,
                kind + " " + pfxUrdfQuoted(name) + ": defined twice (lines " +
                    std::to_string(it->second) + " and " + std::to_string(element->Row()) + ")");
  }
  return PFX_OK;
}

// Collects urdfdom's log while it parses, for the error message.
class LogCapture : public console_bridge::OutputHandler {
 public:
  LogCapture() : m_previous(console_bridge::getOutputHandler()) {
    console_bridge::useOutputHandler(this);
  }
  ~LogCapture() override { console_bridge::useOutputHandler(m_previous); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (!m_text.empty()) m_text += "; ";
    m_text += text;
  }
  const std::string& text() const { return m_text; }

 private:
  console_bridge::OutputHandler* m_previous;
  std::string m_text;
};

}  // namespace

PfxInt32 pfxCheckUrdfXml(const std::string& xml, PfxUrdfDocumentOrder& order, PfxUrdfError& error) {
  TiXmlDocument document;
  document.Parse(xml.c_str());
  if (document.Error()) {
    std::ostringstream text;
    text << "line " << document.ErrorRow() << ", column " << document.ErrorCol()
         << ": malformed XML: " << document.ErrorDesc();
    return fail(error, PFX_ERR_INVALID_VALUE, text.str());
  }
  const TiXmlElement* robot = document.RootElement();
  if (!robot || robot->ValueStr() != "robot") {
    return fail(error, PFX_ERR_INVALID_VALUE, "robot: the top element is not <robot>");
  }
  if (checkNoXacro(robot, error) != PFX_OK) return error.code;
  if (!robot->Attribute("name")) return fail(error, PFX_ERR_INVALID_VALUE, "robot: no name");

  PfxUrdfDocumentOrder found;
  std::map<std::string, int> linkLines;
  std::string name;
  for (const TiXmlElement* link = robot->FirstChildElement("link"); link;
       link = link->NextSiblingElement("link")) {
    if (readName(link, linkLines, name, error) != PFX_OK) return error.code;
    const Subject subject{"link", name};
    if (checkInertial(link, subject, error) != PFX_OK ||
        readCollisions(link, subject, found.collisions[name], error) != PFX_OK) {
      return error.code;
    }
    found.links.push_back(name);
  }
  if (found.links.empty()) return fail(error, PFX_ERR_INVALID_VALUE, "robot: no links");

  std::vector<JointText> joints;
  std::map<std::string, int> jointLines;
  for (const TiXmlElement* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    if (readName(joint, jointLines, name, error) != PFX_OK) return error.code;
    JointText text;
    text.name = name;
    if (checkJoint(joint, text, error) != PFX_OK) return error.code;
    for (const std::string* link : {&text.parent, &text.child}) {
      if (linkLines.count(*link) == 0) {
        return fail(error, PFX_ERR_INVALID_VALUE,
                    "joint " + pfxUrdfQuoted(text.name) + ": " +
                        (link == &text.parent ? "parent" : "child") + " link " +
                        pfxUrdfQuoted(*link) + " is not defined");
      }
    }
    joints.push_back(text);
    found.joints.push_back(name);
  }
  if (checkTree(found.links, joints, error) != PFX_OK) return error.code;
  if (checkMimics(joints, error) != PFX_OK) return error.code;
  order = std::move(found);
  return PFX_OK;
}

urdf::ModelInterfaceSharedPtr pfxParseUrdfModel(const std::string& xml, PfxUrdfError& error) {
  urdf::ModelInterfaceSharedPtr model;
  std::string log;
  {
    const LogCapture capture;
    model = urdf::parseURDF(xml);
    log = capture.text();
  }
  if (!model) {
    fail(error, PFX_ERR_INVALID_VALUE,
         "robot: urdfdom rejected the description: " + (log.empty() ? "no reason given" : log));
  }
  return model;
}

}  // namespace pfx
