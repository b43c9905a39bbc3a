#include "bench_scene.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace pfxbench {

namespace {

struct SceneEntry {
  const char* name;
  void (*build)(std::vector<Scene>&);
};

const SceneEntry kScenes[] = {
    {"pyramid", buildPyramidScene}, {"tower", buildTowerScene},
    {"spinner", buildSpinnerScene}, {"rain", buildRainScene},
    {"spheres", buildSpheresScene},
    {"bullet", buildBulletScene}, {"chain", buildChainScene},
    {"longchain", buildLongChainScene}, {"ragdoll", buildRagdollScene},
#ifdef PFX_BENCH_HAVE_LOADERS
    {"urdf", buildUrdfScene}, {"robots", buildRobotsScene},
#endif
};

int otherEnd(const JointDesc& joint, int body) {
  return joint.bodyA == body ? joint.bodyB : joint.bodyA;
}

}  // namespace

ShapeDesc ShapeDesc::sphere(double radius) {
  ShapeDesc s;
  s.type = ShapeType::Sphere;
  s.radius = radius;
  return s;
}

ShapeDesc ShapeDesc::box(const Vec3& halfExtents) {
  ShapeDesc s;
  s.type = ShapeType::Box;
  s.halfExtents = halfExtents;
  return s;
}

ShapeDesc ShapeDesc::capsule(double halfLength, double radius) {
  ShapeDesc s;
  s.type = ShapeType::Capsule;
  s.halfLength = halfLength;
  s.radius = radius;
  return s;
}

ShapeDesc ShapeDesc::cylinder(double halfLength, double radius) {
  ShapeDesc s;
  s.type = ShapeType::Cylinder;
  s.halfLength = halfLength;
  s.radius = radius;
  return s;
}

double ShapeDesc::volume() const {
  const double sphereVolume = 4.0 / 3.0 * kPi * radius * radius * radius;
  const double cylinderVolume = kPi * radius * radius * 2 * halfLength;
  switch (type) {
    case ShapeType::Sphere: return sphereVolume;
    case ShapeType::Box: return 8 * halfExtents.prod();
    case ShapeType::Capsule: return cylinderVolume + sphereVolume;
    case ShapeType::Cylinder: return cylinderVolume;
  }
  return 0;
}

double ShapeDesc::innerRadius() const {
  switch (type) {
    case ShapeType::Sphere:
    case ShapeType::Capsule: return radius;
    case ShapeType::Box: return halfExtents.minCoeff();
    case ShapeType::Cylinder: return std::min(radius, halfLength);
  }
  return 0;
}

double ShapeDesc::outerRadius() const {
  switch (type) {
    case ShapeType::Sphere: return radius;
    case ShapeType::Box: return halfExtents.norm();
    case ShapeType::Capsule: return halfLength + radius;
    case ShapeType::Cylinder: return std::hypot(halfLength, radius);
  }
  return 0;
}

Vec3 principalInertia(const ShapeDesc& shape, double mass) {
  const double r2 = shape.radius * shape.radius;
  const double h = shape.halfLength;
  switch (shape.type) {
    case ShapeType::Sphere: return Vec3::Constant(0.4 * mass * r2);
    case ShapeType::Box: {
      const Vec3 e2 = shape.halfExtents.cwiseProduct(shape.halfExtents);
      return mass / 3 * Vec3(e2.y() + e2.z(), e2.x() + e2.z(), e2.x() + e2.y());
    }
    case ShapeType::Cylinder: {
      const double across = mass * (3 * r2 + 4 * h * h) / 12;
      return Vec3(0.5 * mass * r2, across, across);
    }
    case ShapeType::Capsule: {
      // Mass shared by volume between the cylinder and the two hemispheres. A hemisphere's
      // moment about its own centre of mass (3r/8 from its flat face) is 83/320 m r^2;
      // moved to the capsule centre this sums to ms (2/5 r^2 + h^2 + 3/4 h r).
      const double cylinderVolume = kPi * r2 * 2 * h;
      const double capsVolume = 4.0 / 3.0 * kPi * r2 * shape.radius;
      const double mc = mass * cylinderVolume / (cylinderVolume + capsVolume);
      const double ms = mass - mc;
      const double axial = 0.5 * mc * r2 + 0.4 * ms * r2;
      const double across =
          mc * (3 * r2 + 4 * h * h) / 12 + ms * (0.4 * r2 + h * h + 0.75 * h * shape.radius);
      return Vec3(axial, across, across);
    }
  }
  return Vec3::Zero();
}

BodyDesc makeDynamicBody(const ShapeDesc& shape, double mass, const Vec3& position,
                         const Quat& orientation) {
  BodyDesc body;
  body.shape = shape;
  body.mass = mass;
  body.inertia = principalInertia(shape, mass);
  body.position = position;
  body.orientation = orientation;
  return body;
}

