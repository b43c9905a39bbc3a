// Engine-neutral description of a benchmark scene: bodies with one shape each, the joints
// between them, gravity, how long to simulate, and which error metrics judge it. Every engine adapter builds its
// world from this alone, so that all engines run the very same scene.
//
// Frame conventions are pfx's: Y is up in the scenes, capsules and cylinders lie along
// their body's X axis. Adapters of engines with other conventions convert.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace pfxbench {

constexpr double kPi = 3.14159265358979323846;

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

enum class ShapeType { Sphere, Box, Capsule, Cylinder };

struct ShapeDesc {
  ShapeType type = ShapeType::Box;
  Vec3 halfExtents = Vec3::Zero();  // box
  double radius = 0;                // sphere, capsule, cylinder
  double halfLength = 0;            // capsule, cylinder: half length of the axis along X

  static ShapeDesc sphere(double radius);
  static ShapeDesc box(const Vec3& halfExtents);
  static ShapeDesc capsule(double halfLength, double radius);
  static ShapeDesc cylinder(double halfLength, double radius);

  double volume() const;
  // Radius of the largest sphere about the centre that fits inside the shape.
  double innerRadius() const;
  // Radius of the smallest sphere about the centre that holds the shape.
  double outerRadius() const;
};

// Principal moments of inertia of a uniform solid of the given mass, about its centre,
// along the body axes.
Vec3 principalInertia(const ShapeDesc& shape, double mass);

struct BodyDesc {
  ShapeDesc shape;
  bool fixed = false;
  double mass = 0;              // dynamic bodies only
  Vec3 inertia = Vec3::Zero();  // principal moments along the body axes, dynamic bodies only
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 linearVelocity = Vec3::Zero();   // world frame
  Vec3 angularVelocity = Vec3::Zero();  // world frame
  double friction = 0.6;
  double restitution = 0;
};

BodyDesc makeDynamicBody(const ShapeDesc& shape, double mass, const Vec3& position,
                         const Quat& orientation = Quat::Identity());
BodyDesc makeFixedBody(const ShapeDesc& shape, const Vec3& position,
                       const Quat& orientation = Quat::Identity());

// Stands for the fixed world where a joint names a body.
constexpr int kWorld = -1;

enum class JointType { Ball, Hinge };

// A joint between two dynamic bodies, or between a dynamic body and the fixed world. Its
// anchor point is given in world coordinates for the bodies' initial poses; each body
// carries it along rigidly from there. Joints to fixed bodies are not part of the
// description: attach to the world instead.
//
// A hinge's angle is B's turn relative to A about the axis, right-handed, zero in the
// initial poses; its rate is (B's angular velocity - A's) along the axis as A carries it.
// Limits and motors use this sign in every engine.
struct JointDesc {
  JointType type = JointType::Ball;
  int bodyA = kWorld;  // index of a dynamic body, or kWorld
  int bodyB = 0;       // index of a dynamic body
  Vec3 anchor = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();  // hinge: the free axis, world direction in the initial poses
  // Hinge: the angle stays within [lowerLimit, upperLimit] (rad), both finite, or turns
  // freely with both infinite.
  double lowerLimit = -std::numeric_limits<double>::infinity();
  double upperLimit = std::numeric_limits<double>::infinity();
  bool limited() const { return std::isfinite(lowerLimit) && std::isfinite(upperLimit); }
};

// A motor on a hinge, given to each engine as its own joint motor: before every step the
// benchmark commands a target rate of the hinge's angle, which the motor reaches with at
// most maxTorque. The command follows a reference angle
//   reference(t) = amplitude (1 - cos(angularFrequency t)),
// at rest at zero when the scene starts, through a proportional term on the angle:
//   rate = reference'(t) + Scene::motorGain (reference(t) - angle),
// cut to +-maxSpeed. Every engine is commanded by the same code from its own body states.
struct JointMotorDesc {
  int joint = 0;          // index of a hinge in Scene::joints
  double maxTorque = 0;   // N m
  double maxSpeed = 0;    // rad/s
  double amplitude = 0;   // rad
  double angularFrequency = 0;  // rad/s
};

