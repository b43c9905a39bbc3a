// MuJoCo behind the benchmark's interface: the scene written as MJCF (fixed bodies as
// geoms of the world body, dynamic ones as bodies with explicit inertia), compiled from an
// in-memory file, stepped with mj_step at dt / substeps and the default solver. Jointed
// bodies are nested in the body tree, each below its parent with a ball or hinge joint at
// the anchor (the first body of a chain hanging from the world is a child of the world
// body); every body without a parent gets a free joint. MuJoCo's capsules and cylinders
// lie along Z; their geoms are turned onto X. Motors are velocity actuators (a velocity
// servo clamped to the motor's torque), stepped with MuJoCo's implicit integrator.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>
#include <string>

#include "bench_engine.h"

namespace pfxbench {

namespace {

// MuJoCo reports fatal errors through a hook and exits when none is set; an exception
// turns them into a failed run instead.
void throwMujocoError(const char* message) { throw std::runtime_error(message); }

void printMujocoWarning(const char* message) { std::fprintf(stderr, "mujoco: %s\n", message); }

void installMujocoHooks() {
  mju_user_error = throwMujocoError;
  mju_user_warning = printMujocoWarning;
}

std::ostream& operator<<(std::ostream& out, const Vec3& v) {
  return out << v.x() << ' ' << v.y() << ' ' << v.z();
}

std::ostream& operator<<(std::ostream& out, const Quat& q) {
  return out << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z();
}

void writeGeom(std::ostream& out, const BodyDesc& body) {
  const ShapeDesc& shape = body.shape;
  out << "<geom friction=\"" << body.friction << " 0 0\"";
  switch (shape.type) {
    case ShapeType::Sphere: out << " type=\"sphere\" size=\"" << shape.radius << '"'; break;
    case ShapeType::Box: out << " type=\"box\" size=\"" << shape.halfExtents << '"'; break;
    case ShapeType::Capsule:
    case ShapeType::Cylinder:
      out << " type=\"" << (shape.type == ShapeType::Capsule ? "capsule" : "cylinder")
          << "\" size=\"" << shape.radius << ' ' << shape.halfLength
          << "\" quat=\"0.70710678118654752 0 0.70710678118654752 0\"";
      break;
  }
  if (body.fixed) out << " pos=\"" << body.position << "\" quat=\"" << body.orientation << '"';
  out << "/>\n";
}

Vec3 inFrame(const Vec3& position, const Quat& orientation, const Vec3& point) {
  return orientation.conjugate() * (point - position);
}

// Pose of a body relative to its parent (the world when it has none), as MJCF nests them.
struct RelativePose {
  Vec3 position;
  Quat orientation;
};

RelativePose poseInParent(const Scene& scene, const JointForest& forest, int body) {
  const BodyDesc& desc = scene.bodies[body];
  const int parent = forest.parentBody[body];
  if (parent == kWorld) return {desc.position, desc.orientation};
  const BodyDesc& p = scene.bodies[parent];
  return {inFrame(p.position, p.orientation, desc.position),
          p.orientation.conjugate() * desc.orientation};
}

// The model as in-memory files, the main one first. A chain is nested one body inside the
// next, and MuJoCo's XML parser refuses documents nested deeper than 100 elements, so a
// deep tree continues in a further file, pulled in with <include> where it branches off.
struct MjcfFiles {
  std::vector<std::string> names;
  std::vector<std::string> texts;
};

constexpr int kMaxBodyDepthPerFile = 64;

// A velocity actuator is a damper towards the target rate, not a constraint: its gain is
// chosen so that it gives the motor's full torque at a rate error of this share of the
// motor's top speed. Stiffer is not closer to the other engines' motors: the implicit
// integrator linearises the servo as if it were never clamped, so a servo that clamps at
// every change of its command (at 1 % the arm's did) hardly moves its joint, and the arm
// fell 1-2.5 rad behind its reference at dt 1/60.
constexpr double kServoSlip = 0.1;

// A hinge's MuJoCo coordinate is the child body's turn relative to its parent: the scene's
// angle, or its opposite where the scene names the child first.
double hingeSign(const JointDesc& joint, int child) { return joint.bodyB == child ? 1 : -1; }

std::ostringstream precisionStream() {
  std::ostringstream out;
  out.precision(17);
  return out;
}

struct MjcfWriter {
  const Scene& scene;
  const JointForest& forest;
  std::vector<std::vector<int>> children;
  MjcfFiles files;

