// Sample 11_xml_import: scenes built from files. (1) The pfx scene XML of the README: bodies
// of every shape come to rest on the ground, a hinged pendulum falls onto its limit, a
// driven slider rides at its speed. (2) Gazebo's simple_pendulums.world through SDFormat:
// three 10 m pendulums released level reach the bottom at a quarter period (1.872 s) and
// are back level after one period (7.488 s). Prints what happened and checks it.
//
// Usage: sample_11_xml_import [scene.xml [world.sdf [model folder]]]; the defaults are the
// files of tests/loaders/data.
#include <cmath>
#include <cstdio>
#include <string>

#include "pfx/loaders/pfx_scene_loader.h"

using namespace pfx;

namespace {

const std::string kData = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/";

bool check(bool ok, const char* what) {
  std::printf("  %-58s %s\n", what, ok ? "ok" : "FAILED");
  return ok;
}

PfxVector3 position(const PfxWorld& world, const PfxSceneModel& model, const char* name) {
  return world.getRigidState(model.bodies[pfxFindSceneBody(model, name)].bodyId).getPosition();
}

bool xmlScene(const std::string& path) {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  PfxSceneModel model;
  std::string message;
  if (pfxLoadSceneXml(world, path, PfxSceneLoadParam(), model, &message) != PFX_OK) {
    std::printf("%s\n", message.c_str());
    return false;
  }
  std::printf("%s: scene '%s', %u bodies, %u joints, %u couplings, step %.4f s x %u sub-steps\n",
              path.c_str(), model.name.c_str(), model.numBodies, model.numJoints,
              model.numCouplings, double(world.getParam().timeStep), world.getParam().subStep);
  const int steps = static_cast<int>(std::lround(3 / world.getParam().timeStep));
  for (int i = 0; i < steps; ++i) world.step();
  bool ok = true;
  const char* resting[] = {"box", "sphere", "capsule", "cylinder", "hull", "dumbbell"};
  const double heights[] = {0.25, 0.2, 0.15, 0.2, 0.2, 0.25};
  for (int i = 0; i < 6; ++i) {
    const double z = position(world, model, resting[i]).z();
    std::printf("  %-9s rests at z = %.4f m (expected %.2f)\n", resting[i], z, heights[i]);
    ok &= std::abs(z - heights[i]) < 0.01;
  }
  ok &= check(ok, "every shape rests on the ground");
  const double hinge =
      pfxGetSceneJointPosition(world, model.joints[pfxFindSceneJoint(model, "hinge")]);
  std::printf("  pendulum hinge at %.3f rad (limit 1)\n", hinge);
  ok &= check(std::abs(std::abs(hinge) - 1) < 0.02, "the pendulum rests on its limit");
  const double rail =
      pfxGetSceneJointPosition(world, model.joints[pfxFindSceneJoint(model, "rail")]);
  std::printf("  cart travelled %.3f m in 3 s (drive 0.5 m/s)\n", rail);
  ok &= check(std::abs(rail - 1.5) < 0.05, "the slider drive keeps its speed");
  return ok;
}

// Angle of a pendulum's centre from the downward vertical, in degrees.
double angle(const PfxWorld& world, PfxUInt32 bodyId, const PfxVector3& pivot,
             const PfxVector3& side) {
  const PfxVector3 d = world.getRigidState(bodyId).getPosition() - pivot;
  return std::atan2(double(d.dot(side)), double(-d.z())) * 180 / PFX_PI;
}

bool sdfWorld(const std::string& path, const std::string& models) {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  PfxSceneModel model;
  PfxSceneLoadParam param;
  param.modelPaths.push_back(models);
  std::string message;
  if (pfxLoadSdfWorld(world, path, param, model, &message) != PFX_OK) {
    std::printf("%s\n", message.c_str());
    return false;
  }
  const PfxWorldParam& p = world.getParam();
  std::printf(
      "%s: world '%s', %u bodies, %u joints, g = (%g, %g, %g), step %g s, %u "
      "iterations, %zu warnings:\n",
      path.c_str(), model.name.c_str(), model.numBodies, model.numJoints, double(p.gravity.x()),
      double(p.gravity.y()), double(p.gravity.z()), double(p.timeStep), p.iteration,
      model.warnings.size());
  for (const std::string& warning : model.warnings) std::printf("    %s\n", warning.c_str());
  const PfxSceneJoint& pivotJoint = model.joints[pfxFindSceneJoint(model, "model_2::joint_0")];
  const PfxJoint& j = world.getJoint(pivotJoint.jointId);
  const PfxVector3 pivot = world.getRigidState(j.m_rigidBodyIdA).getTransform() * j.m_anchorA;
  const PfxUInt32 bob = model.bodies[pfxFindSceneBody(model, "model_2::link_1")].bodyId;
  const PfxVector3 start = world.getRigidState(bob).getPosition() - pivot;
  const PfxVector3 side = PfxVector3(start.x(), start.y(), 0).normalized();
  bool ok = true;
  const double times[] = {1.872, 7.488};
  const double expected[] = {0, 90};
  double t = 0;
  for (int k = 0; k < 2; ++k) {
    while (t < times[k] - 1e-9) {
      world.step();
      t += p.timeStep;
    }
    const double a = angle(world, bob, pivot, side);
    std::printf("  model_2 at t = %.3f s: %.2f deg from the vertical (expected %.0f)\n", t, a,
                expected[k]);
    ok &= std::abs(a - expected[k]) < 2;
  }
  return check(ok, "the pendulum keeps Gazebo's period") && ok;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string scene = argc > 1 ? argv[1] : kData + "scenes/example.xml";
  const std::string sdf = argc > 2 ? argv[2] : kData + "sdf/worlds/simple_pendulums.world";
  const std::string models = argc > 3 ? argv[3] : kData + "sdf/models";
  const bool xml = xmlScene(scene);
  const bool world = sdfWorld(sdf, models);
  std::printf("%s\n", xml && world ? "all checks passed" : "SOME CHECKS FAILED");
  return xml && world ? 0 : 1;
}
