// Stiff and extreme scenes: mass ratios of 1:1000, tall towers for a minute, a large time
// step, fast spin, sizes from 1 cm to 100 m together, bullets against thin walls, a pile of
// 10,000 bodies and joint limits hit at speed. Each test asserts bounds and prints what it
// measured, so that a regression shows as a number before it shows as a failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"

using namespace pfx;

namespace {

constexpr PfxFloat kGravity = 9.80665f;

// Sleep off: these scenes measure what the solver does over time, which sleep would freeze.
PfxWorldParam worldParam(PfxFloat timeStep = 1.0f / 60.0f) {
  PfxWorldParam param;
  param.enableSleep = false;
  param.timeStep = timeStep;
  param.gravity = PfxVector3(0, -kGravity, 0);
  return param;
}

PfxUInt32 addBody(PfxWorld& world, const PfxShape& shape, const PfxVector3& position,
                  PfxFloat mass, const PfxVector3& velocity = PfxVector3::Zero(),
                  const PfxVector3& angularVelocity = PfxVector3::Zero()) {
  PfxBodyInit init;
  init.position = position;
  init.mass = mass;
  init.linearVelocity = velocity;
  init.angularVelocity = angularVelocity;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
  return id;
}

PfxUInt32 addGround(PfxWorld& world, PfxFloat halfSize = 50) {
  return addBody(world, pfxMakeShape(PfxBox(halfSize, 1, halfSize)), PfxVector3(0, -1, 0), 0);
}

// What every test checks over its whole run: finite states, the fastest body, the deepest
// contact and the widest joint gap seen after any step.
struct Extremes {
  bool finite = true;
  PfxFloat fastest = 0;
  PfxFloat fastestSpin = 0;
  PfxFloat deepest = 0;
  PfxFloat widestGap = 0;

  void observe(const PfxWorld& world) {
    for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
      const PfxRigidState& s = world.getRigidState(i);
      finite = finite && s.isValid();
      fastest = std::max(fastest, s.getLinearVelocity().norm());
      fastestSpin = std::max(fastestSpin, s.getAngularVelocity().norm());
    }
    deepest = std::max(deepest, world.getStats().maxPenetration);
    widestGap = std::max(widestGap, world.getStats().maxJointGap);
  }
};

Extremes run(PfxWorld& world, PfxFloat seconds) {
  Extremes seen;
  const int steps = static_cast<int>(std::lround(seconds / world.getParam().timeStep));
  for (int i = 0; i < steps && seen.finite; ++i) {
    EXPECT_EQ(world.step(), PFX_OK);
    seen.observe(world);
  }
  return seen;
}

PfxFloat horizontalDistance(const PfxVector3& a, const PfxVector3& b) {
  return std::hypot(a.x() - b.x(), a.z() - b.z());
}

}  // namespace

TEST(StiffExtreme, HeavyBoxOnLightBoxAtRatio1000) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam()), PFX_OK);
  addGround(world);
  const PfxUInt32 light = addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
                                  PfxVector3(0, 0.5f, 0), 1);
  const PfxUInt32 heavy = addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
                                  PfxVector3(0, 1.5f, 0), 1000);
  const Extremes seen = run(world, 10);
  const PfxFloat lightY = world.getRigidState(light).getPosition().y();
  const PfxFloat heavyY = world.getRigidState(heavy).getPosition().y();
  std::printf("1 kg box under 1000 kg: heights %.4f and %.4f m, deepest contact %.4f m\n", lightY,
              heavyY, seen.deepest);
  ASSERT_TRUE(seen.finite);
  EXPECT_NEAR(lightY, 0.5f, 0.03f);
  EXPECT_NEAR(heavyY, 1.5f, 0.05f);
  EXPECT_LT(seen.fastest, 1.0f);
}

