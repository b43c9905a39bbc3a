// The <sensor> elements of a URDF's <gazebo> blocks. Unlike the pfx scene reader, this one
// reads a format written for another simulator: an element it does not simulate is a warning
// rather than an error, so that a robot description loads unchanged; but a value it does use
// and cannot make sense of is an error, so that a typo never turns into a silent default.
#include "pfx/loaders/pfx_urdf_sensors.h"

#include <tinyxml2.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

namespace pfx {

namespace {

using tinyxml2::XMLElement;

// A number as text, all of it (surrounding spaces allowed); false when it does not read.
bool parseSensorNumber(const char* text, double& value) {
  if (!text) return false;
  char* end = nullptr;
  value = std::strtod(text, &end);
  if (end == text) return false;
  while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r') ++end;
  return *end == '\0';
}

std::string describe(const PfxSensorSpec& spec) { return "sensor '" + spec.name + "'"; }

class SensorReader {
 public:
  SensorReader(const std::string& where, std::vector<std::string>& warnings)
      : m_where(where), m_warnings(warnings) {}

  const std::string& error() const { return m_error; }

  bool fail(const std::string& path, const std::string& why) {
    m_error = m_where + ": <" + path + ">: " + why;
    return false;
  }

  // Warns about every child element of `e` whose name is not in `honoured`.
  void passOver(const XMLElement* e, const std::string& path,
                const std::set<std::string>& honoured) {
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (honoured.count(c->Name()) == 0) {
        m_warnings.push_back(m_where + ": <" + path + "><" + c->Name() + "> is ignored");
      }
    }
  }

  // The number in child `name` of `e`, if there is one (`value` unchanged otherwise). One
  // template for double and PfxFloat, which is double itself in a PFX_DOUBLE build.
  template <typename Real>
  bool number(const XMLElement* e, const char* name, const std::string& path, Real& value) {
    const XMLElement* c = e->FirstChildElement(name);
    if (!c) return true;
    double v;
    if (!parseSensorNumber(c->GetText(), v)) {
      return fail(path + "><" + name,
                  "'" + std::string(c->GetText() ? c->GetText() : "") + "' is not a number");
    }
    if (!std::isfinite(v)) return fail(path + "><" + name, "is not a finite number");
    value = Real(v);
    return true;
  }

  bool samples(const XMLElement* e, const std::string& path, PfxUInt32& value) {
    double v = value;
    if (!number(e, "samples", path, v)) return false;
    if (v < 1 || v != std::floor(v) || v > 1e6) {
      return fail(path + "><samples", "must be a whole number from 1 to 1000000");
    }
    value = PfxUInt32(v);
    return true;
  }

  // <noise><type>..</type><mean>..</mean><stddev>..</stddev></noise> (SDFormat 1.4's form
  // for rays and IMUs) or <noise type=".."> (1.5 and later).
  bool noise(const XMLElement* e, const std::string& path, PfxSensorNoise& noise) {
    const char* type = e->Attribute("type");
    if (const XMLElement* t = e->FirstChildElement("type")) type = t->GetText();
    const std::string kind = type ? type : "gaussian";
    if (kind == "none") {
      noise = PfxSensorNoise();
      passOver(e, path, {"type"});
      return true;
    }
    if (kind != "gaussian" && kind != "gaussian_quantized") {
      return fail(path + "><type", "'" + kind + "' is not a noise type pfx knows (none, gaussian)");
    }
    if (!number(e, "mean", path, noise.mean) || !number(e, "stddev", path, noise.stddev)) {
      return false;
    }
    if (noise.stddev < 0) return fail(path + "><stddev", "must not be negative");
    passOver(e, path, {"type", "mean", "stddev"});
    return true;
  }

