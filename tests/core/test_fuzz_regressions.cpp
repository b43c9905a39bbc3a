// Defects the fuzz targets found (tests/fuzz/, README.md "Fuzzing"), each as the smallest
// sequence of calls that showed it, asserting the refusal or the behaviour that holds now.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

const PfxFloat kLargestFloat = std::numeric_limits<PfxFloat>::max();

PfxUInt32 addSphere(PfxWorld& world, const PfxVector3& position) {
  PfxBodyInit init;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.5))), init, &id), PFX_OK);
  return id;
}

bool sameState(const PfxRigidState& a, const PfxRigidState& b) {
  return a.getPosition() == b.getPosition() && a.getOrientation().coeffs() == b.getOrientation().coeffs() &&
         a.getLinearVelocity() == b.getLinearVelocity() &&
         a.getAngularVelocity() == b.getAngularVelocity();
}

}  // namespace

// fuzz_world_api: a body added with an angular velocity of 3.4e38 rad/s (finite, so it was
// accepted) turned NaN in its first step, and the integrator converted that NaN to an int
// (undefined behaviour). Velocities whose squared length overflows are refused now.
TEST(FuzzRegressions, VelocityWhoseSquareOverflowsIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));

  PfxBodyInit spinning;
  spinning.angularVelocity = PfxVector3(PfxFloat(3.14159), kLargestFloat, 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), spinning),
            PFX_ERR_INVALID_VALUE);
  PfxBodyInit fast;
  // A speed whose square overflows in either precision.
  fast.linearVelocity = PfxVector3(0, -2 * std::sqrt(kLargestFloat), 0);
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), fast),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);

  const PfxRigidState before = world.getRigidState(kept);
  PfxRigidState state = before;
  state.setAngularVelocity(PfxVector3(0, kLargestFloat, 0));
  EXPECT_EQ(world.setRigidState(kept, state), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(sameState(world.getRigidState(kept), before));

  // The fastest spin still accepted steps to finite states.
  state = before;
  state.setAngularVelocity(PfxVector3(0, 1e18f, 0));
  ASSERT_EQ(world.setRigidState(kept, state), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(pfxIsFinite(world.getRigidState(kept).getPosition()));
  EXPECT_TRUE(pfxIsFinite(world.getRigidState(kept).getOrientation()));
}

// fuzz_world_api: a world initialized with a time step of 3.4e38 s (finite, so it was
// accepted) made its bodies' positions and velocities infinite in the first step. A time
// step and gravity whose one-step velocity has an overflowing square are refused now, by
// initialize and setStepParam alike.
TEST(FuzzRegressions, TimeStepThatMakesGravityInfiniteIsRefusedWithNothingChanged) {
  PfxWorld world;
  PfxWorldParam param;
  param.timeStep = kLargestFloat;
  EXPECT_EQ(world.initialize(param), PFX_ERR_INVALID_VALUE);
  param.gravity = PfxVector3::Zero();
  EXPECT_EQ(world.initialize(param), PFX_OK);  // without gravity the step adds nothing

  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 id = addSphere(world, PfxVector3(0, 2, 0));
  EXPECT_EQ(world.setStepParam(kLargestFloat, 1, 10, PfxVector3(0, PfxFloat(-9.8), 0)),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getParam().timeStep, PfxWorldParam().timeStep);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(world.getRigidState(id).isValid());
}

// fuzz_world_file: a saved world whose box had the principal moments 0.0017, 0.031 and
// 1.4e-38 kg m^2 (positive, so it was read) gave the solver an inverse inertia of 7e37 and
// every body it touched turned NaN in the first step. A moment below the largest times the
// precision's epsilon, lost in rounding once the tensor turns, is refused now, by
// addRigidBody, setRigidBody and the file reader (which apply the same check).
TEST(FuzzRegressions, InertiaWithAMomentLostInRoundingIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 kept = addSphere(world, PfxVector3(0, 2, 0));

  PfxRigidBody body;
  body.reset();
  body.setMass(1);
  PfxMatrix3 inertia = PfxMatrix3::Zero();
  inertia.diagonal() = PfxVector3(0.00166667f, 0.0308333f, 1.41047e-38f);
  body.setInertia(inertia);
  EXPECT_FALSE(body.isValid());
  PfxRigidState state;
  state.reset();
  const PfxShape shape = pfxMakeShape(PfxBox(0.5f, 0.1f, 0.1f));
  EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 1u);
  const PfxMatrix3 before = world.getRigidBody(kept).getInertia();
  EXPECT_EQ(world.setRigidBody(kept, body), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getRigidBody(kept).getInertia(), before);

  // A thin rod, its smallest moment a millionth of the largest, is still a body.
  inertia.diagonal() = PfxVector3(1e-6f, 1, 1);
  body.setInertia(inertia);
  EXPECT_TRUE(body.isValid());
  EXPECT_EQ(world.addRigidBody(state, body, &shape, 1), PFX_OK);
}

// fuzz_world_file: a saved world whose shape sat at an offset of -3.4e38 m (finite, so it
// was read) had a bounding box that overflowed to infinity, and the loaded world's first
// step failed in the broad phase. A shape whose bounds are not finite is refused now by
// PfxShape::validate, which addRigidBody and the file reader apply.
TEST(FuzzRegressions, ShapeWhoseBoundsOverflowIsRefusedWithNothingChanged) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxShape shape = pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f));
  shape.setOffsetPosition(PfxVector3(-kLargestFloat, 0, 0));
  EXPECT_EQ(shape.validate(), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxAddBody(world, shape, PfxBodyInit()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.getNumRigidBodies(), 0u);

  shape.setOffsetPosition(PfxVector3(-1e6f, 0, 0));
  EXPECT_EQ(shape.validate(), PFX_OK);
}
