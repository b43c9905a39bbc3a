// Robots at a large step: bullet3's humanoid (urdf/zoo/humanoid.urdf) and the package's
// ragdoll (urdf/ragdoll.urdf), dropped onto the ground in several poses at dt 1/30, come to
// rest without lying in themselves or in the ground. The humanoid crept at 2-4 mm/s for 30 s
// with 4 cm of overlap between its own links while the joints' position correction did not
// see the contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;

namespace {

// Turns the robot's bodies (from `first` on) by `turn` about the origin, then lifts them so
// that their lowest bounding box corner is `clearance` above z = 0.
void placeTurned(PfxWorld& world, PfxUInt32 first, const PfxQuat& turn, PfxFloat clearance) {
  for (PfxUInt32 id = first; id < world.getNumRigidBodies(); ++id) {
    PfxRigidState state = world.getRigidState(id);
    state.setPosition(turn * state.getPosition());
    state.setOrientation(turn * state.getOrientation());
    ASSERT_EQ(world.setRigidState(id, state), PFX_OK);
  }
  PfxFloat lowest = std::numeric_limits<PfxFloat>::max();
  for (PfxUInt32 id = first; id < world.getNumRigidBodies(); ++id) {
    PfxVector3 centre, half;
    world.getCollidable(id).getWorldAabb(world.getRigidState(id).getTransform(), centre, half);
    lowest = std::min(lowest, centre.z() - half.z());
  }
  for (PfxUInt32 id = first; id < world.getNumRigidBodies(); ++id) {
    PfxRigidState state = world.getRigidState(id);
    state.setPosition(state.getPosition() + PfxVector3(0, 0, clearance - lowest));
    ASSERT_EQ(world.setRigidState(id, state), PFX_OK);
  }
}

// Drops the robot of `file` (under the source folder) turned by `angle` about a tilted
// axis at dt 1/30, runs 14 s, and checks that it lands and has settled after 12 s. A
// ragdoll can land balanced: turned 0.4 rad, the package's ragdoll lands with its right hand
// on an edge and tips over it from 3 to 11 s, losing height all the way (the same from that
// state with the contact routines before GJK kept its last direction's separation); a
// twitch, as below, never stops.
void dropAndSettle(const char* file, PfxFloat angle) {
  SCOPED_TRACE(angle);
  PfxWorldParam param;
  param.timeStep = PfxFloat(1) / 30;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  param.enableSleep = false;  // rest is measured, not granted
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, 0, -0.5f);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(50, 50, 0.5f)), ground), PFX_OK);
  PfxUrdfModel model;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfFile(world, std::string(PFX_SOURCE_DIR) + "/" + file, PfxUrdfLoadParam(),
                            model, &message),
            PFX_OK)
      << message;
  ASSERT_GT(model.numBodies, 5u);
  const PfxQuat turn(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3(1, 0.3f, 0).normalized()));
  placeTurned(world, model.firstBodyId, turn, 0.05f);

  PfxFloat fastestLate = 0, deepestLate = 0, widestGap = 0;
  const int steps = 14 * 30;
  for (int step = 1; step <= steps; ++step) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxFloat time = PfxFloat(step) / 30;
    widestGap = std::max(widestGap, world.getStats().maxJointGap);
    if (time > 5) deepestLate = std::max(deepestLate, world.getStats().maxPenetration);
    if (time <= 12) continue;
    for (PfxUInt32 id = model.firstBodyId; id < world.getNumRigidBodies(); ++id) {
      const PfxRigidState& state = world.getRigidState(id);
      ASSERT_TRUE(state.isValid());
      fastestLate = std::max(fastestLate, PfxFloat(state.getLinearVelocity().norm()));
    }
  }
  std::printf("%s dropped turned %.1f rad, dt 1/30: fastest link after 12 s %.2e m/s, "
              "deepest overlap after 5 s %.4f m, widest joint gap %.1e m\n",
              file, angle, fastestLate, deepestLate, widestGap);
  EXPECT_LT(fastestLate, 1e-3f);
  EXPECT_LT(deepestLate, 0.01f);
  EXPECT_LT(widestGap, 0.01f);  // as for the other scenes at dt 1/30; 3 mm on landing
}

}  // namespace

// At 1/240 it settles within 4 s.
TEST(StiffRobots, HumanoidComesToRestAtDt1Over30) {
  for (const PfxFloat angle : {0.0f, 0.8f, 1.6f, 2.4f}) {
    dropAndSettle("urdf/zoo/humanoid.urdf", angle);
  }
}

// The package's ragdoll, whose hips, shoulders, wrists, ankles, neck and lower spine are
// collapsed ball and universal joints with limits. It twitched at 2-33 mm/s in 6 of these 8
// drops while limit rows at rest measured their tree's response from trials lost in rounding.
TEST(StiffRobots, RagdollComesToRestAtDt1Over30) {
  for (int pose = 0; pose < 8; ++pose) dropAndSettle("urdf/ragdoll.urdf", PfxFloat(0.4) * pose);
}
