// Sample 1_simple: the simple pipeline (nothing cached between frames) drops a mix of
// spheres, boxes, capsules and cylinders onto a fixed floor. Prints where they ended up:
// every body should lie on the floor, none below it, none still moving fast.
#include <algorithm>
#include <cstdio>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

int main() {
  PfxWorld world;
  PfxWorldParam param;
  param.pipeline = kPfxPipelineSimple;
  param.iteration = 5;
  world.initialize(param);

  PfxBodyInit floor;
  floor.mass = 0;
  floor.position = PfxVector3(0, -0.5f, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(10, 0.5f, 10)), floor);

  const PfxShape shapes[4] = {pfxMakeShape(PfxSphere(0.3f)), pfxMakeShape(PfxBox(0.3f, 0.2f, 0.25f)),
                              pfxMakeShape(PfxCapsule(0.3f, 0.2f)),
                              pfxMakeShape(PfxCylinder(0.25f, 0.25f))};
  const int count = 40;
  for (int i = 0; i < count; ++i) {
    PfxBodyInit init;
    init.position = PfxVector3(-3.0f + 1.5f * (i % 5), 1.0f + 0.8f * (i / 5), -1.5f + 0.75f * (i % 4));
    init.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f * i, PfxVector3(1, 2, 3).normalized()));
    pfxAddBody(world, shapes[i % 4], init);
  }

  const int steps = 600;
  double seconds = 0;
  for (int s = 0; s < steps; ++s) {
    if (world.step() != PFX_OK) return 1;
    seconds += world.getStats().stepSeconds;
  }

  PfxFloat lowest = 1e9f, highest = -1e9f, fastest = 0;
  for (PfxUInt32 id = 1; id < world.getNumRigidBodies(); ++id) {
    const PfxRigidState& s = world.getRigidState(id);
    PfxVector3 center, half;
    world.getCollidable(id).getWorldAabb(s.getTransform(), center, half);
    lowest = std::min(lowest, center.y() - half.y());
    highest = std::max(highest, center.y() + half.y());
    fastest = std::max(fastest, s.getLinearVelocity().norm());
  }
  const PfxWorldStats& stats = world.getStats();
  std::printf("1_simple: %d bodies dropped, %d steps of %.4f s, %u iterations\n", count, steps,
              param.timeStep, param.iteration);
  std::printf("lowest point of any body %.4f m (floor at 0), highest %.3f m\n", lowest, highest);
  std::printf("fastest body after 10 s: %.4f m/s; %u contact points, deepest %.4f m\n", fastest,
              stats.numContactPoints, stats.maxPenetration);
  std::printf("mean step time %.3f ms\n", 1e3 * seconds / steps);
  const bool ok = lowest > -0.05f && fastest < 0.5f;
  std::printf("%s\n", ok ? "all bodies rest on the floor" : "SOMETHING FELL THROUGH OR STILL MOVES");
  return ok ? 0 : 1;
}
