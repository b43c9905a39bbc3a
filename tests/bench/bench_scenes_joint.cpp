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
