// Every combination of two motion types behaves as the two tables of seed chapter 10 say,
// and contact filters keep pairs out of the broad phase.
#include <gtest/gtest.h>

#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

const char* kNames[] = {"fixed", "active", "keyframe", "one-way", "trigger"};

bool isDynamic(PfxMotionType t) { return t == kPfxMotionTypeActive || t == kPfxMotionTypeOneWay; }

// What the seed's tables say for body `self` meeting body `other`.
bool expectCollide(PfxMotionType a, PfxMotionType b) {
  static const bool table[5][5] = {{0, 1, 0, 1, 1},
                                   {1, 1, 1, 1, 1},
                                   {0, 1, 0, 1, 1},
                                   {1, 1, 1, 0, 1},
                                   {1, 1, 1, 1, 0}};
  return table[a][b];
}
bool expectRespond(PfxMotionType a, PfxMotionType b) {
  static const bool table[5][5] = {{0, 1, 0, 1, 0},
                                   {1, 1, 1, 1, 0},
                                   {0, 1, 0, 1, 0},
                                   {1, 1, 1, 0, 0},
                                   {0, 0, 0, 0, 0}};
  return table[a][b];
}
// A one-way body receives but never gives: whoever faces it gets nothing.
bool expectReceives(PfxMotionType self, PfxMotionType other) {
  return isDynamic(self) && expectRespond(self, other) &&
         !(other == kPfxMotionTypeOneWay && self != kPfxMotionTypeOneWay);
}

}  // namespace

TEST(MotionTypes, EveryCombinationFollowsTheSeedTables) {
  for (int ta = 0; ta < kPfxMotionTypeCount; ++ta) {
    for (int tb = 0; tb < kPfxMotionTypeCount; ++tb) {
      const PfxMotionType a = static_cast<PfxMotionType>(ta);
      const PfxMotionType b = static_cast<PfxMotionType>(tb);
      PfxWorldParam param;
      param.gravity.setZero();
      PfxWorld world;
      ASSERT_EQ(world.initialize(param), PFX_OK);
      // Two boxes overlapping by 5 cm, moving toward each other at 1 m/s.
      PfxBodyInit init;
      init.motionType = a;
      init.position = PfxVector3(-0.475f, 0, 0);
      init.linearVelocity = PfxVector3(1, 0, 0);
      PfxUInt32 ia = 0, ib = 0;
      ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &ia), PFX_OK);
      init.motionType = b;
      init.position = PfxVector3(0.475f, 0, 0);
      init.linearVelocity = PfxVector3(-1, 0, 0);
      ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &ib), PFX_OK);
      if (a == kPfxMotionTypeKeyframe) world.setKeyframeTarget(ia, PfxVector3(-0.475f + 1.0f / 60, 0, 0), PfxQuat::Identity());

      ASSERT_EQ(world.step(), PFX_OK);
      const bool contacts = world.getStats().numContactPoints > 0;
      const std::string what = std::string(kNames[a]) + " vs " + kNames[b];
      EXPECT_EQ(contacts, expectCollide(a, b)) << what;

      const PfxVector3 va = world.getRigidState(ia).getLinearVelocity();
      const PfxVector3 vb = world.getRigidState(ib).getLinearVelocity();
      // Without a response a body keeps its velocity; with one it is pushed back.
      EXPECT_EQ(std::abs(va.x() - 1) > 0.1f, expectReceives(a, b)) << what << ": A v=" << va.x();
      EXPECT_EQ(std::abs(vb.x() + 1) > 0.1f, expectReceives(b, a)) << what << ": B v=" << vb.x();
      // Fixed and trigger bodies never move; keyframe bodies follow their own velocity.
      for (PfxUInt32 id : {ia, ib}) {
        const PfxRigidState& s = world.getRigidState(id);
        const PfxFloat start = id == ia ? -0.475f : 0.475f;
        const PfxFloat moved = s.getPosition().x() - start;
        if (s.getMotionType() == kPfxMotionTypeFixed || s.getMotionType() == kPfxMotionTypeTrigger) {
          EXPECT_EQ(moved, 0) << what;
        } else if (s.getMotionType() == kPfxMotionTypeKeyframe) {
          EXPECT_NEAR(std::abs(moved), 1.0f / 60, 1e-5f) << what;
        }
      }
    }
  }
}

TEST(MotionTypes, KeyframeTargetBecomesVelocityAndPushesOthers) {
  PfxWorldParam param;
  param.gravity.setZero();
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit init;
  init.motionType = kPfxMotionTypeKeyframe;
  PfxUInt32 paddle = 0, ball = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &paddle), PFX_OK);
  init.motionType = kPfxMotionTypeActive;
  init.position = PfxVector3(1.2f, 0, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.3f)), init, &ball), PFX_OK);
  // The application feeds a pose each frame: 2 m/s along X and a quarter turn per second.
  const PfxFloat dt = param.timeStep;
  for (int i = 1; i <= 60; ++i) {
    const PfxQuat q(Eigen::AngleAxis<PfxFloat>(0.5f * PFX_PI * i * dt, PfxVector3::UnitY()));
    ASSERT_EQ(world.setKeyframeTarget(paddle, PfxVector3(2 * i * dt, 0, 0), q), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    EXPECT_NEAR(world.getRigidState(paddle).getLinearVelocity().x(), 2, 1e-3f);
    EXPECT_NEAR(world.getRigidState(paddle).getAngularVelocity().y(), 0.5f * PFX_PI, 1e-3f);
  }
  EXPECT_NEAR(world.getRigidState(paddle).getPosition().x(), 2, 1e-3f);
  // The ball was in the way and got pushed ahead of the paddle.
  EXPECT_GT(world.getRigidState(ball).getPosition().x(), 2.5f);
  EXPECT_GT(world.getRigidState(ball).getLinearVelocity().x(), 1.9f);
}

TEST(MotionTypes, ContactFiltersExcludePairs) {
  PfxWorldParam param;
  param.gravity.setZero();
  for (int matching = 0; matching < 2; ++matching) {
    PfxWorld world;
    ASSERT_EQ(world.initialize(param), PFX_OK);
    PfxShape box = pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f));
    PfxBodyInit init;
    PfxUInt32 ia = 0, ib = 0;
    ASSERT_EQ(pfxAddBody(world, box, init, &ia), PFX_OK);
    init.position = PfxVector3(0.9f, 0, 0);
    ASSERT_EQ(pfxAddBody(world, box, init, &ib), PFX_OK);
    PfxRigidState a = world.getRigidState(ia);
    PfxRigidState b = world.getRigidState(ib);
    // (SelfA & TargetB) && (TargetA & SelfB)
    a.setContactFilterSelf(0x1);
    a.setContactFilterTarget(0x2);
    b.setContactFilterSelf(matching ? 0x2 : 0x4);
    b.setContactFilterTarget(0x1);
    ASSERT_EQ(world.setRigidState(ia, a), PFX_OK);
    ASSERT_EQ(world.setRigidState(ib, b), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    EXPECT_EQ(world.getStats().numPairs, matching ? 1u : 0u);
  }
}