  bool scanAxis(const XMLElement* e, const std::string& path, PfxUInt32& count, PfxFloat& minAngle,
                PfxFloat& maxAngle) {
    if (!samples(e, path, count) || !number(e, "min_angle", path, minAngle) ||
        !number(e, "max_angle", path, maxAngle)) {
      return false;
    }
    if (minAngle > maxAngle) {
      return fail(path + "><min_angle", "is above <max_angle>");
    }
    // Gazebo interpolates resolution * samples beams when resolution is not 1; pfx casts
    // every published beam, so a resolution of 1 is the only one it honours exactly.
    double resolution = 1;
    if (!number(e, "resolution", path, resolution)) return false;
    std::set<std::string> honoured = {"samples", "min_angle", "max_angle"};
    if (resolution == 1) honoured.insert("resolution");
    passOver(e, path, honoured);
    return true;
  }

  bool ray(const XMLElement* e, const std::string& path, PfxSensorSpec& spec) {
    PfxRangeSensorParam& r = spec.ray;
    if (const XMLElement* scan = e->FirstChildElement("scan")) {
      const std::string scanPath = path + "><scan";
      if (const XMLElement* h = scan->FirstChildElement("horizontal")) {
        if (!scanAxis(h, scanPath + "><horizontal", r.horizontalSamples, r.horizontalMinAngle,
                      r.horizontalMaxAngle)) {
          return false;
        }
      }
      if (const XMLElement* v = scan->FirstChildElement("vertical")) {
        if (!scanAxis(v, scanPath + "><vertical", r.verticalSamples, r.verticalMinAngle,
                      r.verticalMaxAngle)) {
          return false;
        }
      }
      passOver(scan, scanPath, {"horizontal", "vertical"});
    }
    const XMLElement* range = e->FirstChildElement("range");
    if (!range) return fail(path, "has no <range> (its <min> and <max> are required)");
    const std::string rangePath = path + "><range";
    if (!range->FirstChildElement("min") || !range->FirstChildElement("max")) {
      return fail(rangePath, "needs both <min> and <max>");
    }
    if (!number(range, "min", rangePath, r.rangeMin) ||
        !number(range, "max", rangePath, r.rangeMax)) {
      return false;
    }
    if (r.rangeMin < 0) return fail(rangePath + "><min", "must not be negative");
    if (r.rangeMax <= r.rangeMin) return fail(rangePath + "><max", "must be above <min>");
    passOver(range, rangePath, {"min", "max"});
    if (const XMLElement* n = e->FirstChildElement("noise")) {
      if (!noise(n, path + "><noise", spec.rangeNoise)) return false;
    }
    passOver(e, path, {"scan", "range", "noise"});
    return true;
  }

  // SDFormat 1.5+: <imu><angular_velocity><x><noise type="gaussian">..; 1.4 (as Gazebo 7
  // still reads it): <imu><noise><rate>..</rate><accel>..</accel></noise>.
  bool imu(const XMLElement* e, const std::string& path, PfxSensorSpec& spec) {
    static const char* const kAxes[3] = {"x", "y", "z"};
    const struct {
      const char* name;
      const char* oldName;
      PfxSensorNoise* noises;
    } kinds[2] = {{"angular_velocity", "rate", spec.angularVelocityNoise},
                  {"linear_acceleration", "accel", spec.linearAccelerationNoise}};
    for (const auto& kind : kinds) {
      const XMLElement* k = e->FirstChildElement(kind.name);
      if (!k) continue;
      const std::string kPath = path + "><" + kind.name;
      for (int axis = 0; axis < 3; ++axis) {
        const XMLElement* a = k->FirstChildElement(kAxes[axis]);
        if (!a) continue;
        const std::string aPath = kPath + "><" + kAxes[axis];
        if (const XMLElement* n = a->FirstChildElement("noise")) {
          if (!noise(n, aPath + "><noise", kind.noises[axis])) return false;
        }
        passOver(a, aPath, {"noise"});
      }
      passOver(k, kPath, {"x", "y", "z"});
    }
    if (const XMLElement* n = e->FirstChildElement("noise")) {
      const std::string nPath = path + "><noise";
      const XMLElement* t = n->FirstChildElement("type");
      const std::string kind = t && t->GetText() ? t->GetText() : "gaussian";
      if (kind != "none" && kind != "gaussian" && kind != "gaussian_quantized") {
        return fail(nPath + "><type",
                    "'" + kind + "' is not a noise type pfx knows (none, gaussian)");
      }
      for (const auto& k : kinds) {
        const XMLElement* part = n->FirstChildElement(k.oldName);
        if (!part || kind == "none") continue;
        PfxSensorNoise one;
        const std::string partPath = nPath + "><" + k.oldName;
        if (!number(part, "mean", partPath, one.mean) ||
            !number(part, "stddev", partPath, one.stddev)) {
          return false;
        }
        if (one.stddev < 0) return fail(partPath + "><stddev", "must not be negative");
        for (int axis = 0; axis < 3; ++axis) k.noises[axis] = one;
        passOver(part, partPath, {"mean", "stddev"});
      }
      passOver(n, nPath, {"type", "rate", "accel"});
    }
    passOver(e, path, {"angular_velocity", "linear_acceleration", "noise"});
    return true;
  }