  void writeBody(std::ostream& out, int index, int depth) {
    const BodyDesc& body = scene.bodies[index];
    const RelativePose pose = poseInParent(scene, forest, index);
    out << "<body name=\"b" << index << "\" pos=\"" << pose.position << "\" quat=\""
        << pose.orientation << "\">\n";
    const int jointIndex = forest.parentJoint[index];
    if (jointIndex < 0) {
      out << "<freejoint/>\n";
    } else {
      const JointDesc& joint = scene.joints[jointIndex];
      out << "<joint name=\"j" << jointIndex << "\" pos=\""
          << inFrame(body.position, body.orientation, joint.anchor) << '"';
      if (joint.type == JointType::Ball) {
        out << " type=\"ball\"/>\n";
      } else {
        out << " type=\"hinge\" axis=\"" << body.orientation.conjugate() * joint.axis.normalized()
            << '"';
        if (joint.limited()) {
          const double sign = hingeSign(joint, index);
          const double a = sign * joint.lowerLimit, b = sign * joint.upperLimit;
          out << " limited=\"true\" range=\"" << std::min(a, b) << ' ' << std::max(a, b) << '"';
        }
        out << "/>\n";
      }
    }
    out << "<inertial pos=\"0 0 0\" mass=\"" << body.mass << "\" diaginertia=\"" << body.inertia
        << "\"/>\n";
    writeGeom(out, body);
    for (int child : children[index]) {
      if (depth + 1 < kMaxBodyDepthPerFile) {
        writeBody(out, child, depth + 1);
        continue;
      }
      const std::size_t slot = files.names.size();
      files.names.push_back("part" + std::to_string(slot) + ".xml");
      files.texts.emplace_back();
      std::ostringstream part = precisionStream();
      part << "<mujoco>\n";
      writeBody(part, child, 0);
      part << "</mujoco>\n";
      files.texts[slot] = part.str();
      out << "<include file=\"" << files.names[slot] << "\"/>\n";
    }
    out << "</body>\n";
  }
};

// MuJoCo makes up to eight contacts per box pair (about 8.5 per box in the pyramid); each
// takes four constraint rows (njmax) with the pyramidal cone and condim 3.
int maxContactsOf(const Scene& scene) {
  int numDynamic = 0;
  for (const BodyDesc& body : scene.bodies) numDynamic += body.fixed ? 0 : 1;
  return 100 + 10 * numDynamic;
}

MjcfFiles writeMjcf(const Scene& scene, const JointForest& forest,
                    const EngineSettings& settings) {
  MjcfWriter writer{scene, forest, std::vector<std::vector<int>>(scene.bodies.size()), {}};
  for (int body : forest.order) {
    if (forest.parentBody[body] != kWorld) writer.children[forest.parentBody[body]].push_back(body);
  }
  writer.files.names.push_back("scene.xml");
  writer.files.texts.emplace_back();

  std::ostringstream out = precisionStream();
  const int maxContacts = maxContactsOf(scene);
  // The velocity servos blow the arm up within 0.1 s in the default Euler integrator at dt
  // 1/30 and 1/60.
  const char* integrator = scene.motors.empty() ? "Euler" : "implicit";
  out << "<mujoco model=\"" << scene.name << "\">\n"
      << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "<option timestep=\"" << settings.dt / settings.substeps << "\" iterations=\""
      << settings.iterations << "\" gravity=\"" << scene.gravity << "\" integrator=\""
      << integrator << "\"/>\n"
      << "<size nconmax=\"" << maxContacts << "\" njmax=\"" << 4 * maxContacts << "\"/>\n"
      << "<worldbody>\n";
  for (const BodyDesc& body : scene.bodies) {
    if (body.fixed) writeGeom(out, body);
  }
  for (int body : forest.order) {
    if (forest.parentBody[body] == kWorld) writer.writeBody(out, body, 0);
  }
  out << "</worldbody>\n";
  if (!scene.motors.empty()) {
    out << "<actuator>\n";
    for (const JointMotorDesc& motor : scene.motors) {
      out << "<velocity joint=\"j" << motor.joint << "\" kv=\""
          << motor.maxTorque / (kServoSlip * motor.maxSpeed)
          << "\" forcelimited=\"true\" forcerange=\"" << -motor.maxTorque << ' '
          << motor.maxTorque << "\"/>\n";
    }
    out << "</actuator>\n";
  }
  out << "</mujoco>\n";
  writer.files.texts[0] = out.str();
  return writer.files;
}

int degreesOfFreedom(const Scene& scene, const JointForest& forest) {
  int dofs = 0;
  for (int body : forest.order) {
    const int joint = forest.parentJoint[body];
    if (joint < 0) {
      dofs += 6;
    } else {
      dofs += scene.joints[joint].type == JointType::Ball ? 3 : 1;
    }
  }
  return dofs;
}

// A jointed body that starts moving would need its velocity turned into joint rates.
bool jointedBodiesAtRest(const Scene& scene, const JointForest& forest) {
  for (int body : forest.order) {
    const bool jointed = forest.parentJoint[body] >= 0 ||
                         std::any_of(forest.order.begin(), forest.order.end(),
                                     [&](int other) { return forest.parentBody[other] == body; });
    const BodyDesc& desc = scene.bodies[body];
    if (jointed && !(desc.linearVelocity.isZero() && desc.angularVelocity.isZero())) return false;
  }
  return true;
}

// Above this many degrees of freedom a run is not attempted: MuJoCo 2.2's default Newton
// solver factorises a dense nv x nv Hessian in every iteration and its mjData holds
// constraint arrays quadratic in njmax. 210 free boxes (1260 dofs) already take about a
// quarter of a second and 1.6 GB per step.
constexpr int kMaxDegreesOfFreedom = 3000;
// Nor above this many constraint rows (njmax): mjData holds efc_AR, njmax x njmax doubles,
// and the 64 arms and 16 ragdolls of `robots` (22,800 rows, 4.2 GB) are refused there
// ("could not create mjData").
constexpr double kMaxConstraintArrayBytes = 2.0 * (1 << 30);

// Where a joint's anchor sits on the parent's side: a point fixed in the parent body's
// frame (the world body, id 0, for a joint to the world). The child's side is MuJoCo's
// own joint anchor, xanchor.
struct MjJoint {
  int joint = -1;
  int parentBody = 0;
  Vec3 onParent = Vec3::Zero();
  bool childIsB = true;
};

class MujocoEngine final : public Engine {
 public:
  ~MujocoEngine() override {
    if (m_data) mj_deleteData(m_data);
    if (m_model) mj_deleteModel(m_model);
  }

