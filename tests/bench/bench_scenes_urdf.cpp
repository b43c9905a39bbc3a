// The `urdf` scene: the package's arm (urdf/arm.urdf, read with urdfdom) on a fixed base,
// every revolute joint driven by its motor along a smooth reference (JointMotorDesc). What
// the file gives is what every engine gets: link masses, centres and inertias, joint
// origins, axes and limits, effort and velocity limits.
//
// How the URDF becomes the engine-neutral scene:
// - The root link is the fixed world that the first joint hangs from; neither it nor links
//   fixed to it are bodies (the shoulder stands on the base, which the engines could not
//   all keep from colliding without a joint between them).
// - A revolute or continuous joint makes its child link a body, hinged at the joint origin
//   about the joint axis; fixed and prismatic joints lump their child into the parent's
//   body at the joint's zero (the gripper's mimic fingers, closed, go into the palm).
// - A body sits at its centre of mass with its principal axes; its shape is the box about
//   that centre, along those axes, that bounds the vertices of its links' collision
//   geometry (pfxLoadMeshFile reads the meshes). The arm's meshes are boxes and octagonal
//   prisms centred on their links' centres of mass, so each box is the mesh's own bounding
//   box.
// - The scene is Y-up like the others: the URDF's Z turns onto Y.
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "bench_scene.h"
#include "pfx/loaders/pfx_mesh_loader.h"

namespace pfxbench {

namespace {

using Matrix3 = Eigen::Matrix3d;

struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Pose operator*(const Pose& local) const {
    return {position + orientation * local.position, orientation * local.orientation};
  }
  Vec3 operator*(const Vec3& point) const { return position + orientation * point; }
};

Pose fromUrdf(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  return {Vec3(pose.position.x, pose.position.y, pose.position.z), Quat(w, x, y, z).normalized()};
}

Vec3 fromUrdf(const urdf::Vector3& v) { return Vec3(v.x, v.y, v.z); }

// What the links lumped into one body add up to, in world coordinates.
struct BodyParts {
  Quat frame;  // orientation of the link that starts the body
  double mass = 0;
  Vec3 massMoment = Vec3::Zero();            // sum of mass times centre
  Matrix3 inertiaAboutOrigin = Matrix3::Zero();  // sum of inertias about the world origin
  std::vector<Vec3> points;                  // collision geometry
  int revoluteDepth = 0;                     // hinges between the body and the world
};

// The inertia of a point mass m at p about the origin, to move a tensor by parallel axes.
Matrix3 pointInertia(double mass, const Vec3& p) {
  return mass * (p.squaredNorm() * Matrix3::Identity() - p * p.transpose());
}

class ArmReader {
 public:
  explicit ArmReader(std::string folder) : m_folder(std::move(folder)) {}

  bool read(const urdf::ModelInterface& model, Scene& scene) {
    // URDF's Z onto the scene's Y: a quarter turn about -X.
    const Pose root{Vec3::Zero(), Quat(Eigen::AngleAxisd(-0.5 * kPi, Vec3::UnitX()))};
    if (!walk(*model.getRoot(), root, kWorld, 0)) return false;
    for (std::size_t i = 0; i < m_parts.size(); ++i) {
      if (!addBody(m_parts[i], m_names[i], scene)) return false;
    }
    scene.joints = m_joints;
    scene.motors = m_motors;
    int deepest = 0;
    for (std::size_t i = 0; i < m_parts.size(); ++i) {
      if (m_parts[i].revoluteDepth > m_parts[deepest].revoluteDepth) deepest = static_cast<int>(i);
    }
    scene.trackedBodies = {deepest};
    return true;
  }

  const std::string& error() const { return m_error; }

 private:
  bool fail(const std::string& what) {
    m_error = what;
    return false;
  }

  // Adds the link at `pose` to body `body` (kWorld: the fixed base), then its children.
  bool walk(const urdf::Link& link, const Pose& pose, int body, int depth) {
    if (body != kWorld && !addLink(link, pose, m_parts[body])) return false;
    for (const urdf::JointSharedPtr& joint : link.child_joints) {
      const urdf::LinkSharedPtr child = findChild(link, joint->child_link_name);
      if (!child) return fail("joint '" + joint->name + "': its child link is missing");
      const Pose childPose = pose * fromUrdf(joint->parent_to_joint_origin_transform);
      const std::string where = "joint '" + joint->name + "'";
      switch (joint->type) {
        case urdf::Joint::FIXED:
        case urdf::Joint::PRISMATIC:
          if (!walk(*child, childPose, body, depth)) return false;
          break;
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS: {
          if (joint->mimic) return fail(where + ": a mimic hinge is not modelled");
          if (!joint->limits || joint->limits->effort <= 0 || joint->limits->velocity <= 0) {
            return fail(where + ": the motor needs positive effort and velocity limits");
          }
          const int childBody = static_cast<int>(m_parts.size());
          m_parts.emplace_back();
          m_parts.back().frame = childPose.orientation;
          m_parts.back().revoluteDepth = depth + 1;
          m_names.push_back(child->name);
          addHinge(*joint, childPose, body, childBody);
          if (!walk(*child, childPose, childBody, depth + 1)) return false;
          break;
        }
        default: return fail(where + ": only revolute, continuous, prismatic and fixed joints");
      }
    }
    return true;
  }