// The heavy boxes on top, each ten times the one below it: the light bottom box carries
// 1110 kg, and with friction only iterated it slid out from under the others after 5 s.
TEST(StiffExtreme, FourBoxStackOf1To1000KgLightestAtTheBottomStandsForAMinute) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam()), PFX_OK);
  addGround(world);
  std::vector<PfxUInt32> boxes;
  PfxFloat mass = 1;
  for (int i = 0; i < 4; ++i, mass *= 10) {
    boxes.push_back(addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
                            PfxVector3(0, 0.5f + i, 0), mass));
  }
  const Extremes seen = run(world, 60);
  PfxFloat drift = 0, sunk = 0;
  for (int i = 0; i < 4; ++i) {
    const PfxVector3& p = world.getRigidState(boxes[i]).getPosition();
    drift = std::max(drift, horizontalDistance(p, PfxVector3::Zero()));
    sunk = std::max(sunk, PfxFloat(0.5f + i - p.y()));
  }
  std::printf("1, 10, 100, 1000 kg stack after 60 s: drift %.2e m, sunk %.2e m, deepest contact "
              "%.2e m, fastest %.2e m/s\n", drift, sunk, seen.deepest, seen.fastest);
  ASSERT_TRUE(seen.finite);
  // Solved at once with their friction, the faces hold to micrometres; a millimetre is
  // the margin for another platform's rounding.
  EXPECT_LT(drift, 0.001f);
  EXPECT_LT(sunk, 0.002f);
  EXPECT_LT(seen.deepest, 0.002f);
  EXPECT_LT(seen.fastest, 0.01f);
}

TEST(StiffExtreme, ThirtyBoxTowerStandsForAMinute) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam()), PFX_OK);
  addGround(world);
  std::vector<PfxUInt32> boxes;
  for (int i = 0; i < 30; ++i) {
    boxes.push_back(addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
                            PfxVector3(0, 0.5f + i, 0), 1));
  }
  const Extremes seen = run(world, 60);
  const PfxVector3& top = world.getRigidState(boxes.back()).getPosition();
  const PfxFloat drift = horizontalDistance(top, PfxVector3(0, 0, 0));
  std::printf("30-box tower after 60 s: top at height %.4f m (29.5 at start), drifted %.4f m\n",
              top.y(), drift);
  ASSERT_TRUE(seen.finite);
  EXPECT_GT(top.y(), 29.3f);
  EXPECT_LT(drift, 0.1f);
}

// 5 x 5 x 20 boxes of 0.4 m, touching, between four walls 0.56 m away, at 4 iterations:
// sweeps pass the weight down one box per sweep, and the columns are joined in loops (side
// faces, edges of diagonal neighbours) that the contacts' direct solve does not take.
// Without shock propagation the pile sank into itself (the top 0.19 m down within 1 s, 2 cm
// deep contacts, boxes at 1.1 m/s) and the warm start threw it back up. With it, before it
// held each box on the boxes under it, the outer columns slid outwards from the first step
// (5 cm in 1 s, 0.54 m by 3 s, 0.78 m by 5 s, up to the walls) and from 9 s the pile fell
// apart; 3 s is long enough to see that slide.
TEST(StiffExtreme, DeepPileAtFourIterationsStandsBetweenWalls) {
  PfxWorldParam param = worldParam();
  param.iteration = 4;
  param.enableShockPropagation = true;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  addGround(world);
  constexpr int kSide = 5, kLayers = 20;
  constexpr PfxFloat kHalf = 0.2f, kPileHalfWidth = kSide * kHalf, kRoom = 0.56f;
  for (int side = 0; side < 4; ++side) {
    const PfxFloat sign = side % 2 ? 1.0f : -1.0f;
    const PfxFloat offset = sign * (kPileHalfWidth + kRoom + 0.1f);
    const PfxFloat length = kPileHalfWidth + kRoom + 0.2f;
    if (side < 2) {
      addBody(world, pfxMakeShape(PfxBox(0.1f, 5, length)), PfxVector3(offset, 5, 0), 0);
    } else {
      addBody(world, pfxMakeShape(PfxBox(length, 5, 0.1f)), PfxVector3(0, 5, offset), 0);
    }
  }
  std::vector<PfxUInt32> boxes;
  std::vector<PfxVector3> built;
  for (int y = 0; y < kLayers; ++y) {
    for (int z = 0; z < kSide; ++z) {
      for (int x = 0; x < kSide; ++x) {
        PfxBodyInit init;
        init.position =
            PfxVector3((x - 2) * 2 * kHalf, kHalf + y * 2 * kHalf, (z - 2) * 2 * kHalf);
        init.mass = 1;
        init.friction = 0.6f;
        PfxUInt32 id = 0;
        ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(kHalf, kHalf, kHalf)), init, &id), PFX_OK);
        boxes.push_back(id);
        built.push_back(init.position);
      }
    }
  }
  const PfxFloat topStart = kHalf + (kLayers - 1) * 2 * kHalf;
  const std::size_t firstOfTop = boxes.size() - kSide * kSide;
  const int steps = 3 * 60, settled = 60;
  Extremes seen;
  PfxFloat lowestTop = topStart, widestSlide = 0, fastestSettled = 0;
  for (int i = 0; i < steps && seen.finite; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    seen.observe(world);
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const PfxRigidState& s = world.getRigidState(boxes[b]);
      widestSlide = std::max(widestSlide, horizontalDistance(s.getPosition(), built[b]));
      if (b >= firstOfTop) lowestTop = std::min(lowestTop, s.getPosition().y());
      if (i >= settled) fastestSettled = std::max(fastestSettled, s.getLinearVelocity().norm());
    }
  }
  std::printf("5 x 5 x 20 pile at 4 iterations, 3 s: top layer down by %.2e m, widest slide "
              "%.2e m, deepest contact %.2e m, fastest %.2e m/s, after 1 s %.2e m/s\n",
              topStart - lowestTop, widestSlide, seen.deepest, seen.fastest, fastestSettled);
  ASSERT_TRUE(seen.finite);
  EXPECT_GT(lowestTop, topStart - 0.005f);
  EXPECT_LT(widestSlide, 0.01f);
  EXPECT_LT(seen.deepest, 0.01f);
  EXPECT_LT(seen.fastest, 1.0f);
  EXPECT_LT(fastestSettled, 0.05f);
}