  // <plugin> of gazebo_ros: the ROS topics and frame it would publish under
  // (gazebo_ros_bumper names its topic bumperTopicName; gazebo_ros_openni_kinect puts its
  // topics under cameraName).
  void plugin(const XMLElement* e, const std::string& path, PfxSensorSpec& spec) {
    for (const char* name : {"topicName", "bumperTopicName"}) {
      if (const XMLElement* t = e->FirstChildElement(name); t && t->GetText()) {
        spec.topic = t->GetText();
      }
    }
    const struct {
      const char* name;
      std::string* topic;
    } cameraTopics[3] = {{"depthImageTopicName", &spec.depthImageTopic},
                         {"depthImageCameraInfoTopicName", &spec.cameraInfoTopic},
                         {"pointCloudTopicName", &spec.pointsTopic}};
    std::set<std::string> honoured = {"topicName", "bumperTopicName", "frameName"};
    if (spec.type == PfxSensorType::kDepthCamera) {
      honoured.insert("cameraName");
      if (const XMLElement* c = e->FirstChildElement("cameraName"); c && c->GetText()) {
        spec.topic = c->GetText();
      }
      for (const auto& t : cameraTopics) {
        honoured.insert(t.name);
        if (const XMLElement* c = e->FirstChildElement(t.name); c && c->GetText()) {
          *t.topic = c->GetText();
        }
      }
    }
    if (const XMLElement* f = e->FirstChildElement("frameName"); f && f->GetText()) {
      spec.frame = f->GetText();
    }
    passOver(e, path, honoured);
  }

  // <camera>: <horizontal_fov>, <image><width>, <image><height>, <clip><near>, <clip><far>
  // and a <noise> on the depth.
  bool camera(const XMLElement* e, const std::string& path, PfxSensorSpec& spec) {
    PfxDepthCameraParam& c = spec.camera;
    if (!number(e, "horizontal_fov", path, c.horizontalFov)) return false;
    if (c.horizontalFov <= 0 || c.horizontalFov >= PfxFloat(3.14159265358979)) {
      return fail(path + "><horizontal_fov", "must be between 0 and pi");
    }
    if (const XMLElement* image = e->FirstChildElement("image")) {
      const std::string imagePath = path + "><image";
      for (const char* name : {"width", "height"}) {
        double v = name[0] == 'w' ? c.width : c.height;
        if (!number(image, name, imagePath, v)) return false;
        if (v < 1 || v > 4096 || v != std::floor(v)) {
          return fail(imagePath + "><" + name, "must be a whole number from 1 to 4096");
        }
        (name[0] == 'w' ? c.width : c.height) = PfxUInt32(v);
      }
      passOver(image, imagePath, {"width", "height"});
    }
    if (const XMLElement* clip = e->FirstChildElement("clip")) {
      const std::string clipPath = path + "><clip";
      if (!number(clip, "near", clipPath, c.nearClip) ||
          !number(clip, "far", clipPath, c.farClip)) {
        return false;
      }
      if (c.nearClip < 0) return fail(clipPath + "><near", "must not be negative");
      if (c.farClip <= c.nearClip) return fail(clipPath + "><far", "must be above <near>");
      passOver(clip, clipPath, {"near", "far"});
    }
    if (const XMLElement* n = e->FirstChildElement("noise")) {
      if (!noise(n, path + "><noise", spec.depthNoise)) return false;
    }
    passOver(e, path, {"horizontal_fov", "image", "clip", "noise"});
    return true;
  }

