// Sample 1_simple: the simple pipeline (nothing cached between frames) drops a mix of
// spheres, boxes, capsules and cylinders into a walled pen. Prints where they ended up:
// every body inside the pen and on its floor, none sunk into it. (Spheres and lying
// capsules may roll on: there is no rolling resistance.)
#include <algorithm>
#include <cmath>
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
  for (int side = 0; side < 4; ++side) {
    PfxBodyInit wall;
    wall.mass = 0;
    const PfxFloat sign = side < 2 ? 1.0f : -1.0f;
    const bool alongX = side % 2 == 0;
    wall.position = alongX ? PfxVector3(0, 1, sign * 5.25f) : PfxVector3(sign * 5.25f, 1, 0);
    pfxAddBody(world, pfxMakeShape(alongX ? PfxBox(5.5f, 1, 0.25f) : PfxBox(0.25f, 1, 5.5f)), wall);
  }
  const PfxUInt32 firstBody = world.getNumRigidBodies();

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

  PfxFloat lowest = 1e9f, highest = -1e9f, fastest = 0, outermost = 0;
  for (PfxUInt32 id = firstBody; id < world.getNumRigidBodies(); ++id) {
    const PfxRigidState& s = world.getRigidState(id);
    const PfxShape& shape = world.getCollidable(id).getShape(0);
    const PfxTransform3 pose = s.getTransform() * shape.getOffsetTransform();
    lowest = std::min(lowest, pfxGetSupportPoint(shape, pose, -PfxVector3::UnitY()).y());
    highest = std::max(highest, pfxGetSupportPoint(shape, pose, PfxVector3::UnitY()).y());
    for (int axis : {0, 2}) {
      const PfxVector3 out = PfxVector3::Unit(axis);
      outermost = std::max(outermost, pfxGetSupportPoint(shape, pose, out).dot(out));
      outermost = std::max(outermost, -pfxGetSupportPoint(shape, pose, -out).dot(out));
    }
    fastest = std::max(fastest, s.getLinearVelocity().norm());
  }
  const PfxWorldStats& stats = world.getStats();
  std::printf("1_simple: %d bodies dropped, %d steps of %.4f s, %u iterations\n", count, steps,
              param.timeStep, param.iteration);
  std::printf("lowest point of any body %.4f m (floor at 0), highest %.3f m\n", lowest, highest);
  std::printf("outermost point %.3f m from the centre (walls at 5.0)\n", outermost);
  std::printf("fastest body after 10 s: %.4f m/s; %u contact points, deepest %.4f m\n", fastest,
              stats.numContactPoints, stats.maxPenetration);
  std::printf("mean step time %.3f ms\n", 1e3 * seconds / steps);
  const bool ok = lowest > -0.02f && outermost < 5.02f && highest < 2.0f;
  std::printf("%s\n", ok ? "all bodies lie in the pen, on its floor"
                          : "A BODY SANK, ESCAPED OR STILL FLIES");
  return ok ? 0 : 1;
}