TEST(StiffExtreme, EverythingStaysBoundedAtDt1Over30) {
  // A pyramid, a chain with a 1:1000 payload and a ragdoll, all at twice the usual step.
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam(1.0f / 30.0f)), PFX_OK);
  addGround(world);
  for (int row = 0; row < 6; ++row) {
    for (int i = 0; i < 6 - row; ++i) {
      addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
              PfxVector3(-8 + i * 1.02f + row * 0.51f, 0.5f + row, 0), 1);
    }
  }
  const PfxUInt32 anchor = addBody(world, pfxMakeShape(PfxSphere(0.05f)), PfxVector3(5, 6, 0), 0);
  PfxUInt32 previous = anchor;
  for (int i = 0; i <= 10; ++i) {
    const bool payload = i == 10;
    const PfxUInt32 id =
        addBody(world, payload ? pfxMakeShape(PfxSphere(0.2f)) : pfxMakeShape(PfxCapsule(0.1f, 0.02f)),
                PfxVector3(5.1f + 0.2f * i, 6, 0), payload ? 1000 : 1);
    PfxBallJointInitParam joint;
    joint.anchorPoint = PfxVector3(5 + 0.2f * i, 6, 0);
    PfxJoint j;
    ASSERT_EQ(pfxInitializeBallJoint(j, world.getRigidState(previous), world.getRigidState(id), joint),
              PFX_OK);
    ASSERT_EQ(world.addJoint(j), PFX_OK);
    previous = id;
  }
  PfxRagdoll ragdoll;
  ASSERT_EQ(pfxAddRagdoll(world, PfxVector3(0, 3, 4), PfxQuat::Identity(), &ragdoll), PFX_OK);
  const Extremes seen = run(world, 10);
  std::printf("dt 1/30 for 10 s: fastest body %.2f m/s, deepest contact %.4f m, widest joint gap "
              "%.2e m\n", seen.fastest, seen.deepest, seen.widestGap);
  ASSERT_TRUE(seen.finite);
  // The chain's 2.2 m swing reaches sqrt(2 g h) ~ 6.6 m/s; a whip's tip may outrun that.
  EXPECT_LT(seen.fastest, 30.0f);
  // The deepest contact is a ragdoll's foot on landing (0.097 m before its contacts were
  // solved as its joint tree answers them).
  EXPECT_LT(seen.deepest, 0.05f);
  EXPECT_LT(seen.widestGap, 0.01f);
}

// The total energy of the dynamic bodies, the ground at height 0.
PfxFloat totalEnergy(const PfxWorld& world) {
  PfxFloat energy = 0;
  for (PfxUInt32 i = 0; i < world.getNumRigidBodies(); ++i) {
    const PfxRigidBody& body = world.getRigidBody(i);
    if (body.getMassInv() == 0) continue;
    const PfxRigidState& s = world.getRigidState(i);
    energy += body.getMass() * (PfxFloat(0.5) * s.getLinearVelocity().squaredNorm() +
                                kGravity * s.getPosition().y());
  }
  return energy;
}

