// The pfx scene XML reader (format: README, "Scene files"). The format is pfx's own, so it
// is strict: an unknown element or attribute is an error rather than something skipped,
// since a typo ("fricton") would otherwise change a simulation without a word.
#include <tinyxml2.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "loaders/pfx_scene_internal.h"
#include "pfx/base_level/collision/pfx_mass_properties.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfx {

namespace {

using tinyxml2::XMLElement;

struct Material {
  PfxFloat friction = PfxFloat(0.6);
  PfxFloat restitution = 0;
};

const std::map<std::string, PfxMotionType> kMotionTypes = {{"active", kPfxMotionTypeActive},
                                                           {"fixed", kPfxMotionTypeFixed},
                                                           {"keyframe", kPfxMotionTypeKeyframe},
                                                           {"one_way", kPfxMotionTypeOneWay},
                                                           {"trigger", kPfxMotionTypeTrigger}};

const std::map<std::string, PfxJointType> kJointTypes = {
    {"ball", kPfxJointBall},   {"swing_twist", kPfxJointSwingTwist},
    {"hinge", kPfxJointHinge}, {"slider", kPfxJointSlider},
    {"fixed", kPfxJointFixed}, {"universal", kPfxJointUniversal}};

const std::map<std::string, PfxUInt32> kJointAxisByName = {
    {"x", kPfxJointAxisX},           {"y", kPfxJointAxisY},
    {"z", kPfxJointAxisZ},           {"twist", kPfxJointAxisTwist},
    {"swing1", kPfxJointAxisSwing1}, {"swing2", kPfxJointAxisSwing2}};

class Reader {
 public:
  Reader(const std::string& basePath, PfxSceneBuild& build, PfxSceneError& error)
      : m_basePath(basePath), m_build(build), m_error(error) {}

