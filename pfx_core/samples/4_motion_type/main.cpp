// Sample 4_motion_type: the three scenes of the seed. (1) A keyframe paddle, driven by
// poses the application feeds each frame, sweeps boxes off a table. (2) A one-way box and
// an active box of the same mass fall onto a heavy active plank: the one-way box bounces
// off it without pressing it down. (3) A trigger in the middle reports the bodies that pass
// through it and stops none of them.
#include <cmath>
#include <cstdio>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

void addFloor(PfxWorld& world) {
  PfxBodyInit floor;
  floor.mass = 0;
  floor.position = PfxVector3(0, -0.5f, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(20, 0.5f, 20)), floor);
}

bool keyframeScene() {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  addFloor(world);
  PfxBodyInit init;
  init.motionType = kPfxMotionTypeKeyframe;
  init.position = PfxVector3(0, 0.5f, 0);
  PfxUInt32 paddle = 0;
  pfxAddBody(world, pfxMakeShape(PfxBox(2.0f, 0.5f, 0.1f)), init, &paddle);
  PfxUInt32 boxes[5];
  for (int i = 0; i < 5; ++i) {
    PfxBodyInit box;
    box.position = PfxVector3(-1.5f + 0.75f * i, 0.25f, 1.0f);
    pfxAddBody(world, pfxMakeShape(PfxBox(0.25f, 0.25f, 0.25f)), box, &boxes[i]);
  }
  // The paddle turns a half turn about the vertical in 2 s: the application gives poses.
  const PfxFloat dt = world.getParam().timeStep;
  for (int i = 1; i <= 180; ++i) {
    const PfxFloat angle = std::min(PFX_PI, 0.5f * PFX_PI * i * dt);
    world.setKeyframeTarget(paddle, PfxVector3(0, 0.5f, 0),
                            PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3::UnitY())));
    world.step();
  }
  int swept = 0;
  for (PfxUInt32 id : boxes) swept += world.getRigidState(id).getPosition().z() < 0.5f ? 1 : 0;
  const PfxFloat turned = 2 * std::acos(std::min(PfxFloat(1), std::abs(world.getRigidState(paddle).getOrientation().w())));
  std::printf("keyframe: paddle turned %.1f deg as fed; %d of 5 boxes swept off their row\n",
              turned * 180 / PFX_PI, swept);
  return swept >= 3 && std::abs(turned - PFX_PI) < 0.01f;
}

bool oneWayScene() {
  PfxWorldParam param;
  param.gravity.setZero();
  PfxWorld world;
  world.initialize(param);
  // In each lane a heavy box flies at a light one: active in the first lane, one-way in the
  // second. The active one knocks its target away; the one-way one gives no impulse, so its
  // target stays put, and it is itself stopped as if the light box were a wall.
  const PfxMotionType types[2] = {kPfxMotionTypeActive, kPfxMotionTypeOneWay};
  PfxUInt32 target[2], heavy[2];
  for (int k = 0; k < 2; ++k) {
    PfxBodyInit light;
    light.position = PfxVector3(1, 0, 2.0f * k);
    light.mass = 1;
    pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), light, &target[k]);
    PfxBodyInit h;
    h.motionType = types[k];
    h.mass = 20;
    h.position = PfxVector3(-1, 0, 2.0f * k);
    h.linearVelocity = PfxVector3(2, 0, 0);
    pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), h, &heavy[k]);
  }
  for (int i = 0; i < 120; ++i) world.step();
  const PfxFloat targetSpeed[2] = {world.getRigidState(target[0]).getLinearVelocity().x(),
                                   world.getRigidState(target[1]).getLinearVelocity().x()};
  const PfxFloat heavySpeed = world.getRigidState(heavy[1]).getLinearVelocity().x();
  std::printf("one-way: a 20 kg active box sent its 1 kg target off at %.3f m/s;\n"
              "         a 20 kg one-way box left its 1 kg target at %.3f m/s and now moves at %.3f m/s\n",
              targetSpeed[0], targetSpeed[1], heavySpeed);
  return targetSpeed[0] > 1.5f && std::abs(targetSpeed[1]) < 1e-4f && heavySpeed < 0.1f;
}

bool triggerScene() {
  PfxWorld world;
  PfxWorldParam param;
  world.initialize(param);
  addFloor(world);
  PfxBodyInit t;
  t.motionType = kPfxMotionTypeTrigger;
  t.position = PfxVector3(0, 2, 0);
  PfxUInt32 trigger = 0;
  pfxAddBody(world, pfxMakeShape(PfxBox(1, 1, 1)), t, &trigger);
  for (int i = 0; i < 3; ++i) {
    PfxBodyInit s;
    s.position = PfxVector3(-0.5f + 0.5f * i, 5 + i, 0);
    pfxAddBody(world, pfxMakeShape(PfxSphere(0.2f)), s);
  }
  bool inside[4] = {false, false, false, false};
  for (int step = 0; step < 180; ++step) {
    world.step();
    for (PfxUInt32 p = 0; p < world.getNumContactPairs(); ++p) {
      const PfxConstraintPair& pair = world.getContactPair(p);
      if (pfxGetObjectIdA(pair) != trigger && pfxGetObjectIdB(pair) != trigger) continue;
      const PfxUInt32 other = pfxGetObjectIdA(pair) == trigger ? pfxGetObjectIdB(pair) : pfxGetObjectIdA(pair);
      if (world.getContactManifold(pair).getNumContacts() > 0 && other >= 2) inside[other - 2] = true;
    }
  }
  int reported = 0, onFloor = 0;
  for (int i = 0; i < 3; ++i) {
    reported += inside[i] ? 1 : 0;
    onFloor += world.getRigidState(2 + i).getPosition().y() < 0.25f ? 1 : 0;
  }
  std::printf("trigger: %d of 3 spheres reported inside the trigger; %d of 3 fell through it to the floor\n",
              reported, onFloor);
  return reported == 3 && onFloor == 3;
}

}  // namespace

int main() {
  const bool a = keyframeScene();
  const bool b = oneWayScene();
  const bool c = triggerScene();
  std::printf("%s\n", a && b && c ? "all three scenes behaved as the motion types say" : "A SCENE MISBEHAVED");
  return a && b && c ? 0 : 1;
}
