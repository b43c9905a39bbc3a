// Sample 6_joint: the basic joints, then a ragdoll dropped onto the ground. Prints, for
// each, what it measured: how far every joint strayed from its locks and limits, the
// largest gap between a joint's anchors, and whether the bodies came to rest.
#include <algorithm>
#include <cstdio>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"

using namespace pfx;

namespace {

constexpr PfxFloat kDegree = PFX_PI / 180;

struct Measured {
  PfxFloat violation = 0;  // radians or metres
  PfxFloat gap = 0;        // metres, between anchors that should coincide
};

void measure(const PfxWorld& world, Measured& m) {
  for (PfxUInt32 j = 0; j < world.getNumJoints(); ++j) {
    const PfxJoint& joint = world.getJoint(j);
    const PfxRigidState& a = world.getRigidState(joint.m_rigidBodyIdA);
    const PfxRigidState& b = world.getRigidState(joint.m_rigidBodyIdB);
    m.violation = std::max(m.violation, pfxGetJointLimitViolation(joint, a, b));
    if (joint.m_type == kPfxJointSlider) continue;  // its anchors slide apart by design
    m.gap = std::max(m.gap, ((a.getPosition() + a.getOrientation() * joint.m_anchorA) -
                             (b.getPosition() + b.getOrientation() * joint.m_anchorB))
                                .norm());
  }
}

PfxFloat fastest(const PfxWorld& world) {
  PfxFloat speed = 0;
  for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
    speed = std::max(speed, world.getRigidState(i).getLinearVelocity().norm());
  }
  return speed;
}

void addGround(PfxWorld& world) {
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -0.5f, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(20, 0.5f, 20)), ground);
}

// Scene 1: each basic joint holds a box below a fixed post; the boxes are kicked sideways.
bool basicJoints() {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  addGround(world);
  for (int type = 0; type < 6; ++type) {
    PfxBodyInit post;
    post.mass = 0;
    post.position = PfxVector3(-5 + 2.0f * type, 3, 0);
    PfxUInt32 postId = 0, boxId = 0;
    pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), post, &postId);
    PfxBodyInit box;
    box.position = post.position - PfxVector3(0, 0.8f, 0);
    box.angularVelocity = PfxVector3(1, 2, 3);
    box.linearVelocity = PfxVector3(1.5f, 0, 1);
    pfxAddBody(world, pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f)), box, &boxId);
    const PfxRigidState& a = world.getRigidState(postId);
    const PfxRigidState& b = world.getRigidState(boxId);
    const PfxVector3 anchor = post.position - PfxVector3(0, 0.4f, 0);
    PfxJoint joint;
    switch (type) {
      case 0: { PfxBallJointInitParam p; p.anchorPoint = anchor; pfxInitializeBallJoint(joint, a, b, p); break; }
      case 1: { PfxSwingTwistJointInitParam p; p.anchorPoint = anchor; p.twistAxis = -PfxVector3::UnitY(); p.swingUpperAngle = 30 * kDegree; pfxInitializeSwingTwistJoint(joint, a, b, p); break; }
      case 2: { PfxHingeJointInitParam p; p.anchorPoint = anchor; p.axis = PfxVector3::UnitZ(); p.lowerAngle = -45 * kDegree; p.upperAngle = 45 * kDegree; pfxInitializeHingeJoint(joint, a, b, p); break; }
      case 3: { PfxSliderJointInitParam p; p.anchorPoint = anchor; p.direction = PfxVector3::UnitY(); p.lowerDistance = -0.5f; p.upperDistance = 0.2f; pfxInitializeSliderJoint(joint, a, b, p); break; }
      case 4: { PfxFixedJointInitParam p; p.anchorPoint = anchor; pfxInitializeFixedJoint(joint, a, b, p); break; }
      case 5: { PfxUniversalJointInitParam p; p.anchorPoint = anchor; p.axis = -PfxVector3::UnitY(); p.upVec = PfxVector3::UnitX(); pfxInitializeUniversalJoint(joint, a, b, p); break; }
    }
    world.addJoint(joint);
  }
  Measured m;
  for (int i = 0; i < 600; ++i) {
    world.step();
    measure(world, m);
  }
  std::printf("basic joints (ball, swing-twist, hinge, slider, fixed, universal) after 10 s:\n"
              "  largest excursion past a lock or limit %.3f deg / %.2e m, largest anchor gap %.2e m\n",
              m.violation / kDegree, m.violation, m.gap);
  return m.violation < 2 * kDegree && m.gap < 1e-3f;
}

// Scene 2: a ragdoll falls 2 m onto the ground and lies still.
bool ragdoll() {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  addGround(world);
  PfxRagdoll doll;
  const PfxQuat tumble(Eigen::AngleAxis<PfxFloat>(0.6f, PfxVector3(1, 0, 0.3f).normalized()));
  if (pfxAddRagdoll(world, PfxVector3(0, 3, 0), tumble, &doll) != PFX_OK) return false;
  Measured m;
  PfxFloat lastSecond = 0;
  for (int i = 0; i < 600; ++i) {
    world.step();
    measure(world, m);
    if (i >= 540) lastSecond = std::max(lastSecond, fastest(world));
  }
  std::printf("ragdoll (16 bodies, 15 joints) dropped from 2 m, after 10 s:\n"
              "  largest excursion past a limit %.3f deg, largest anchor gap %.2e m,\n"
              "  fastest body in the last second %.4f m/s -> %s\n",
              m.violation / kDegree, m.gap, lastSecond, lastSecond < 0.05f ? "at rest" : "STILL MOVING");
  return m.violation < 2 * kDegree && m.gap < 1e-3f && lastSecond < 0.05f;
}

}  // namespace

int main() {
  const bool a = basicJoints();
  const bool b = ragdoll();
  std::printf("%s\n", a && b ? "joints held within their limits" : "A JOINT STRAYED");
  return a && b ? 0 : 1;
}