TEST(StiffExtreme, RagdollLandsWithoutSinkingIntoTheGroundAtDt1Over30) {
  // The package's ragdoll dropped upright at dt 1/30: a 1 kg foot under 70 kg lands first.
  // Its contacts used to stop the foot with the foot's mass alone, the joint tree's solve
  // handed it the body's momentum back, and the joints' position correction then closed the
  // ankle by pressing the foot further in: 0.10 m deep.
  for (const PfxFloat height : {1.2f, 3.0f}) {
    PfxWorld world;
    ASSERT_EQ(world.initialize(worldParam(1.0f / 30.0f)), PFX_OK);
    addGround(world);
    PfxRagdoll ragdoll;
    ASSERT_EQ(pfxAddRagdoll(world, PfxVector3(0, height, 0), PfxQuat::Identity(), &ragdoll),
              PFX_OK);
    const PfxFloat startEnergy = totalEnergy(world);
    Extremes seen;
    PfxFloat mostEnergy = startEnergy, lastSecond = 0;
    const int steps = 8 * 30;
    for (int i = 0; i < steps && seen.finite; ++i) {
      ASSERT_EQ(world.step(), PFX_OK);
      seen.observe(world);
      mostEnergy = std::max(mostEnergy, totalEnergy(world));
      if (i >= steps - 30) {
        for (const PfxUInt32 b : ragdoll.bodies) {
          lastSecond = std::max(lastSecond, world.getRigidState(b).getLinearVelocity().norm());
        }
      }
    }
    std::printf("ragdoll dropped from %.1f m at dt 1/30: deepest contact %.4f m, energy gained "
                "%.3f J of %.0f J, widest joint gap %.2e m, fastest link in the last second "
                "%.2e m/s\n",
                height, seen.deepest, mostEnergy - startEnergy, startEnergy, seen.widestGap,
                lastSecond);
    ASSERT_TRUE(seen.finite);
    EXPECT_LT(seen.deepest, 0.03f);
    EXPECT_LT(mostEnergy - startEnergy, 0.01f * startEnergy);
    EXPECT_LT(seen.widestGap, 0.01f);
    EXPECT_LT(lastSecond, 0.05f);
  }
}

TEST(StiffExtreme, BodySpinningAt100RadPerSecondKeepsMomentumAndEnergy) {
  PfxWorldParam param = worldParam();
  param.gravity.setZero();
  param.measureConservation = true;
  // About each principal axis, and about a tilted axis that makes it tumble.
  const PfxVector3 spins[] = {PfxVector3(100, 0, 0), PfxVector3(0, 100, 0), PfxVector3(0, 0, 100),
                              PfxVector3(60, 60, 52.9f)};
  for (const PfxVector3& spin : spins) {
    PfxWorld world;
    ASSERT_EQ(world.initialize(param), PFX_OK);
    addBody(world, pfxMakeShape(PfxBox(0.5f, 0.25f, 0.125f)), PfxVector3::Zero(), 1,
            PfxVector3::Zero(), spin);
    const PfxConservedQuantities before = world.measureConservedQuantities();
    const Extremes seen = run(world, 10);
    const PfxConservedQuantities after = world.measureConservedQuantities();
    const double momentumDrift =
        (after.angularMomentum - before.angularMomentum).norm() / before.angularMomentum.norm();
    const double energyDrift = std::abs(after.energy - before.energy) / before.energy;
    std::printf("spin (%.0f, %.0f, %.0f) rad/s for 10 s: angular momentum drift %.2e, energy drift "
                "%.2e\n", spin.x(), spin.y(), spin.z(), momentumDrift, energyDrift);
    ASSERT_TRUE(seen.finite);
    EXPECT_LT(momentumDrift, 1e-3);
    EXPECT_LT(energyDrift, 1e-2);
    EXPECT_LT(seen.fastestSpin, 1.5f * spin.norm());
  }
}