  bool supports(const Scene& scene, const EngineSettings&, std::string& reason) const override {
    JointForest forest;
    if (!buildJointForest(scene, forest, reason)) {
      reason = "mujoco: " + reason + " (a loop needs equality constraints, not built here)";
      return false;
    }
    if (!jointedBodiesAtRest(scene, forest)) {
      reason = "mujoco: a jointed body starts moving (joint rates are not derived here)";
      return false;
    }
    const int dofs = degreesOfFreedom(scene, forest);
    if (dofs > kMaxDegreesOfFreedom) {
      reason = "mujoco: " + std::to_string(dofs) +
               " degrees of freedom; its default Newton solver factorises a dense Hessian of "
               "that size every iteration, which is out of reach here";
      return false;
    }
    const double rows = 4.0 * maxContactsOf(scene);
    if (8 * rows * rows <= kMaxConstraintArrayBytes) return true;
    char text[160];
    std::snprintf(text, sizeof(text),
                  "mujoco: %.0f constraint rows; mjData's njmax x njmax array would take %.1f GB",
                  rows, 8 * rows * rows / 1e9);
    reason = text;
    return false;
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string& error) override {
    installMujocoHooks();
    JointForest forest;
    if (!buildJointForest(scene, forest, error)) {
      error = "mujoco: " + error;
      return false;
    }
    const MjcfFiles files = writeMjcf(scene, forest, settings);
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    for (std::size_t i = 0; i < files.names.size(); ++i) {
      const std::string& text = files.texts[i];
      if (mj_makeEmptyFileVFS(vfs.get(), files.names[i].c_str(), static_cast<int>(text.size())) !=
          0) {
        mj_deleteVFS(vfs.get());
        error = "mujoco: cannot make the in-memory model file " + files.names[i];
        return false;
      }
      const int file = mj_findFileVFS(vfs.get(), files.names[i].c_str());
      std::copy(text.begin(), text.end(), static_cast<char*>(vfs->filedata[file]));
    }
    char loadError[1000] = "";
    std::string failure;
    try {
      m_model = mj_loadXML(files.names[0].c_str(), vfs.get(), loadError, sizeof(loadError));
      if (!m_model) failure = std::string("model rejected: ") + loadError;
      if (m_model) m_data = mj_makeData(m_model);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    mj_deleteVFS(vfs.get());
    if (!failure.empty()) {
      error = "mujoco: " + failure;
      return false;
    }
    m_substeps = settings.substeps;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const BodyDesc& desc = scene.bodies[i];
      const std::string name = "b" + std::to_string(i);
      m_bodyIds.push_back(desc.fixed ? -1 : mj_name2id(m_model, mjOBJ_BODY, name.c_str()));
      m_fixedStates.push_back({desc.position, desc.orientation, Vec3::Zero(), Vec3::Zero()});
      if (!desc.fixed && forest.parentJoint[i] < 0) {
        setInitialVelocity(m_model->body_jntadr[m_bodyIds[i]], desc);
      }
    }
    for (std::size_t k = 0; k < scene.joints.size(); ++k) {
      const JointDesc& desc = scene.joints[k];
      const std::string name = "j" + std::to_string(k);
      MjJoint joint;
      joint.joint = mj_name2id(m_model, mjOBJ_JOINT, name.c_str());
      const int child = forest.parentJoint[desc.bodyB] == static_cast<int>(k) ? desc.bodyB
                                                                              : desc.bodyA;
      const int parent = forest.parentBody[child];
      joint.childIsB = child == desc.bodyB;
      if (parent == kWorld) {
        joint.onParent = desc.anchor;
      } else {
        const BodyDesc& p = scene.bodies[parent];
        joint.parentBody = m_bodyIds[parent];
        joint.onParent = inFrame(p.position, p.orientation, desc.anchor);
      }
      m_joints.push_back(joint);
    }
    for (const JointMotorDesc& motor : scene.motors) {
      const JointDesc& desc = scene.joints[motor.joint];
      const int child = forest.parentJoint[desc.bodyB] == motor.joint ? desc.bodyB : desc.bodyA;
      m_motorSigns.push_back(hingeSign(desc, child));
    }
    return true;
  }

