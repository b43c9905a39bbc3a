// What the scene-file suites (test_scene_xml, test_sdf_loader) share: finding a loaded body or
// joint by name, and the check that a refused load leaves the world and the model as they
// were.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_scene_loader.h"

namespace pfx_test {

inline const pfx::PfxSceneBody& body(const pfx::PfxSceneModel& model, const std::string& name) {
  const pfx::PfxInt32 i = pfx::pfxFindSceneBody(model, name);
  EXPECT_GE(i, 0) << name;
  return model.bodies[std::max(i, 0)];
}

inline const pfx::PfxSceneJoint& joint(const pfx::PfxSceneModel& model, const std::string& name) {
  const pfx::PfxInt32 i = pfx::pfxFindSceneJoint(model, name);
  EXPECT_GE(i, 0) << name;
  return model.joints[std::max(i, 0)];
}

inline pfx::PfxVector3 position(const pfx::PfxWorld& world, const pfx::PfxSceneModel& model,
                                const std::string& name) {
  return world.getRigidState(body(model, name).bodyId).getPosition();
}

// One body already in the world, so that "unchanged" means more than "empty".
inline void addMarker(pfx::PfxWorld& world) {
  pfx::PfxBodyInit init;
  init.position = pfx::PfxVector3(1, 2, 3);
  ASSERT_EQ(pfx::pfxAddBody(world, pfx::pfxMakeShape(pfx::PfxSphere(0.5f)), init), pfx::PFX_OK);
}

// Runs `load(world, model, message)` on an empty world and on one holding a body; both must
// fail with the world (bodies, joints, couplings, parameters) and the model exactly as
// before, and give the same message, which is returned.
template <typename Load>
std::string loadError(Load&& load) {
  using namespace pfx;
  std::string messages[2];
  for (int withMarker = 0; withMarker < 2; ++withMarker) {
    PfxWorld world;
    EXPECT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    if (withMarker) addMarker(world);
    const PfxWorldParam before = world.getParam();
    PfxSceneModel model;
    model.name = "untouched";
    EXPECT_NE(load(world, model, &messages[withMarker]), PFX_OK);
    EXPECT_EQ(world.getNumRigidBodies(), PfxUInt32(withMarker));
    EXPECT_EQ(world.getNumJoints(), 0u);
    EXPECT_EQ(world.getNumJointCouplings(), 0u);
    EXPECT_EQ(world.getParam().gravity, before.gravity);
    EXPECT_EQ(world.getParam().timeStep, before.timeStep);
    EXPECT_EQ(model.name, "untouched");
    if (withMarker) {
      EXPECT_EQ(world.getRigidState(0).getPosition(), PfxVector3(1, 2, 3));
    }
  }
  EXPECT_EQ(messages[0], messages[1]);
  return messages[0];
}

}  // namespace pfx_test