TEST(StiffExtreme, BodiesFrom1CentimetreTo100MetresShareAScene) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam()), PFX_OK);
  addGround(world, 200);
  // A 100 m slab resting on the ground, a 1 m box and a 1 cm cube on the slab.
  const PfxUInt32 slab = addBody(world, pfxMakeShape(PfxBox(50, 0.5f, 50)), PfxVector3(0, 0.5f, 0),
                                 5000);
  const PfxUInt32 box = addBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)),
                                PfxVector3(10, 1.5f, 0), 1);
  const PfxUInt32 cube = addBody(world, pfxMakeShape(PfxBox(0.005f, 0.005f, 0.005f)),
                                 PfxVector3(-10, 1.005f, 3), 0.001f);
  const PfxUInt32 pebble = addBody(world, pfxMakeShape(PfxSphere(0.005f)),
                                   PfxVector3(20, 1.2f, -7), 0.0005f);
  const Extremes seen = run(world, 5);
  const PfxFloat slabY = world.getRigidState(slab).getPosition().y();
  const PfxFloat boxY = world.getRigidState(box).getPosition().y();
  const PfxFloat cubeY = world.getRigidState(cube).getPosition().y();
  const PfxFloat pebbleY = world.getRigidState(pebble).getPosition().y();
  std::printf("slab %.4f (0.5), box %.4f (1.5), 1 cm cube %.4f (1.005), pebble %.4f (1.005) m; "
              "cube speed %.2e m/s\n", slabY, boxY, cubeY, pebbleY,
              world.getRigidState(cube).getLinearVelocity().norm());
  ASSERT_TRUE(seen.finite);
  EXPECT_NEAR(slabY, 0.5f, 0.01f);
  EXPECT_NEAR(boxY, 1.5f, 0.01f);
  // The small ones rest on the slab's top, neither sunk through nor hopping on it.
  EXPECT_NEAR(cubeY, 1.005f, 0.004f);
  EXPECT_NEAR(pebbleY, 1.005f, 0.004f);
  EXPECT_LT(world.getRigidState(cube).getLinearVelocity().norm(), 0.01f);
  EXPECT_LT(world.getRigidState(pebble).getLinearVelocity().norm(), 0.01f);
}

TEST(StiffExtreme, BulletsStopAtA1CentimetreWallEvenAtDt1Over30) {
  for (PfxFloat timeStep : {1.0f / 60.0f, 1.0f / 30.0f}) {
    PfxWorldParam param = worldParam(timeStep);
    param.gravity.setZero();
    PfxWorld world;
    ASSERT_EQ(world.initialize(param), PFX_OK);
    addBody(world, pfxMakeShape(PfxBox(0.005f, 1, 1)), PfxVector3::Zero(), 0);
    std::vector<PfxUInt32> shots;
    for (PfxFloat offset : {0.0f, 0.29f, 0.73f}) {
      shots.push_back(addBody(world, pfxMakeShape(PfxSphere(0.01f)),
                              PfxVector3(-3 - offset, 0.3f * offset, 0.1f), 0.05f,
                              PfxVector3(100, 0, 0)));
      shots.push_back(addBody(world, pfxMakeShape(PfxBox(0.01f, 0.01f, 0.01f)),
                              PfxVector3(-3 - offset, -0.3f * offset, -0.2f), 0.05f,
                              PfxVector3(100, 0, 0)));
    }
    const Extremes seen = run(world, 1);
    PfxFloat furthest = -1e9f;
    for (PfxUInt32 id : shots) furthest = std::max(furthest, world.getRigidState(id).getPosition().x());
    std::printf("100 m/s at dt 1/%.0f: furthest shot at x = %.4f m (wall face at -0.005)\n",
                1 / timeStep, furthest);
    ASSERT_TRUE(seen.finite);
    EXPECT_LT(furthest, -0.005f);
  }
}

