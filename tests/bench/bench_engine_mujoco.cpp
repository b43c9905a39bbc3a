// MuJoCo behind the benchmark's interface: the scene written as MJCF (fixed bodies as
// geoms of the world body, dynamic ones as bodies with a free joint and explicit inertia),
// compiled from an in-memory file, stepped with mj_step at dt / substeps and the default
// solver. MuJoCo's capsules and cylinders lie along Z; their geoms are turned onto X.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
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

std::string writeMjcf(const Scene& scene, const EngineSettings& settings) {
  std::ostringstream out;
  out.precision(17);
  int numDynamic = 0;
  for (const BodyDesc& body : scene.bodies) numDynamic += body.fixed ? 0 : 1;
  // MuJoCo makes up to eight contacts per box pair (about 8.5 per box in the pyramid);
  // each takes four constraint rows with the pyramidal cone and condim 3.
  const int maxContacts = 100 + 10 * numDynamic;
  out << "<mujoco model=\"" << scene.name << "\">\n"
      << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "<option timestep=\"" << settings.dt / settings.substeps << "\" iterations=\""
      << settings.iterations << "\" gravity=\"" << scene.gravity << "\"/>\n"
      << "<size nconmax=\"" << maxContacts << "\" njmax=\"" << 4 * maxContacts << "\"/>\n"
      << "<worldbody>\n";
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& body = scene.bodies[i];
    if (body.fixed) {
      writeGeom(out, body);
      continue;
    }
    out << "<body name=\"b" << i << "\" pos=\"" << body.position << "\" quat=\""
        << body.orientation << "\">\n<freejoint/>\n<inertial pos=\"0 0 0\" mass=\"" << body.mass
        << "\" diaginertia=\"" << body.inertia << "\"/>\n";
    writeGeom(out, body);
    out << "</body>\n";
  }
  out << "</worldbody>\n</mujoco>\n";
  return out.str();
}

// Above this many degrees of freedom a run is not attempted: MuJoCo 2.2's default Newton
// solver factorises a dense nv x nv Hessian in every iteration and its mjData holds
// constraint arrays quadratic in njmax. 210 free boxes (1260 dofs) already take about a
// quarter of a second and 1.6 GB per step.
constexpr int kMaxDegreesOfFreedom = 3000;

class MujocoEngine final : public Engine {
 public:
  ~MujocoEngine() override {
    if (m_data) mj_deleteData(m_data);
    if (m_model) mj_deleteModel(m_model);
  }

  bool supports(const Scene& scene, const EngineSettings&, std::string& reason) const override {
    int dofs = 0;
    for (const BodyDesc& body : scene.bodies) dofs += body.fixed ? 0 : 6;
    if (dofs <= kMaxDegreesOfFreedom) return true;
    reason = "mujoco: " + std::to_string(dofs) +
             " degrees of freedom; its default Newton solver factorises a dense Hessian of "
             "that size every iteration, which is out of reach here";
    return false;
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string& error) override {
    installMujocoHooks();
    const std::string xml = writeMjcf(scene, settings);
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    const char* fileName = "scene.xml";
    if (mj_makeEmptyFileVFS(vfs.get(), fileName, static_cast<int>(xml.size())) != 0) {
      error = "mujoco: cannot make the in-memory model file";
      return false;
    }
    const int file = mj_findFileVFS(vfs.get(), fileName);
    std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[file]));
    char loadError[1000] = "";
    std::string failure;
    try {
      m_model = mj_loadXML(fileName, vfs.get(), loadError, sizeof(loadError));
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
    int joint = 0;
    for (const BodyDesc& desc : scene.bodies) {
      m_jointOfBody.push_back(desc.fixed ? -1 : joint);
      m_fixedStates.push_back({desc.position, desc.orientation, Vec3::Zero(), Vec3::Zero()});
      if (!desc.fixed) setInitialVelocity(joint++, desc);
    }
    return true;
  }

  bool step(std::string& error) override {
    try {
      for (int i = 0; i < m_substeps; ++i) mj_step(m_model, m_data);
    } catch (const std::exception& e) {
      error = std::string("mujoco: ") + e.what();
      return false;
    }
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    states.resize(m_jointOfBody.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
      const int joint = m_jointOfBody[i];
      if (joint < 0) {
        states[i] = m_fixedStates[i];
        continue;
      }
      const mjtNum* q = m_data->qpos + m_model->jnt_qposadr[joint];
      const mjtNum* v = m_data->qvel + m_model->jnt_dofadr[joint];
      states[i].position = Vec3(q[0], q[1], q[2]);
      states[i].orientation = Quat(q[3], q[4], q[5], q[6]).normalized();
      states[i].linearVelocity = Vec3(v[0], v[1], v[2]);
      // A free joint's angular velocity is expressed in the body frame.
      states[i].angularVelocity = states[i].orientation * Vec3(v[3], v[4], v[5]);
    }
  }

 private:
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
  std::vector<int> m_jointOfBody;        // free joint of each scene body, -1 where fixed
  std::vector<BodyState> m_fixedStates;  // indexed like m_jointOfBody, used where fixed
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createMujocoEngine() { return std::make_unique<MujocoEngine>(); }

}  // namespace pfxbench
