// The C++ side of the Python tests and of the Python overhead measurement: builds one of the
// scenes that pfx_scenes.py builds in Python (the same calls, the same values), steps it and
// prints either every body's state as the bits of its 13 floats, or the seconds per step of
// a loop that copies every body's position and orientation out after each step.
//
// usage: pfx_python_reference arm URDF STEPS [--time REPEATS]
//        pfx_python_reference pyramid STEPS [--time REPEATS]
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;

namespace {

// The arm of urdf/arm.urdf on a fixed base over a ground slab, gravity along -Z, its shoulder
// (joint_2) driven to 0.8 rad so that it swings over.
PfxInt32 buildArm(PfxWorld& world, PfxUrdfModel& model, const std::string& urdf) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  param.timeStep = PfxFloat(1) / 240;
  param.enableSleep = false;
  if (const PfxInt32 err = world.initialize(param); err != PFX_OK) return err;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, 0, PfxFloat(-0.5));
  if (const PfxInt32 err = pfxAddBody(world, pfxMakeShape(PfxBox(50, 50, PfxFloat(0.5))), ground);
      err != PFX_OK) {
    return err;
  }
  PfxUrdfLoadParam load;
  load.fixedBase = true;
  std::string message;
  if (const PfxInt32 err = pfxLoadUrdfFile(world, urdf, load, model, &message); err != PFX_OK) {
    std::fprintf(stderr, "pfx_python_reference: %s\n", message.c_str());
    return err;
  }
  return pfxSetUrdfJointCommand(world, model, PfxUInt32(pfxFindUrdfJoint(model, "joint_2")),
                                kPfxJointDrivePosition, PfxFloat(0.8));
}

// 210 one-metre cubes of 1 kg in 20 layers on a ground slab, gravity along -Y (the benchmark's
// pyramid).
PfxInt32 buildPyramid(PfxWorld& world) {
  PfxWorldParam param;
  param.enableSleep = false;
  if (const PfxInt32 err = world.initialize(param); err != PFX_OK) return err;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, PfxFloat(-0.5), 0);
  if (const PfxInt32 err = pfxAddBody(world, pfxMakeShape(PfxBox(50, PfxFloat(0.5), 50)), ground);
      err != PFX_OK) {
    return err;
  }
  const int base = 20;
  const double pitch = 1.02;
  for (int layer = 0; layer < base; ++layer) {
    const int count = base - layer;
    for (int i = 0; i < count; ++i) {
      PfxBodyInit cube;
      cube.position = PfxVector3(PfxFloat((i - 0.5 * (count - 1)) * pitch), PfxFloat(0.5 + layer), 0);
      if (const PfxInt32 err =
              pfxAddBody(world, pfxMakeShape(PfxBox(PfxFloat(0.5), PfxFloat(0.5), PfxFloat(0.5))), cube);
          err != PFX_OK) {
        return err;
      }
    }
  }
  return PFX_OK;
}

void printStates(const PfxWorld& world) {
  for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
    const PfxRigidState& s = world.getRigidState(i);
    PfxFloat values[13];
    std::copy(s.getPosition().data(), s.getPosition().data() + 3, values);
    std::copy(s.getOrientation().coeffs().data(), s.getOrientation().coeffs().data() + 4, values + 3);
    std::copy(s.getLinearVelocity().data(), s.getLinearVelocity().data() + 3, values + 7);
    std::copy(s.getAngularVelocity().data(), s.getAngularVelocity().data() + 3, values + 10);
    for (int k = 0; k < 13; ++k) {
      unsigned long long bits = 0;
      std::memcpy(&bits, &values[k], sizeof(PfxFloat));
      std::printf(k ? " %0*llx" : "%0*llx", int(2 * sizeof(PfxFloat)), bits);
    }
    std::printf("\n");
  }
}

// CPU seconds of this thread: on a shared machine wall time measures the other jobs too.
double threadSeconds() {
  timespec now;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

// Seconds per step, the fastest of `repeats` runs of `steps` steps from the same start: the
// loop a controller runs, reading every body's position and orientation after each step.
double timeLoop(int steps, int repeats, PfxInt32 (*rebuild)(PfxWorld&, void*), void* context) {
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    PfxWorld world;
    if (rebuild(world, context) != PFX_OK) std::exit(1);
    std::vector<PfxFloat> positions(3 * world.getNumRigidBodies());
    std::vector<PfxFloat> orientations(4 * world.getNumRigidBodies());
    const double start = threadSeconds();
    for (int step = 0; step < steps; ++step) {
      if (world.step() != PFX_OK) std::exit(1);
      const PfxRigidState* states = world.getRigidStates();
      for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
        std::copy(states[i].getPosition().data(), states[i].getPosition().data() + 3,
                  &positions[3 * i]);
        std::copy(states[i].getOrientation().coeffs().data(),
                  states[i].getOrientation().coeffs().data() + 4, &orientations[4 * i]);
      }
    }
    best = std::min(best, (threadSeconds() - start) / steps);
  }
  return best;
}

struct ArmContext {
  std::string urdf;
  PfxUrdfModel model;
};

PfxInt32 rebuildArm(PfxWorld& world, void* context) {
  ArmContext& arm = *static_cast<ArmContext*>(context);
  arm.model = PfxUrdfModel();
  return buildArm(world, arm.model, arm.urdf);
}

PfxInt32 rebuildPyramid(PfxWorld& world, void*) { return buildPyramid(world); }

int usage() {
  std::fprintf(stderr,
               "usage: pfx_python_reference arm URDF STEPS [--time REPEATS]\n"
               "       pfx_python_reference pyramid STEPS [--time REPEATS]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string scene = argv[1];
  ArmContext arm;
  int next = 2;
  PfxInt32 (*rebuild)(PfxWorld&, void*) = nullptr;
  void* context = nullptr;
  if (scene == "arm") {
    if (argc < 4) return usage();
    arm.urdf = argv[next++];
    rebuild = &rebuildArm;
    context = &arm;
  } else if (scene == "pyramid") {
    rebuild = &rebuildPyramid;
  } else {
    return usage();
  }
  const int steps = std::atoi(argv[next++]);
  if (steps <= 0) return usage();
  if (next < argc) {
    if (std::strcmp(argv[next], "--time") != 0 || next + 1 >= argc) return usage();
    const int repeats = std::max(1, std::atoi(argv[next + 1]));
    std::printf("%.9e\n", timeLoop(steps, repeats, rebuild, context));
    return 0;
  }
  PfxWorld world;
  if (rebuild(world, context) != PFX_OK) return 1;
  for (int step = 0; step < steps; ++step) {
    if (world.step() != PFX_OK) return 1;
  }
  printStates(world);
  return 0;
}