// The error figures a scene is judged by; each becomes one TSV row per run.
enum class Metric {
  StackDrift,
  PenetrationMax,
  EnergyDrift,
  MomentumDrift,
  Escaped,
  PositionError,
  JointGapMax,
  // Heap the engine holds per body of the scene after a few steps (bench_run.cpp).
  BytesPerBody,
  // What a step costs (bench_run.cpp): wall time, wall time per robot of Scene::robots, and
  // processor time of all threads per robot, which on a shared machine does not count the
  // waits for a core.
  MsPerStep,
  MsPerStepPerRobot,
  CpuMsPerStepPerRobot
};
const char* metricName(Metric metric);
// The metric of that name; false for a name no metric has.
bool metricByName(const std::string& name, Metric& metric);

struct Aabb {
  Vec3 min = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(std::numeric_limits<double>::infinity());
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

struct Scene {
  std::string name;
  std::string variant = "-";  // e.g. a chain's mass ratio; "-" for scenes without variants
  Vec3 gravity = Vec3(0, -9.80665, 0);
  double duration = 5;        // simulated seconds unless the command line says otherwise
  std::vector<BodyDesc> bodies;
  std::vector<JointDesc> joints;
  std::vector<JointMotorDesc> motors;
  double motorGain = 0;  // 1/s, see JointMotorDesc
  std::vector<Metric> metrics;
  // Dynamic bodies whose paths position_error compares; empty: all of them.
  std::vector<int> trackedBodies;
  // `escaped` counts dynamic bodies whose centre ends outside this box.
  Aabb keepInside;
  // A body faster than this (m/s) at a sample means the run blew up: it stops there and
  // its figures are NaN, so that an exploded run cannot pass for an accurate one.
  double speedLimit = std::numeric_limits<double>::infinity();
  // Robots the scene holds, the divisor of the per-robot cost metrics.
  int robots = 1;
  bool hasMetric(Metric metric) const;
};

// The joints seen as a forest: each jointed body hangs from one parent (a body or the
// world) by one joint, and a group of jointed bodies not attached to the world has a root
// body that floats free. Engines in generalised coordinates build their trees from this.
struct JointForest {
  std::vector<int> parentJoint;  // per body: the joint to its parent, -1 for roots and free bodies
  std::vector<int> parentBody;   // per body: the parent body, kWorld when none
  std::vector<int> order;        // every dynamic body, each after its parent
};

// False, with the reason, when the joints close a loop or name a body that cannot take a
// joint (out of range, fixed, or both ends the same).
bool buildJointForest(const Scene& scene, JointForest& forest, std::string& reason);

// Adds a copy of `part`'s bodies, joints and motors, moved by `offset`, to `scene`; joints
// to the world stay joints to the world.
void appendScene(Scene& scene, const Scene& part, const Vec3& offset);

// Names of every scene this build knows, in the order of the default sweep.
const std::vector<std::string>& sceneNames();
// Builds every variant of the named scene; false for an unknown name.
bool buildScene(const std::string& name, std::vector<Scene>& variants);

// Rigid-body scenes (bench_scenes_rigid.cpp).
void buildPyramidScene(std::vector<Scene>& variants);
void buildTowerScene(std::vector<Scene>& variants);
void buildSpinnerScene(std::vector<Scene>& variants);
void buildRainScene(std::vector<Scene>& variants);
void buildSpheresScene(std::vector<Scene>& variants);
void buildBulletScene(std::vector<Scene>& variants);

// Jointed scenes (bench_scenes_joint.cpp).
void buildChainScene(std::vector<Scene>& variants);
void buildLongChainScene(std::vector<Scene>& variants);
void buildRagdollScene(std::vector<Scene>& variants);
// One ragdoll of 11 bodies, 70 kg, standing with its arms stretched out sideways, feet at
// y = 0 of its own frame, placed at `origin` turned by `turn`: ball joints at the neck,
// spine, shoulders and hips, hinges limited to +-1.2 rad at the elbows and knees.
void addRagdoll(Scene& scene, const Vec3& origin, const Quat& turn);

#ifdef PFX_BENCH_HAVE_LOADERS
// The package's arm (urdf/arm.urdf) driven by its joint motors (bench_scenes_urdf.cpp).
// Leaves `variants` empty, saying why on stderr, when the file cannot be read.
void buildUrdfScene(std::vector<Scene>& variants);
// Many copies of that arm with ragdolls dropped on them (bench_scenes_robots.cpp).
void buildRobotsScene(std::vector<Scene>& variants);
#endif

}  // namespace pfxbench