  static urdf::LinkSharedPtr findChild(const urdf::Link& link, const std::string& name) {
    for (const urdf::LinkSharedPtr& child : link.child_links) {
      if (child->name == name) return child;
    }
    return nullptr;
  }

  // A hinge at the joint origin with the file's limits, and its motor: the reference swings
  // from zero to half of the limit on one side (joints alternate sides) and back, its top
  // speed at most half the velocity limit so that the controller keeps room to correct.
  void addHinge(const urdf::Joint& urdfJoint, const Pose& pose, int parent, int child) {
    JointDesc joint;
    joint.type = JointType::Hinge;
    joint.bodyA = parent;
    joint.bodyB = child;
    joint.anchor = pose.position;
    joint.axis = pose.orientation * fromUrdf(urdfJoint.axis).normalized();
    const bool limited = urdfJoint.type == urdf::Joint::REVOLUTE;
    if (limited) {
      joint.lowerLimit = urdfJoint.limits->lower;
      joint.upperLimit = urdfJoint.limits->upper;
    }
    JointMotorDesc motor;
    motor.joint = static_cast<int>(m_joints.size());
    motor.maxTorque = urdfJoint.limits->effort;
    motor.maxSpeed = urdfJoint.limits->velocity;
    const bool upward = m_motors.size() % 2 == 0;
    const double reach = limited ? (upward ? joint.upperLimit : -joint.lowerLimit) : kPi;
    motor.amplitude = (upward ? 1 : -1) * 0.25 * std::max(reach, 0.0);
    const double frequency = 1.2 + 0.4 * static_cast<double>(m_motors.size());
    motor.angularFrequency =
        motor.amplitude == 0 ? frequency
                             : std::min(frequency, 0.5 * motor.maxSpeed / std::abs(motor.amplitude));
    m_joints.push_back(joint);
    m_motors.push_back(motor);
  }

  bool addLink(const urdf::Link& link, const Pose& pose, BodyParts& parts) {
    if (link.inertial && link.inertial->mass > 0) {
      const urdf::Inertial& in = *link.inertial;
      const Pose frame = pose * fromUrdf(in.origin);
      Matrix3 local;
      local << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Matrix3 r = frame.orientation.toRotationMatrix();
      parts.mass += in.mass;
      parts.massMoment += in.mass * frame.position;
      parts.inertiaAboutOrigin += r * local * r.transpose() + pointInertia(in.mass, frame.position);
    }
    for (const urdf::CollisionSharedPtr& collision : link.collision_array) {
      if (!collision || !collision->geometry) continue;
      const Pose frame = pose * fromUrdf(collision->origin);
      std::vector<Vec3> local;
      if (!geometryPoints(*collision->geometry, link.name, local)) return false;
      for (const Vec3& p : local) parts.points.push_back(frame * p);
    }
    return true;
  }

  // Points whose bounds are the geometry's: mesh vertices, or the corners of a primitive's box.
  bool geometryPoints(const urdf::Geometry& geometry, const std::string& link,
                      std::vector<Vec3>& points) {
    Vec3 half;
    switch (geometry.type) {
      case urdf::Geometry::BOX:
        half = 0.5 * fromUrdf(static_cast<const urdf::Box&>(geometry).dim);
        break;
      case urdf::Geometry::SPHERE:
        half = Vec3::Constant(static_cast<const urdf::Sphere&>(geometry).radius);
        break;
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
        half = Vec3(cylinder.radius, cylinder.radius, 0.5 * cylinder.length);
        break;
      }
      case urdf::Geometry::MESH: return meshPoints(static_cast<const urdf::Mesh&>(geometry), link, points);
      default: return fail("link '" + link + "': unknown collision geometry");
    }
    for (int corner = 0; corner < 8; ++corner) {
      points.emplace_back((corner & 1) ? half.x() : -half.x(), (corner & 2) ? half.y() : -half.y(),
                          (corner & 4) ? half.z() : -half.z());
    }
    return true;
  }