TEST(StiffExtreme, TenThousandBodiesPileUpWithoutExploding) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(worldParam()), PFX_OK);
  addGround(world);
  // A 10 x 10 m container, and a 20 x 20 x 25 block of spheres and boxes above it.
  const PfxFloat wall = 5.2f;
  for (int side = 0; side < 4; ++side) {
    const bool alongX = side < 2;
    const PfxFloat offset = side % 2 ? wall : -wall;
    addBody(world, pfxMakeShape(alongX ? PfxBox(0.2f, 6, wall) : PfxBox(wall, 6, 0.2f)),
            alongX ? PfxVector3(offset, 6, 0) : PfxVector3(0, 6, offset), 0);
  }
  const PfxUInt32 first = world.getNumRigidBodies();
  for (int i = 0; i < 10000; ++i) {
    const int x = i % 20, z = (i / 20) % 20, y = i / 400;
    const PfxVector3 position(-4.75f + 0.5f * x, 1 + 0.5f * y, -4.75f + 0.5f * z);
    const PfxShape shape = (i % 2) ? pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f))
                                   : pfxMakeShape(PfxSphere(0.2f));
    addBody(world, shape, position, 1, PfxVector3(0, -1, 0));
  }
  ASSERT_EQ(world.getNumRigidBodies(), first + 10000);
  const Extremes seen = run(world, 3);
  PfxFloat lowest = 1e9f, outside = -1e9f;
  for (PfxUInt32 id = first; id < world.getNumRigidBodies(); ++id) {
    const PfxVector3& p = world.getRigidState(id).getPosition();
    lowest = std::min(lowest, p.y());
    outside = std::max(outside, std::max(std::abs(p.x()), std::abs(p.z())) - wall);
  }
  std::printf("10,000 bodies after 3 s: fastest %.2f m/s, deepest contact %.4f m, lowest centre "
              "%.3f m, furthest past the walls %.3f m\n", seen.fastest, seen.deepest, lowest, outside);
  ASSERT_TRUE(seen.finite);
  // Falling 13 m gives 16 m/s; nothing may be flung much faster than that.
  EXPECT_LT(seen.fastest, 25.0f);
  EXPECT_GT(lowest, 0.15f);  // no 0.2 m body sinks more than 5 cm into the ground
  EXPECT_LT(outside, -0.15f);  // nothing pushes into the walls (inner faces at 5.0 m)
  // Deep piles are where the solver is weakest: the position correction reaches only a few
  // layers per step, so overlaps build up low in the 25 layers (0.085 m at the default 10
  // iterations, 0.42 m at 4).
  EXPECT_LT(seen.deepest, 0.15f);
}

TEST(StiffExtreme, JointLimitsHoldWhenHitAtSpeed) {
  PfxWorldParam param = worldParam();
  param.gravity.setZero();
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxUInt32 base = addBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), PfxVector3::Zero(), 0);
  // A 1 m arm on a hinge about Z limited to +-0.5 rad, swung at 30 rad/s into the limit
  // (15 m/s at its tip), and a slider limited to +-0.2 m hit at 10 m/s.
  const PfxUInt32 arm = addBody(world, pfxMakeShape(PfxBox(0.5f, 0.05f, 0.05f)),
                                PfxVector3(0.5f, 0, 0), 2, PfxVector3(0, 15, 0),
                                PfxVector3(0, 0, 30));
  PfxHingeJointInitParam hinge;
  hinge.axis = PfxVector3::UnitZ();
  hinge.lowerAngle = -0.5f;
  hinge.upperAngle = 0.5f;
  PfxJoint hingeJoint;
  ASSERT_EQ(pfxInitializeHingeJoint(hingeJoint, world.getRigidState(base), world.getRigidState(arm),
                                    hinge), PFX_OK);
  ASSERT_EQ(world.addJoint(hingeJoint), PFX_OK);
  const PfxUInt32 base2 = addBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)),
                                  PfxVector3(0, 5, 0), 0);
  const PfxUInt32 carriage = addBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)),
                                     PfxVector3(0, 5, 0), 1, PfxVector3(10, 0, 0));
  PfxSliderJointInitParam slider;
  slider.anchorPoint = PfxVector3(0, 5, 0);
  slider.direction = PfxVector3::UnitX();
  slider.lowerDistance = -0.2f;
  slider.upperDistance = 0.2f;
  PfxJoint sliderJoint;
  ASSERT_EQ(pfxInitializeSliderJoint(sliderJoint, world.getRigidState(base2),
                                     world.getRigidState(carriage), slider), PFX_OK);
  ASSERT_EQ(world.addJoint(sliderJoint), PFX_OK);

  PfxFloat worstHinge = 0, worstSlider = 0;
  const double energyBefore = world.measureConservedQuantities().energy;
  for (int step = 0; step < 300; ++step) {
    ASSERT_EQ(world.step(), PFX_OK);
    worstHinge = std::max(worstHinge, pfxGetJointLimitViolation(world.getJoint(0),
        world.getRigidState(base), world.getRigidState(arm)));
    worstSlider = std::max(worstSlider, pfxGetJointLimitViolation(world.getJoint(1),
        world.getRigidState(base2), world.getRigidState(carriage)));
  }
  const double energyAfter = world.measureConservedQuantities().energy;
  std::printf("limits hit at speed: hinge overshoot %.4f rad, slider overshoot %.4f m, energy "
              "%.1f J -> %.1f J\n", worstHinge, worstSlider, energyBefore, energyAfter);
  EXPECT_LT(worstHinge, 0.05f);
  EXPECT_LT(worstSlider, 0.01f);
  // Hitting a limit may lose energy but never gain it.
  EXPECT_LE(energyAfter, energyBefore * 1.001);
}