  // Actuator i is motor i; its control is the target rate of the MuJoCo coordinate.
  void setMotorRates(const std::vector<double>& rates) override {
    for (std::size_t i = 0; i < rates.size(); ++i) m_data->ctrl[i] = m_motorSigns[i] * rates[i];
  }

  // MuJoCo answers a diverging simulation (a bad number in qpos, qvel or qacc) with a
  // warning and a reset to the initial state; carrying on from there would hide the
  // explosion, so the run stops at the first such warning.
  bool step(std::string& error) override {
    try {
      for (int i = 0; i < m_substeps; ++i) {
        mj_step(m_model, m_data);
        if (divergences() > 0) {
          error = "mujoco: diverged (a bad number in qpos, qvel or qacc) and reset its state";
          return false;
        }
      }
    } catch (const std::exception& e) {
      error = std::string("mujoco: ") + e.what();
      return false;
    }
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    deriveFromState(true);
    states.resize(m_bodyIds.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
      const int id = m_bodyIds[i];
      if (id < 0) {
        states[i] = m_fixedStates[i];
        continue;
      }
      mjtNum velocity[6];  // angular, then linear, at the body's origin, world axes
      mj_objectVelocity(m_model, m_data, mjOBJ_XBODY, id, velocity, 0);
      states[i].position = position(id);
      states[i].orientation = orientation(id);
      states[i].angularVelocity = Vec3(velocity[0], velocity[1], velocity[2]);
      states[i].linearVelocity = Vec3(velocity[3], velocity[4], velocity[5]);
    }
  }