BodyDesc makeFixedBody(const ShapeDesc& shape, const Vec3& position, const Quat& orientation) {
  BodyDesc body;
  body.shape = shape;
  body.fixed = true;
  body.position = position;
  body.orientation = orientation;
  return body;
}

const char* metricName(Metric metric) {
  switch (metric) {
    case Metric::StackDrift: return "stack_drift";
    case Metric::PenetrationMax: return "penetration_max";
    case Metric::EnergyDrift: return "energy_drift";
    case Metric::MomentumDrift: return "momentum_drift";
    case Metric::Escaped: return "escaped";
    case Metric::PositionError: return "position_error";
    case Metric::JointGapMax: return "joint_gap_max";
    case Metric::BytesPerBody: return "bytes_per_body";
    case Metric::MsPerStep: return "ms_per_step";
    case Metric::MsPerStepPerRobot: return "ms_per_step_per_robot";
    case Metric::CpuMsPerStepPerRobot: return "cpu_ms_per_step_per_robot";
  }
  return "unknown";
}

bool metricByName(const std::string& name, Metric& metric) {
  for (int i = 0; i <= static_cast<int>(Metric::CpuMsPerStepPerRobot); ++i) {
    if (name == metricName(static_cast<Metric>(i))) {
      metric = static_cast<Metric>(i);
      return true;
    }
  }
  return false;
}

void appendScene(Scene& scene, const Scene& part, const Vec3& offset) {
  const int firstBody = static_cast<int>(scene.bodies.size());
  const int firstJoint = static_cast<int>(scene.joints.size());
  for (BodyDesc body : part.bodies) {
    body.position += offset;
    scene.bodies.push_back(body);
  }
  for (JointDesc joint : part.joints) {
    if (joint.bodyA != kWorld) joint.bodyA += firstBody;
    joint.bodyB += firstBody;
    joint.anchor += offset;
    scene.joints.push_back(joint);
  }
  for (JointMotorDesc motor : part.motors) {
    motor.joint += firstJoint;
    scene.motors.push_back(motor);
  }
}

bool Scene::hasMetric(Metric metric) const {
  return std::find(metrics.begin(), metrics.end(), metric) != metrics.end();
}

bool buildJointForest(const Scene& scene, JointForest& forest, std::string& reason) {
  const int numBodies = static_cast<int>(scene.bodies.size());
  auto dynamicBody = [&](int i) { return i >= 0 && i < numBodies && !scene.bodies[i].fixed; };
  std::vector<std::vector<int>> jointsOfBody(scene.bodies.size());
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const JointDesc& joint = scene.joints[j];
    if (!dynamicBody(joint.bodyB) || joint.bodyA == joint.bodyB ||
        (joint.bodyA != kWorld && !dynamicBody(joint.bodyA))) {
      reason = "joint " + std::to_string(j) + " does not join a dynamic body to another or to the world";
      return false;
    }
    jointsOfBody[joint.bodyB].push_back(static_cast<int>(j));
    if (joint.bodyA != kWorld) jointsOfBody[joint.bodyA].push_back(static_cast<int>(j));
  }

  forest.parentJoint.assign(scene.bodies.size(), -1);
  forest.parentBody.assign(scene.bodies.size(), kWorld);
  forest.order.clear();
  std::vector<bool> reached(scene.bodies.size(), false);
  const std::string loop = "the joints close a loop";
  // Walks the jointed group below `root` breadth first; false on meeting a body twice.
  auto grow = [&](int root) {
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int body = queue.front();
      queue.pop_front();
      for (int j : jointsOfBody[body]) {
        if (j == forest.parentJoint[body]) continue;
        const int child = otherEnd(scene.joints[j], body);
        if (child == kWorld || reached[child]) return false;
        reached[child] = true;
        forest.parentJoint[child] = j;
        forest.parentBody[child] = body;
        forest.order.push_back(child);
        queue.push_back(child);
      }
    }
    return true;
  };
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const JointDesc& joint = scene.joints[j];
    if (joint.bodyA != kWorld) continue;
    if (reached[joint.bodyB]) {
      reason = loop;
      return false;
    }
    reached[joint.bodyB] = true;
    forest.parentJoint[joint.bodyB] = static_cast<int>(j);
    forest.order.push_back(joint.bodyB);
    if (!grow(joint.bodyB)) {
      reason = loop;
      return false;
    }
  }
  for (int i = 0; i < numBodies; ++i) {
    if (scene.bodies[i].fixed || reached[i]) continue;
    reached[i] = true;
    forest.order.push_back(i);
    if (!grow(i)) {
      reason = loop;
      return false;
    }
  }
  return true;
}

const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const SceneEntry& entry : kScenes) list.emplace_back(entry.name);
    return list;
  }();
  return names;
}

bool buildScene(const std::string& name, std::vector<Scene>& variants) {
  for (const SceneEntry& entry : kScenes) {
    if (name == entry.name) {
      variants.clear();
      entry.build(variants);
      return true;
    }
  }
  return false;
}

}  // namespace pfxbench