  // <force_torque><measure_direction> is honoured; the wrench is always given in the child
  // link's frame, so another <frame> is passed over with its warning.
  bool forceTorque(const XMLElement* e, const std::string& path, PfxSensorSpec& spec) {
    std::set<std::string> honoured = {"measure_direction"};
    if (const XMLElement* d = e->FirstChildElement("measure_direction")) {
      const std::string direction = d->GetText() ? d->GetText() : "";
      if (direction != "child_to_parent" && direction != "parent_to_child") {
        return fail(path + "><measure_direction",
                    "'" + direction + "' is neither child_to_parent nor parent_to_child");
      }
      spec.childToParent = direction == "child_to_parent";
    }
    if (const XMLElement* f = e->FirstChildElement("frame");
        f && f->GetText() && std::string(f->GetText()) == "child") {
      honoured.insert("frame");
    }
    passOver(e, path, honoured);
    return true;
  }

  bool pose(const XMLElement* e, const std::string& path, PfxTransform3& pose) {
    std::istringstream in(e->GetText() ? e->GetText() : "");
    double v[6];
    for (double& x : v) {
      std::string word;
      if (!(in >> word) || !parseSensorNumber(word.c_str(), x) || !std::isfinite(x)) {
        return fail(path, "must be six finite numbers: x y z roll pitch yaw");
      }
    }
    std::string extra;
    if (in >> extra) return fail(path, "must be six finite numbers: x y z roll pitch yaw");
    const PfxQuat rotation(Eigen::AngleAxis<PfxFloat>(PfxFloat(v[5]), PfxVector3::UnitZ()) *
                           Eigen::AngleAxis<PfxFloat>(PfxFloat(v[4]), PfxVector3::UnitY()) *
                           Eigen::AngleAxis<PfxFloat>(PfxFloat(v[3]), PfxVector3::UnitX()));
    pose = pfxMakeTransform(rotation, PfxVector3(PfxFloat(v[0]), PfxFloat(v[1]), PfxFloat(v[2])));
    return true;
  }

 private:
  std::string m_where;
  std::vector<std::string>& m_warnings;
  std::string m_error;
};

}  // namespace