  PfxInt32 read(const std::string& xml) {
    tinyxml2::XMLDocument document;
    if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
      return pfxSceneFail(m_error, PFX_ERR_INVALID_VALUE,
                          std::to_string(document.ErrorLineNum()) + ": not well-formed XML (" +
                              document.ErrorStr() + ")");
    }
    const XMLElement* root = document.RootElement();
    // A document of only a declaration, comments or text parses, and has no element.
    if (!root) {
      return pfxSceneFail(m_error, PFX_ERR_INVALID_VALUE, "1: no element (a <pfx_scene> root)");
    }
    if (std::string(root->Name()) != "pfx_scene") {
      return fail(root, "the root element must be <pfx_scene>");
    }
    if (!allow(root, {"version", "name"})) return m_error.code;
    const char* version = root->Attribute("version");
    if (!version || std::string(version) != "1") {
      return fail(root, "version must be \"1\" (the only version of the format)");
    }
    m_build.model.name = root->Attribute("name") ? root->Attribute("name") : "";
    bool sawWorld = false;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      PfxInt32 err = PFX_OK;
      if (tag == "world") {
        if (sawWorld) return fail(e, "a scene has one <world>");
        sawWorld = true;
        err = readWorld(e);
      } else if (tag == "material") {
        err = readMaterial(e);
      } else if (tag == "body") {
        err = readBody(e);
      } else if (tag == "joint") {
        err = readJoint(e);
      } else if (tag == "coupling") {
        err = readCoupling(e);
      } else {
        err = fail(e, "unknown element (a scene holds world, material, body, joint, coupling)");
      }
      if (err != PFX_OK) return err;
    }
    return PFX_OK;
  }

 private:
  // "<line>: <tag> '<name>': <reason>", or without the name when the element has none.
  PfxInt32 fail(const XMLElement* e, const std::string& reason,
                PfxInt32 code = PFX_ERR_INVALID_VALUE) {
    std::string text = std::to_string(e->GetLineNum()) + ": " + e->Name();
    if (const char* name = e->Attribute("name")) text += std::string(" '") + name + "'";
    return pfxSceneFail(m_error, code, text + ": " + reason);
  }

  bool allow(const XMLElement* e, std::initializer_list<const char*> names) {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      bool known = false;
      for (const char* name : names) known = known || std::string(name) == a->Name();
      if (!known) {
        fail(e, std::string("unknown attribute '") + a->Name() + "'");
        return false;
      }
    }
    return true;
  }

  // Reads `count` finite numbers from attribute `name` into out; absent leaves out alone.
  // Each check says what it wants, so that the error names the attribute and the value.
  bool numbers(const XMLElement* e, const char* name, double* out, int count, bool& present) {
    const char* text = e->Attribute(name);
    present = text != nullptr;
    if (!text) return true;
    const char* p = text;
    for (int i = 0; i < count; ++i) {
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(p, &end);
      // Finite also once in PfxFloat: 1e39 is a double but no float.
      if (end == p || errno == ERANGE || !std::isfinite(static_cast<PfxFloat>(value))) {
        fail(e, std::string(name) + "=\"" + text + "\": expected " + std::to_string(count) +
                    (count == 1 ? " finite number" : " finite numbers"));
        return false;
      }
      out[i] = value;
      p = end;
    }
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    if (*p != '\0') {
      fail(e, std::string(name) + "=\"" + text + "\": expected " + std::to_string(count) +
                  (count == 1 ? " number" : " numbers") + ", found more text");
      return false;
    }
    return true;
  }

  bool number(const XMLElement* e, const char* name, PfxFloat& out) {
    double value = 0;
    bool present = false;
    if (!numbers(e, name, &value, 1, present)) return false;
    if (present) out = static_cast<PfxFloat>(value);
    return true;
  }

  bool vector(const XMLElement* e, const char* name, PfxVector3& out) {
    double v[3];
    bool present = false;
    if (!numbers(e, name, v, 3, present)) return false;
    if (present) out = PfxVector3(PfxFloat(v[0]), PfxFloat(v[1]), PfxFloat(v[2]));
    return true;
  }

  // A count or bit mask: decimal or 0x hexadecimal, within [low, high].
  bool integer(const XMLElement* e, const char* name, unsigned long low, unsigned long high,
               PfxUInt32& out) {
    const char* text = e->Attribute(name);
    if (!text) return true;
    char* end = nullptr;
    errno = 0;
    const unsigned long value = std::strtoul(text, &end, 0);
    if (end == text || *end != '\0' || errno == ERANGE || text[0] == '-' || value < low ||
        value > high) {
      fail(e, std::string(name) + "=\"" + text + "\": expected a whole number in [" +
                  std::to_string(low) + ", " + std::to_string(high) + "]");
      return false;
    }
    out = static_cast<PfxUInt32>(value);
    return true;
  }

  bool positive(const XMLElement* e, const char* name, PfxFloat value) {
    if (value > 0) return true;
    fail(e, std::string(name) + " must be positive");
    return false;
  }

  bool inUnit(const XMLElement* e, const char* name, PfxFloat value) {
    if (value >= 0 && value <= 1) return true;
    fail(e, std::string(name) + " must lie in [0, 1]");
    return false;
  }

  // position="x y z" with rpy="roll pitch yaw" (radians, about fixed X, then Y, then Z, as
  // URDF and SDF turn) or quat="w x y z" (normalised; far from unit length is an error).
  bool pose(const XMLElement* e, PfxVector3& position, PfxQuat& orientation) {
    position.setZero();
    orientation.setIdentity();
    if (!vector(e, "position", position)) return false;
    double rpy[3], q[4];
    bool hasRpy = false, hasQuat = false;
    if (!numbers(e, "rpy", rpy, 3, hasRpy) || !numbers(e, "quat", q, 4, hasQuat)) return false;
    if (hasRpy && hasQuat) {
      fail(e, "give rpy or quat, not both");
      return false;
    }
    if (hasRpy) {
      orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(PfxFloat(rpy[2]), PfxVector3::UnitZ()) *
                            Eigen::AngleAxis<PfxFloat>(PfxFloat(rpy[1]), PfxVector3::UnitY()) *
                            Eigen::AngleAxis<PfxFloat>(PfxFloat(rpy[0]), PfxVector3::UnitX()));
    } else if (hasQuat) {
      const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (std::abs(norm - 1) > 1e-3) {
        fail(e, "quat is not a unit quaternion (length " + std::to_string(norm) + ")");
        return false;
      }
      orientation = PfxQuat(PfxFloat(q[0] / norm), PfxFloat(q[1] / norm), PfxFloat(q[2] / norm),
                            PfxFloat(q[3] / norm));
    }
    return true;
  }

  PfxInt32 readWorld(const XMLElement* e) {
    if (!allow(e, {"gravity", "time_step", "sub_steps", "iterations", "pipeline", "contact_slop",
                   "contact_margin", "separate_bias", "restitution_threshold", "sleep", "center",
                   "extent"})) {
      return m_error.code;
    }
    PfxWorldParam& p = m_build.param;
    m_build.hasPhysics = true;
    if (!vector(e, "gravity", p.gravity) || !number(e, "time_step", p.timeStep) ||
        !positive(e, "time_step", p.timeStep) || !integer(e, "sub_steps", 1, PFX_MAX_SUB_STEPS, p.subStep) ||
        !integer(e, "iterations", 1, PFX_MAX_ITERATIONS, p.iteration) ||
        !number(e, "contact_slop", p.contactSlop) ||
        !number(e, "contact_margin", p.contactMargin) ||
        !number(e, "separate_bias", p.separateBias) ||
        !number(e, "restitution_threshold", p.restitutionThreshold) ||
        !vector(e, "center", p.worldCenter) || !vector(e, "extent", p.worldExtent)) {
      return m_error.code;
    }
    if (!(p.contactSlop >= 0) || !(p.contactMargin >= 0) || !(p.restitutionThreshold >= 0)) {
      return fail(e, "contact_slop, contact_margin and restitution_threshold must be >= 0");
    }
    if (!inUnit(e, "separate_bias", p.separateBias)) return m_error.code;
    if (!(p.worldExtent.minCoeff() > 0)) return fail(e, "extent must be positive on each axis");
    if (const char* pipeline = e->Attribute("pipeline")) {
      const std::string name = pipeline;
      if (name != "stable" && name != "simple") {
        return fail(e, "pipeline=\"" + name + "\": expected stable or simple");
      }
      p.pipeline = name == "stable" ? kPfxPipelineStable : kPfxPipelineSimple;
    }
    if (e->Attribute("sleep") && e->QueryBoolAttribute("sleep", &p.enableSleep) != 0) {
      return fail(e, "sleep must be true or false");
    }
    return PFX_OK;
  }

  PfxInt32 readMaterial(const XMLElement* e) {
    if (!allow(e, {"name", "friction", "restitution"})) return m_error.code;
    const char* name = e->Attribute("name");
    if (!name || !*name) return fail(e, "a material needs a name");
    if (m_materials.count(name)) return fail(e, "a material of that name already exists");
    Material m;
    if (!readMaterialValues(e, m)) return m_error.code;
    m_materials[name] = m;
    return PFX_OK;
  }

  bool readMaterialValues(const XMLElement* e, Material& m) {
    if (!number(e, "friction", m.friction) || !number(e, "restitution", m.restitution)) {
      return false;
    }
    if (!(m.friction >= 0)) {
      fail(e, "friction must be >= 0");
      return false;
    }
    return inUnit(e, "restitution", m.restitution);
  }

  // One shape element of a body; `moves`: whether forces move the body (a large mesh
  // cannot: it has no volume, so no mass).
  PfxInt32 readShape(const XMLElement* e, bool moves, PfxShape& shape) {
    const std::string tag = e->Name();
    PfxVector3 offset;
    PfxQuat rotation;
    if (tag == "sphere") {
      PfxFloat radius = 0;
      if (!allow(e, {"radius", "position", "rpy", "quat"}) || !number(e, "radius", radius) ||
          !positive(e, "radius", radius)) {
        return m_error.code;
      }
      shape = pfxMakeShape(PfxSphere(radius));
    } else if (tag == "box") {
      PfxVector3 size = PfxVector3::Zero();
      if (!allow(e, {"size", "position", "rpy", "quat"}) || !vector(e, "size", size)) {
        return m_error.code;
      }
      if (!(size.minCoeff() > 0)) return fail(e, "size must be positive on each axis");
      shape = pfxMakeShape(PfxBox(size / 2));
    } else if (tag == "capsule" || tag == "cylinder") {
      PfxFloat radius = 0, length = 0;
      if (!allow(e, {"radius", "length", "position", "rpy", "quat"}) ||
          !number(e, "radius", radius) || !number(e, "length", length) ||
          !positive(e, "radius", radius) || !positive(e, "length", length)) {
        return m_error.code;
      }
      shape = tag == "capsule" ? pfxMakeShape(PfxCapsule(length / 2, radius))
                               : pfxMakeShape(PfxCylinder(length / 2, radius));
    } else if (tag == "convex_mesh" || tag == "large_mesh") {
      if (!allow(e, {"file", "scale", "position", "rpy", "quat"})) return m_error.code;
      if (tag == "large_mesh" && moves) {
        return fail(e,
                    "a large mesh has no volume, so only a body that forces do not move "
                    "(fixed, keyframe, trigger) may hold one; use convex_mesh");
      }
      const char* file = e->Attribute("file");
      if (!file || !*file) return fail(e, "needs a file");
      PfxVector3 scale = PfxVector3::Ones();
      if (!vector(e, "scale", scale)) return m_error.code;
      if (!(scale.minCoeff() > 0)) return fail(e, "scale must be positive on each axis");
      const std::filesystem::path given(file);
      const std::string path = given.is_absolute()
                                   ? given.string()
                                   : (std::filesystem::path(m_basePath) / given).string();
      std::string reason;
      if (const PfxInt32 err =
              pfxMakeSceneMeshShape(path, scale, tag == "large_mesh", m_build, shape, reason);
          err != PFX_OK) {
        return fail(e, reason, err);
      }
    } else {
      return fail(e, "unknown shape (sphere, box, capsule, cylinder, convex_mesh, large_mesh)");
    }
    if (!pose(e, offset, rotation)) return m_error.code;
    shape.setOffsetPosition(offset);
    shape.setOffsetOrientation(rotation);
    return PFX_OK;
  }

  PfxInt32 readBody(const XMLElement* e) {
    if (!allow(e, {"name", "motion", "position", "rpy", "quat", "velocity", "angular_velocity",
                   "mass", "inertia", "material", "friction", "restitution", "filter_self",
                   "filter_target"})) {
      return m_error.code;
    }
    const char* name = e->Attribute("name");
    if (!name || !*name) return fail(e, "a body needs a name");
    if (m_bodies.count(name)) return fail(e, "a body of that name already exists");
    PfxMotionType motion = kPfxMotionTypeActive;
    if (const char* text = e->Attribute("motion")) {
      const auto it = kMotionTypes.find(text);
      if (it == kMotionTypes.end()) {
        return fail(e, std::string("motion=\"") + text +
                           "\": expected active, fixed, keyframe, one_way or trigger");
      }
      motion = it->second;
    }
    const bool moves = pfxMotionTypeIsDynamic(motion);
    PfxSceneBuildBody body;
    body.state.reset();
    body.body.reset();
    body.state.setMotionType(motion);
    PfxVector3 position, velocity = PfxVector3::Zero(), angular = PfxVector3::Zero();
    PfxQuat orientation;
    if (!pose(e, position, orientation) || !vector(e, "velocity", velocity) ||
        !vector(e, "angular_velocity", angular)) {
      return m_error.code;
    }
    body.state.setPosition(position);
    body.state.setOrientation(orientation);
    body.state.setLinearVelocity(velocity);
    body.state.setAngularVelocity(angular);
    PfxUInt32 self = body.state.getContactFilterSelf(),
              target = body.state.getContactFilterTarget();
    if (!integer(e, "filter_self", 0, 0xffffffffu, self) ||
        !integer(e, "filter_target", 0, 0xffffffffu, target)) {
      return m_error.code;
    }
    body.state.setContactFilterSelf(self);
    body.state.setContactFilterTarget(target);
    Material material;
    if (const char* text = e->Attribute("material")) {
      const auto it = m_materials.find(text);
      if (it == m_materials.end()) {
        return fail(e, std::string("material '") + text + "' is not defined above the body");
      }
      material = it->second;
    }
    if (!readMaterialValues(e, material)) return m_error.code;
    body.body.setFriction(material.friction);
    body.body.setRestitution(material.restitution);

    for (const XMLElement* s = e->FirstChildElement(); s; s = s->NextSiblingElement()) {
      if (body.shapes.size() == PFX_MAX_SHAPES_PER_COLLIDABLE) {
        return fail(e, "more than " + std::to_string(PFX_MAX_SHAPES_PER_COLLIDABLE) + " shapes",
                    PFX_ERR_OUT_OF_RANGE);
      }
      PfxShape shape;
      if (readShape(s, moves, shape) != PFX_OK) return m_error.code;
      body.shapes.push_back(shape);
    }
    if (body.shapes.empty()) return fail(e, "a body needs at least one shape");
    if (readMass(e, moves, body) != PFX_OK) return m_error.code;
    m_bodies[name] = static_cast<PfxUInt32>(m_build.bodies.size());
    m_build.bodies.push_back(std::move(body));
    PfxSceneBody out;
    out.name = name;
    out.bodyId = m_bodies[name];
    m_build.model.bodies.push_back(out);
    return PFX_OK;
  }

  // Mass and inertia of a body that forces move: mass is required; inertia (about the
  // body's origin, which is its centre of mass) is given, or that of the shapes as a
  // uniform solid of that mass about the origin.
  PfxInt32 readMass(const XMLElement* e, bool moves, PfxSceneBuildBody& body) {
    const bool hasMass = e->Attribute("mass"), hasInertia = e->Attribute("inertia");
    if (!moves) {
      if (hasMass || hasInertia) {
        return fail(e, "mass and inertia apply only to active and one_way bodies");
      }
      return PFX_OK;
    }
    PfxFloat mass = 0;
    if (!hasMass) return fail(e, "an active or one_way body needs a mass");
    if (!number(e, "mass", mass) || !positive(e, "mass", mass)) return m_error.code;
    PfxMatrix3 inertia;
    if (hasInertia) {
      double v[6];
      bool present = false;
      if (!numbers(e, "inertia", v, 6, present)) return m_error.code;
      inertia << PfxFloat(v[0]), PfxFloat(v[3]), PfxFloat(v[4]), PfxFloat(v[3]), PfxFloat(v[1]),
          PfxFloat(v[5]), PfxFloat(v[4]), PfxFloat(v[5]), PfxFloat(v[2]);
    } else {
      const std::vector<PfxFloat> densities(body.shapes.size(), PfxFloat(1));
      const PfxMassProperties unit = pfxCalcMassPropertiesCompound(
          body.shapes.data(), densities.data(), static_cast<PfxUInt32>(body.shapes.size()));
      if (!(unit.mass > 0)) return fail(e, "the shapes have no volume to take an inertia from");
      inertia = pfxMassTranslate(mass, unit.inertia * (mass / unit.mass), unit.centerOfMass);
    }
    body.body.setMass(mass);
    body.body.setInertia(inertia);
    if (const char* problem = body.body.problem()) {
      return fail(e, std::string("inertia (ixx iyy izz ixy ixz iyz) or mass: ") + problem);
    }
    return PFX_OK;
  }

  PfxInt32 bodyIndex(const XMLElement* e, const char* attribute, PfxUInt32& index) {
    const char* name = e->Attribute(attribute);
    if (!name) return fail(e, std::string("needs ") + attribute);
    const auto it = m_bodies.find(name);
    if (it == m_bodies.end()) {
      return fail(e, std::string(attribute) + " '" + name + "' is not a body defined above");
    }
    index = it->second;
    return PFX_OK;
  }

  PfxInt32 readJoint(const XMLElement* e) {
    if (!allow(e, {"name", "type", "body_a", "body_b", "anchor", "axis", "up"})) {
      return m_error.code;
    }
    const char* name = e->Attribute("name");
    if (!name || !*name) return fail(e, "a joint needs a name");
    if (m_joints.count(name)) return fail(e, "a joint of that name already exists");
    const char* type = e->Attribute("type");
    const auto it = type ? kJointTypes.find(type) : kJointTypes.end();
    if (it == kJointTypes.end()) {
      return fail(e, "type must be ball, swing_twist, hinge, slider, fixed or universal");
    }
    PfxUInt32 a = 0, b = 0;
    if (bodyIndex(e, "body_a", a) != PFX_OK || bodyIndex(e, "body_b", b) != PFX_OK) {
      return m_error.code;
    }
    if (a == b) return fail(e, "body_a and body_b are the same body");
    PfxVector3 anchor = PfxVector3::Zero(), axis = PfxVector3::UnitX(), up = PfxVector3::UnitY();
    if (!vector(e, "anchor", anchor) || !vector(e, "axis", axis) || !vector(e, "up", up)) {
      return m_error.code;
    }
    if (!(axis.norm() > PfxFloat(1e-6))) return fail(e, "axis has no direction");
    PfxJoint joint;
    if (pfxInitSceneJoint(it->second, m_build, a, b, anchor, pfxSceneFrame(axis, up), joint) !=
        PFX_OK) {
      return fail(e, "the joint cannot be set up between these bodies");
    }
    for (const XMLElement* x = e->FirstChildElement(); x; x = x->NextSiblingElement()) {
      if (std::string(x->Name()) != "axis") return fail(x, "unknown element (a joint holds axis)");
      if (readAxis(x, joint) != PFX_OK) return m_error.code;
    }
    if (pfxCheckJoint(joint) != PFX_OK) {
      return fail(e, "the axes' values are not valid together (pfxCheckJoint)");
    }
    PfxSceneJoint out;
    out.name = name;
    out.type = type;
    out.parent = e->Attribute("body_a");
    out.child = e->Attribute("body_b");
    out.jointId = static_cast<PfxUInt32>(m_build.joints.size());
    switch (it->second) {
      case kPfxJointHinge:
        out.axes[0] = kPfxJointAxisTwist;
        break;
      case kPfxJointSlider:
        out.axes[0] = kPfxJointAxisX;
        break;
      case kPfxJointUniversal:
        out.axes[0] = kPfxJointAxisSwing1;
        out.axes[1] = kPfxJointAxisSwing2;
        break;
      default:
        break;
    }
    m_joints[name] = out.jointId;
    m_build.joints.push_back(joint);
    m_build.model.joints.push_back(out);
    return PFX_OK;
  }

  // <axis index="twist" lock= lower= upper= damping= friction= bias= weight= drive= target=
  // max_force=/>: overrides what the joint type set up on one of its six axes.
  PfxInt32 readAxis(const XMLElement* x, PfxJoint& joint) {
    if (!allow(x, {"index", "lock", "lower", "upper", "damping", "friction", "bias", "weight",
                   "drive", "target", "max_force"})) {
      return m_error.code;
    }
    const char* index = x->Attribute("index");
    const auto axis = index ? kJointAxisByName.find(index) : kJointAxisByName.end();
    if (axis == kJointAxisByName.end())
      return fail(x, "index must be x, y, z, twist, swing1 or swing2");
    PfxJointConstraint& c = joint.m_constraints[axis->second];
    const bool hasLimit = x->Attribute("lower") || x->Attribute("upper");
    if (!number(x, "lower", c.m_movableLowerLimit) || !number(x, "upper", c.m_movableUpperLimit) ||
        !number(x, "damping", c.m_damping) || !number(x, "friction", c.m_friction) ||
        !number(x, "bias", c.m_bias) || !number(x, "weight", c.m_weight) ||
        !number(x, "target", c.m_driveTarget) || !number(x, "max_force", c.m_driveMaxForce)) {
      return m_error.code;
    }
    if (const char* lock = x->Attribute("lock")) {
      const std::string l = lock;
      if (l != "free" && l != "locked" && l != "limit") {
        return fail(x, "lock=\"" + l + "\": expected free, locked or limit");
      }
      c.m_lock = l == "free" ? kPfxJointLockFree
                             : (l == "locked" ? kPfxJointLockLocked : kPfxJointLockLimit);
    } else if (hasLimit) {
      c.m_lock = kPfxJointLockLimit;
    }
    if (c.m_lock == kPfxJointLockLimit && !(c.m_movableLowerLimit <= c.m_movableUpperLimit)) {
      return fail(x, "lower is above upper");
    }
    if (!inUnit(x, "damping", c.m_damping) || !inUnit(x, "bias", c.m_bias) ||
        !inUnit(x, "weight", c.m_weight)) {
      return m_error.code;
    }
    if (!(c.m_friction >= 0) || !(c.m_driveMaxForce >= 0)) {
      return fail(x, "friction and max_force must be >= 0");
    }
    if (const char* drive = x->Attribute("drive")) {
      const std::string d = drive;
      if (d != "none" && d != "velocity" && d != "position") {
        return fail(x, "drive=\"" + d + "\": expected none, velocity or position");
      }
      c.m_drive = d == "none" ? kPfxJointDriveNone
                              : (d == "velocity" ? kPfxJointDriveVelocity : kPfxJointDrivePosition);
    }
    return PFX_OK;
  }

  PfxInt32 readCoupling(const XMLElement* e) {
    if (!allow(e, {"name", "leader", "leader_axis", "follower", "follower_axis", "multiplier",
                   "offset", "bias", "max_force"})) {
      return m_error.code;
    }
    const char* name = e->Attribute("name");
    if (!name || !*name) return fail(e, "a coupling needs a name");
    PfxJointCoupling coupling;
    coupling.reset();
    const char* names[2] = {e->Attribute("leader"), e->Attribute("follower")};
    const char* axes[2] = {e->Attribute("leader_axis"), e->Attribute("follower_axis")};
    PfxUInt32 joints[2], axisIds[2];
    for (int i = 0; i < 2; ++i) {
      const auto joint = names[i] ? m_joints.find(names[i]) : m_joints.end();
      if (joint == m_joints.end()) {
        return fail(
            e, std::string(i == 0 ? "leader" : "follower") + " must name a joint defined above");
      }
      const auto axis = axes[i] ? kJointAxisByName.find(axes[i]) : kJointAxisByName.end();
      if (axis == kJointAxisByName.end()) {
        return fail(e, std::string(i == 0 ? "leader_axis" : "follower_axis") +
                           " must be x, y, z, twist, swing1 or swing2");
      }
      joints[i] = joint->second;
      axisIds[i] = axis->second;
    }
    coupling.m_leaderJointId = joints[0];
    coupling.m_followerJointId = joints[1];
    coupling.m_leaderAxis = static_cast<PfxUInt8>(axisIds[0]);
    coupling.m_followerAxis = static_cast<PfxUInt8>(axisIds[1]);
    if (!number(e, "multiplier", coupling.m_multiplier) ||
        !number(e, "offset", coupling.m_offset) || !number(e, "bias", coupling.m_bias) ||
        !number(e, "max_force", coupling.m_maxImpulseForce) ||
        !inUnit(e, "bias", coupling.m_bias)) {
      return m_error.code;
    }
    if (pfxCheckJointCoupling(coupling, m_build.joints.data(),
                              static_cast<PfxUInt32>(m_build.joints.size())) != PFX_OK) {
      return fail(e, "an axis is locked, or leader and follower are the same axis");
    }
    PfxSceneCoupling out;
    out.name = name;
    out.couplingId = static_cast<PfxUInt32>(m_build.couplings.size());
    m_build.couplings.push_back(coupling);
    m_build.model.couplings.push_back(out);
    return PFX_OK;
  }

  std::string m_basePath;
  PfxSceneBuild& m_build;
  PfxSceneError& m_error;
  std::map<std::string, Material> m_materials;
  std::map<std::string, PfxUInt32> m_bodies;
  std::map<std::string, PfxUInt32> m_joints;
};

}  // namespace

PfxInt32 pfxReadSceneXml(const std::string& xml, const std::string& basePath, PfxSceneBuild& build,
                         PfxSceneError& error) {
  return Reader(basePath, build, error).read(xml);
}

}  // namespace pfx
