// The jointed scenes: capsule chains hanging from a fixed point by ball joints, released
// from the horizontal, with a heavy sphere at the end. A light link between a fixed point
// and a heavy load is the classic hard case for iterative solvers in maximal coordinates:
// the load's weight has to be carried through every link within one step's iterations.
#include <cmath>
#include <string>

#include "bench_scene.h"

namespace pfxbench {

namespace {

constexpr double kLinkLength = 0.2;  // between the two joint anchors of a link
constexpr double kLinkRadius = 0.02;
constexpr double kLinkMass = 1;
// One size for every payload mass, so that the variants differ in mass ratio alone.
constexpr double kPayloadRadius = 0.1;

// `links` capsules along +X from a fixed point at the origin, each joined to the one
// before (the first to the world) at their shared end point, then the payload sphere
// joined to the last link's free end, touching it there. Only the payload is tracked for
// position_error: it carries the error of every link above it.
Scene makeChain(const std::string& name, int links, double payloadRatio) {
  Scene scene;
  scene.name = name;
  scene.variant = "ratio" + std::to_string(static_cast<long long>(payloadRatio));
  scene.duration = 10;
  scene.metrics = {Metric::JointGapMax, Metric::PositionError};
  const ShapeDesc link = ShapeDesc::capsule(0.5 * kLinkLength, kLinkRadius);
  for (int i = 0; i < links; ++i) {
    scene.bodies.push_back(makeDynamicBody(link, kLinkMass, Vec3((i + 0.5) * kLinkLength, 0, 0)));
    JointDesc joint;
    joint.bodyA = i == 0 ? kWorld : i - 1;
    joint.bodyB = i;
    joint.anchor = Vec3(i * kLinkLength, 0, 0);
    scene.joints.push_back(joint);
  }
  const double end = links * kLinkLength;
  scene.bodies.push_back(makeDynamicBody(ShapeDesc::sphere(kPayloadRadius),
                                         payloadRatio * kLinkMass,
                                         Vec3(end + kPayloadRadius, 0, 0)));
  JointDesc joint;
  joint.bodyA = links - 1;
  joint.bodyB = links;
  joint.anchor = Vec3(end, 0, 0);
  scene.joints.push_back(joint);
  scene.trackedBodies = {links};
  // A whip's tip outruns a free fall from the chain's full length, but not tenfold.
  const double length = end + 2 * kPayloadRadius;
  scene.speedLimit = 10 * std::sqrt(2 * scene.gravity.norm() * length);
  return scene;
}

}  // namespace

// 20 links with payloads of 1, 10, 100 and 1000 link masses.
void buildChainScene(std::vector<Scene>& variants) {
  for (double ratio : {1.0, 10.0, 100.0, 1000.0}) variants.push_back(makeChain("chain", 20, ratio));
}

// 100 links with a payload of one link mass.
void buildLongChainScene(std::vector<Scene>& variants) {
  variants.push_back(makeChain("longchain", 100, 1));
}

}  // namespace pfxbench