std::string pfxCheckSensorSpec(const PfxSensorSpec& spec, const std::vector<std::string>& links,
                               const std::vector<std::string>& joints) {
  const std::string who = describe(spec);
  if (spec.name.empty()) return "a sensor has no name";
  bool known = false;
  if (spec.type == PfxSensorType::kForceTorque) {
    for (const std::string& joint : joints) known = known || joint == spec.joint;
    if (!known) return who + ": no joint named '" + spec.joint + "'";
  } else {
    for (const std::string& link : links) known = known || link == spec.link;
    if (!known) return who + ": no link named '" + spec.link + "'";
  }
  if (!std::isfinite(spec.updateRate) || spec.updateRate < 0) {
    return who + ": update rate must be a finite number of Hz > 0 (0: every step)";
  }
  if (!pfxIsFinite(PfxVector3(spec.pose.translation())) || !spec.pose.linear().allFinite()) {
    return who + ": pose is not finite";
  }
  auto checkNoise = [&](const PfxSensorNoise& n, const char* what) -> std::string {
    if (!std::isfinite(n.mean) || !std::isfinite(n.stddev)) {
      return who + ": " + what + " noise is not finite";
    }
    if (n.stddev < 0) return who + ": " + what + " noise stddev must not be negative";
    return "";
  };
  if (spec.type == PfxSensorType::kRay) {
    const PfxRangeSensorParam& r = spec.ray;
    if (r.horizontalSamples == 0 || r.verticalSamples == 0) {
      return who + ": samples must be at least 1";
    }
    if (!std::isfinite(r.horizontalMinAngle) || !std::isfinite(r.horizontalMaxAngle) ||
        !std::isfinite(r.verticalMinAngle) || !std::isfinite(r.verticalMaxAngle)) {
      return who + ": scan angles must be finite";
    }
    if (r.horizontalMinAngle > r.horizontalMaxAngle || r.verticalMinAngle > r.verticalMaxAngle) {
      return who + ": a minimum scan angle is above its maximum";
    }
    if (!std::isfinite(r.rangeMin) || !std::isfinite(r.rangeMax)) {
      return who + ": range min and max must be finite";
    }
    if (r.rangeMin < 0) return who + ": range min must not be negative";
    if (r.rangeMax <= r.rangeMin) return who + ": range max must be above range min";
    if (std::string why = checkNoise(spec.rangeNoise, "range"); !why.empty()) return why;
  }
  if (spec.type == PfxSensorType::kDepthCamera) {
    if (pfxCheckDepthCameraParam(spec.camera) != PFX_OK) {
      return who +
             ": the camera needs 1 to 4096 pixels each way, a field of view between 0 "
             "and pi, and 0 <= near < far, all finite";
    }
    if (std::string why = checkNoise(spec.depthNoise, "depth"); !why.empty()) return why;
  }
  if (spec.type == PfxSensorType::kImu) {
    for (int axis = 0; axis < 3; ++axis) {
      if (std::string why = checkNoise(spec.angularVelocityNoise[axis], "angular velocity");
          !why.empty()) {
        return why;
      }
      if (std::string why = checkNoise(spec.linearAccelerationNoise[axis], "linear acceleration");
          !why.empty()) {
        return why;
      }
    }
  }
  return "";
}