  void readJointAnchors(std::vector<JointAnchors>& anchors) const override {
    deriveFromState(false);
    anchors.resize(m_joints.size());
    for (std::size_t k = 0; k < m_joints.size(); ++k) {
      const MjJoint& joint = m_joints[k];
      const mjtNum* x = m_data->xanchor + 3 * joint.joint;
      const Vec3 onChild(x[0], x[1], x[2]);
      const Vec3 onParent =
          position(joint.parentBody) + orientation(joint.parentBody) * joint.onParent;
      anchors[k].onA = joint.childIsB ? onParent : onChild;
      anchors[k].onB = joint.childIsB ? onChild : onParent;
    }
  }

 private:
  // Body poses (and velocities) from qpos and qvel, for reading. mj_kinematics normalises
  // the quaternions in qpos in place, which changes their last bits and, through contacts
  // that hinge on them, the rest of the run; qpos is put back as it was so that reading
  // leaves the run alone. Whatever else this computes, the next mj_step computes afresh.
  void deriveFromState(bool velocities) const {
    m_savedQpos.assign(m_data->qpos, m_data->qpos + m_model->nq);
    mj_kinematics(m_model, m_data);
    if (velocities) {
      mj_comPos(m_model, m_data);
      mj_comVel(m_model, m_data);
    }
    std::copy(m_savedQpos.begin(), m_savedQpos.end(), m_data->qpos);
  }

  int divergences() const {
    return m_data->warning[mjWARN_BADQPOS].number + m_data->warning[mjWARN_BADQVEL].number +
           m_data->warning[mjWARN_BADQACC].number;
  }

  Vec3 position(int body) const {
    const mjtNum* p = m_data->xpos + 3 * body;
    return Vec3(p[0], p[1], p[2]);
  }
  Quat orientation(int body) const {
    const mjtNum* q = m_data->xquat + 4 * body;
    return Quat(q[0], q[1], q[2], q[3]).normalized();
  }

  // A free joint takes the linear velocity in world axes, the angular one in body axes.
  void setInitialVelocity(int joint, const BodyDesc& desc) {
    mjtNum* v = m_data->qvel + m_model->jnt_dofadr[joint];
    const Vec3 localAngular = desc.orientation.conjugate() * desc.angularVelocity;
    for (int k = 0; k < 3; ++k) {
      v[k] = desc.linearVelocity[k];
      v[3 + k] = localAngular[k];
    }
  }

  mjModel* m_model = nullptr;
  mjData* m_data = nullptr;
  std::vector<int> m_bodyIds;            // MuJoCo body of each scene body, -1 where fixed
  std::vector<BodyState> m_fixedStates;  // indexed like m_bodyIds, used where fixed
  std::vector<MjJoint> m_joints;         // indexed like the scene's joints
  std::vector<double> m_motorSigns;      // per motor of the scene, see hingeSign
  mutable std::vector<mjtNum> m_savedQpos;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createMujocoEngine() { return std::make_unique<MujocoEngine>(); }

}  // namespace pfxbench