namespace pfxbench {

namespace {

// Poses are given in the ragdoll's own frame (see addRagdoll).
struct RagdollPart {
  ShapeDesc shape;
  double mass;
  Vec3 position;
  bool upright;  // capsule turned from X to Y (legs)
};

struct RagdollJoint {
  int parent, child;
  JointType type;
  Vec3 anchor;
  Vec3 axis;
};

}  // namespace

void addRagdoll(Scene& scene, const Vec3& origin, const Quat& turn) {
  constexpr double pelvis = 1.05;  // height of the pelvis centre
  const RagdollPart parts[] = {
      {ShapeDesc::capsule(0.10, 0.10), 10, Vec3(0, pelvis, 0), false},               // 0 pelvis
      {ShapeDesc::capsule(0.12, 0.12), 20, Vec3(0, pelvis + 0.30, 0), false},        // 1 torso
      {ShapeDesc::sphere(0.10), 5, Vec3(0, pelvis + 0.57, 0), false},                // 2 head
      {ShapeDesc::capsule(0.105, 0.045), 2.5, Vec3(-0.39, pelvis + 0.38, 0), false},  // 3 arms
      {ShapeDesc::capsule(0.105, 0.045), 2.5, Vec3(0.39, pelvis + 0.38, 0), false},
      {ShapeDesc::capsule(0.10, 0.04), 1.5, Vec3(-0.68, pelvis + 0.38, 0), false},    // 5 forearms
      {ShapeDesc::capsule(0.10, 0.04), 1.5, Vec3(0.68, pelvis + 0.38, 0), false},
      {ShapeDesc::capsule(0.18, 0.07), 7, Vec3(-0.1, pelvis - 0.35, 0), true},        // 7 thighs
      {ShapeDesc::capsule(0.18, 0.07), 7, Vec3(0.1, pelvis - 0.35, 0), true},
      {ShapeDesc::capsule(0.17, 0.055), 6.5, Vec3(-0.1, pelvis - 0.825, 0), true},    // 9 shins
      {ShapeDesc::capsule(0.17, 0.055), 6.5, Vec3(0.1, pelvis - 0.825, 0), true},
  };
  const Vec3 bend = Vec3::UnitY(), knee = Vec3::UnitX();
  const RagdollJoint joints[] = {
      {0, 1, JointType::Ball, Vec3(0, pelvis + 0.14, 0), Vec3::Zero()},
      {1, 2, JointType::Ball, Vec3(0, pelvis + 0.46, 0), Vec3::Zero()},
      {1, 3, JointType::Ball, Vec3(-0.24, pelvis + 0.38, 0), Vec3::Zero()},
      {1, 4, JointType::Ball, Vec3(0.24, pelvis + 0.38, 0), Vec3::Zero()},
      {3, 5, JointType::Hinge, Vec3(-0.54, pelvis + 0.38, 0), bend},
      {4, 6, JointType::Hinge, Vec3(0.54, pelvis + 0.38, 0), bend},
      {0, 7, JointType::Ball, Vec3(-0.1, pelvis - 0.10, 0), Vec3::Zero()},
      {0, 8, JointType::Ball, Vec3(0.1, pelvis - 0.10, 0), Vec3::Zero()},
      {7, 9, JointType::Hinge, Vec3(-0.1, pelvis - 0.60, 0), knee},
      {8, 10, JointType::Hinge, Vec3(0.1, pelvis - 0.60, 0), knee},
  };
  const int first = static_cast<int>(scene.bodies.size());
  const Quat upright(Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()));
  for (const RagdollPart& part : parts) {
    const Quat local = part.upright ? upright : Quat::Identity();
    scene.bodies.push_back(
        makeDynamicBody(part.shape, part.mass, origin + turn * part.position, turn * local));
  }
  for (const RagdollJoint& j : joints) {
    JointDesc joint;
    joint.type = j.type;
    joint.bodyA = first + j.parent;
    joint.bodyB = first + j.child;
    joint.anchor = origin + turn * j.anchor;
    if (j.type == JointType::Hinge) {
      joint.axis = turn * j.axis;
      joint.lowerLimit = -1.2;
      joint.upperLimit = 1.2;
    }
    scene.joints.push_back(joint);
  }
}

// Eight ragdolls dropped lying flat, each turned 45 degrees from the one below, onto one
// spot of the ground: a pile of limbs pressing on jointed limbs, joint limits under load.
void buildRagdollScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "ragdoll";
  scene.duration = 5;
  scene.metrics = {Metric::JointGapMax, Metric::PenetrationMax, Metric::Escaped};
  scene.bodies.push_back(makeFixedBody(ShapeDesc::box(Vec3(20, 1, 20)), Vec3(0, -1, 0)));
  const Quat lieDown(Eigen::AngleAxisd(-0.5 * M_PI, Vec3::UnitX()));
  for (int i = 0; i < 8; ++i) {
    const Quat yaw(Eigen::AngleAxisd(0.25 * M_PI * i, Vec3::UnitY()));
    // Lying down puts the pelvis 1.05 m out along -Z; shift it back over the origin.
    const Quat turn = yaw * lieDown;
    const Vec3 origin = Vec3(0, 0.2 + 0.35 * i, 0) - turn * Vec3(0, 1.05, 0);
    addRagdoll(scene, origin, turn);
  }
  scene.keepInside.min = Vec3(-5, -0.5, -5);
  scene.keepInside.max = Vec3(5, 10, 5);
  scene.speedLimit = 30;
  variants.push_back(scene);
}

}  // namespace pfxbench