PfxInt32 pfxLoadUrdfSensors(const std::string& urdfXml, const std::string& fileName,
                            PfxUrdfSensors& out, std::string* message) {
  auto failWith = [&](const std::string& why) {
    if (message) *message = fileName + ": " + why;
    return PFX_ERR_INVALID_VALUE;
  };
  tinyxml2::XMLDocument document;
  if (document.Parse(urdfXml.c_str(), urdfXml.size()) != tinyxml2::XML_SUCCESS) {
    return failWith("line " + std::to_string(document.ErrorLineNum()) + ": not well-formed XML (" +
                    document.ErrorStr() + ")");
  }
  const XMLElement* robot = document.RootElement();
  std::vector<std::string> links;
  for (const XMLElement* l = robot->FirstChildElement("link"); l;
       l = l->NextSiblingElement("link")) {
    if (l->Attribute("name")) links.push_back(l->Attribute("name"));
  }
  // Joint names and their child links: a force_torque sensor refers to a joint.
  std::vector<std::string> joints, jointChildren;
  for (const XMLElement* j = robot->FirstChildElement("joint"); j;
       j = j->NextSiblingElement("joint")) {
    const XMLElement* child = j->FirstChildElement("child");
    if (!j->Attribute("name") || !child || !child->Attribute("link")) continue;
    joints.push_back(j->Attribute("name"));
    jointChildren.push_back(child->Attribute("link"));
  }

  PfxUrdfSensors result;
  std::set<std::string> names;
  for (const XMLElement* g = robot->FirstChildElement("gazebo"); g;
       g = g->NextSiblingElement("gazebo")) {
    const char* reference = g->Attribute("reference");
    const std::string block =
        reference ? "<gazebo reference='" + std::string(reference) + "'>" : "<gazebo>";
    for (const XMLElement* s = g->FirstChildElement("sensor"); s;
         s = s->NextSiblingElement("sensor")) {
      const char* name = s->Attribute("name");
      const char* type = s->Attribute("type");
      if (!name || !*name) return failWith(block + ": a <sensor> has no name attribute");
      const std::string where = block + " <sensor name='" + name + "'>";
      if (!reference)
        return failWith(where + ": a sensor belongs to a link: <gazebo reference='link'>");
      if (!type) return failWith(where + ": no type attribute");
      const std::string kind = type;
      const bool range =
          kind == "ray" || kind == "gpu_ray" || kind == "lidar" || kind == "gpu_lidar";
      const bool depth = kind == "depth" || kind == "depth_camera" || kind == "rgbd_camera";
      if (!range && !depth && kind != "imu" && kind != "contact" && kind != "force_torque") {
        result.warnings.push_back(where + ": type '" + kind + "' is not simulated; ignored");
        continue;
      }
      if (!names.insert(name).second) {
        return failWith(where + ": another sensor has this name already");
      }
      PfxSensorSpec spec;
      spec.name = name;
      spec.link = reference;
      spec.type = range               ? PfxSensorType::kRay
                  : depth             ? PfxSensorType::kDepthCamera
                  : kind == "imu"     ? PfxSensorType::kImu
                  : kind == "contact" ? PfxSensorType::kContact
                                      : PfxSensorType::kForceTorque;
      if (spec.type == PfxSensorType::kForceTorque) {
        spec.joint = reference;
        spec.link.clear();
        for (std::size_t j = 0; j < joints.size(); ++j) {
          if (joints[j] == spec.joint) spec.link = jointChildren[j];
        }
      }
      SensorReader reader(where, result.warnings);
      bool ok = true;
      // SDFormat reads a missing or zero rate as "as fast as possible"; an explicit rate
      // that is not positive is refused here, since it is most likely a mistake.
      if (s->FirstChildElement("update_rate")) {
        ok = reader.number(s, "update_rate", "sensor", spec.updateRate);
        if (ok && spec.updateRate <= 0) {
          ok = reader.fail("sensor><update_rate", "must be > 0 Hz (leave it out for every step)");
        }
      }
      if (ok) {
        if (const XMLElement* p = s->FirstChildElement("pose"))
          ok = reader.pose(p, "sensor><pose", spec.pose);
      }
      std::set<std::string> honoured = {"update_rate", "pose", "plugin"};
      if (ok && spec.type == PfxSensorType::kRay) {
        // SDFormat 1.7 renamed <ray> to <lidar>; descriptions in the wild mix the two.
        const XMLElement* ray = s->FirstChildElement("ray");
        if (!ray) ray = s->FirstChildElement("lidar");
        if (!ray) {
          ok = reader.fail("sensor", "a " + kind + " sensor needs a <ray> (or <lidar>) element");
        } else {
          ok = reader.ray(ray, std::string("sensor><") + ray->Name(), spec);
          honoured.insert(ray->Name());
        }
      }
      if (ok && spec.type == PfxSensorType::kImu) {
        if (const XMLElement* imu = s->FirstChildElement("imu"))
          ok = reader.imu(imu, "sensor><imu", spec);
        honoured.insert("imu");
      }
      if (ok && spec.type == PfxSensorType::kForceTorque) {
        if (const XMLElement* ft = s->FirstChildElement("force_torque")) {
          ok = reader.forceTorque(ft, "sensor><force_torque", spec);
        }
        honoured.insert("force_torque");
      }
      if (ok && spec.type == PfxSensorType::kDepthCamera) {
        const XMLElement* camera = s->FirstChildElement("camera");
        if (!camera) {
          ok = reader.fail("sensor", "a " + kind + " sensor needs a <camera> element");
        } else {
          ok = reader.camera(camera, "sensor><camera", spec);
        }
        honoured.insert("camera");
      }
      if (!ok) return failWith(reader.error());
      for (const XMLElement* plugin = s->FirstChildElement("plugin"); plugin;
           plugin = plugin->NextSiblingElement("plugin")) {
        reader.plugin(plugin, "sensor><plugin", spec);
      }
      if (std::string why = pfxCheckSensorSpec(spec, links, joints); !why.empty()) {
        return failWith(where + ": " + why);
      }
      reader.passOver(s, "sensor", honoured);
      result.sensors.push_back(spec);
    }
  }
  out = std::move(result);
  return PFX_OK;
}

}  // namespace pfx
