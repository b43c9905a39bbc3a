#include "bench_scene.h"

#include <algorithm>
#include <cmath>

namespace pfxbench {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct SceneEntry {
  const char* name;
  void (*build)(std::vector<Scene>&);
};

const SceneEntry kScenes[] = {
    {"pyramid", buildPyramidScene}, {"tower", buildTowerScene},
    {"spinner", buildSpinnerScene}, {"rain", buildRainScene},
    {"bullet", buildBulletScene},
};

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
  }
  return "unknown";
}

bool Scene::hasMetric(Metric metric) const {
  return std::find(metrics.begin(), metrics.end(), metric) != metrics.end();
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