  // package://pfx/... is this repository; other packages are not looked for.
  bool meshPoints(const urdf::Mesh& mesh, const std::string& link, std::vector<Vec3>& points) {
    const std::string ownPackage = "package://pfx/";
    std::string path = mesh.filename;
    if (path.rfind(ownPackage, 0) == 0) {
      path = std::string(PFX_SOURCE_DIR) + "/" + path.substr(ownPackage.size());
    } else if (path.rfind("file://", 0) == 0) {
      path = path.substr(7);
    } else if (path.find("://") != std::string::npos) {
      return fail("link '" + link + "': mesh '" + mesh.filename + "' is outside package pfx");
    } else if (std::filesystem::path(path).is_relative()) {
      path = m_folder + "/" + path;
    }
    pfx::PfxTriangleMesh triangles;
    std::string message;
    const pfx::PfxVector3 scale = fromUrdf(mesh.scale).cast<pfx::PfxFloat>();
    if (pfx::pfxLoadMeshFile(path, scale, triangles, &message) != pfx::PFX_OK) {
      return fail("link '" + link + "': " + message);
    }
    for (std::size_t i = 0; i + 2 < triangles.vertices.size(); i += 3) {
      points.emplace_back(triangles.vertices[i], triangles.vertices[i + 1], triangles.vertices[i + 2]);
    }
    return true;
  }

  bool addBody(const BodyParts& parts, const std::string& name, Scene& scene) {
    if (!(parts.mass > 0)) return fail("link '" + name + "': a moving link without mass");
    if (parts.points.empty()) return fail("link '" + name + "': no collision geometry");
    const Vec3 centre = parts.massMoment / parts.mass;
    const Matrix3 frame = parts.frame.toRotationMatrix();
    // The inertia about the centre, in the frame of the body's first link: its own axes
    // where they are principal (the arm's), else the eigenvectors, turned into a rotation.
    const Matrix3 inertia =
        frame.transpose() * (parts.inertiaAboutOrigin - pointInertia(parts.mass, centre)) * frame;
    const Matrix3 offDiagonal = inertia - Matrix3(inertia.diagonal().asDiagonal());
    Matrix3 axes = Matrix3::Identity();
    Vec3 moments = inertia.diagonal();
    if (offDiagonal.norm() > 1e-9 * inertia.trace()) {
      const Eigen::SelfAdjointEigenSolver<Matrix3> solver(inertia);
      axes = solver.eigenvectors();
      if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
      moments = solver.eigenvalues();
    }
    if (!(moments.minCoeff() > 0)) return fail("link '" + name + "': inertia not positive");
    const Quat orientation(frame * axes);
    Vec3 half = Vec3::Zero();
    for (const Vec3& p : parts.points) {
      half = half.cwiseMax((orientation.conjugate() * (p - centre)).cwiseAbs());
    }
    BodyDesc body = makeDynamicBody(ShapeDesc::box(half), parts.mass, centre, orientation.normalized());
    body.inertia = moments;
    scene.bodies.push_back(body);
    return true;
  }

  std::string m_folder;
  std::string m_error;
  std::vector<BodyParts> m_parts;  // one per body, in the order the walk meets them
  std::vector<std::string> m_names;
  std::vector<JointDesc> m_joints;
  std::vector<JointMotorDesc> m_motors;
};

}  // namespace

void buildUrdfScene(std::vector<Scene>& variants) {
  const std::string folder = std::string(PFX_SOURCE_DIR) + "/urdf";
  const std::string path = folder + "/arm.urdf";
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(path);
  if (!model) {
    std::fprintf(stderr, "urdf: %s: urdfdom cannot read it\n", path.c_str());
    return;
  }
  Scene scene;
  scene.name = "urdf";
  scene.variant = "arm";
  scene.duration = 4;
  scene.metrics = {Metric::JointGapMax, Metric::PositionError};
  // The controller's proportional gain: it halves an angle error in 0.07 s, and a step of
  // 1/30 s takes away a third of it, so the coarsest step still follows smoothly.
  scene.motorGain = 10;
  // The arm's tip moves at a few metres per second at most.
  scene.speedLimit = 20;
  ArmReader reader(folder);
  if (!reader.read(*model, scene)) {
    std::fprintf(stderr, "urdf: %s: %s\n", path.c_str(), reader.error().c_str());
    return;
  }
  variants.push_back(scene);
}

}  // namespace pfxbench
