// PfxWorld's sleep (seed 3_sleep): still islands fall asleep whole and cost nothing, every
// waking cause wakes exactly the islands it should, nothing stays asleep when its support
// goes, a settled pile sleeps soon after it comes to rest, and sleeping and waking allocate
// nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx_allocation_counter.h"
#include "pfx_box_pile.h"
#include "pfx_large_mesh_test_util.h"

using namespace pfx;

namespace {

constexpr PfxFloat kHalf = 0.25f;

PfxUInt32 addBox(PfxWorld& world, const PfxVector3& position,
                 PfxMotionType type = kPfxMotionTypeActive, const PfxVector3& half =
                                                                PfxVector3::Constant(kHalf)) {
  PfxBodyInit init;
  init.position = position;
  init.motionType = type;
  init.mass = type == kPfxMotionTypeFixed ? 0 : 1;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(half.x(), half.y(), half.z())), init, &id), PFX_OK);
  return id;
}

PfxUInt32 addGround(PfxWorld& world) {
  return addBox(world, PfxVector3(0, -0.5f, 0), kPfxMotionTypeFixed, PfxVector3(20, 0.5f, 20));
}

// A column of boxes resting on a surface at height `base`.
std::vector<PfxUInt32> addStack(PfxWorld& world, PfxFloat x, PfxFloat base, int count,
                                PfxFloat z = 0) {
  std::vector<PfxUInt32> ids;
  for (int i = 0; i < count; ++i) {
    ids.push_back(addBox(world, PfxVector3(x, base + kHalf + 2 * kHalf * i, z)));
  }
  return ids;
}

bool allAsleep(const PfxWorld& world, const std::vector<PfxUInt32>& ids) {
  return std::all_of(ids.begin(), ids.end(),
                     [&](PfxUInt32 id) { return world.getRigidState(id).isAsleep(); });
}

bool allAwake(const PfxWorld& world, const std::vector<PfxUInt32>& ids) {
  return std::all_of(ids.begin(), ids.end(),
                     [&](PfxUInt32 id) { return world.getRigidState(id).isAwake(); });
}

bool everythingAsleep(const PfxWorld& world) { return world.getStats().numAwakeBodies == 0; }

// Steps until `done` holds, at most `maxSteps`; whether it came to hold.
template <typename Done>
bool stepUntil(PfxWorld& world, Done done, int maxSteps) {
  for (int i = 0; i < maxSteps; ++i) {
    EXPECT_EQ(world.step(), PFX_OK);
    if (done()) return true;
  }
  return false;
}

// Two stacks of three boxes far apart on one ground, both asleep.
struct TwoStacks {
  PfxWorld world;
  PfxUInt32 ground = 0;
  std::vector<PfxUInt32> a, b;

  explicit TwoStacks(PfxPipelineType pipeline = kPfxPipelineStable) {
    PfxWorldParam param;
    param.pipeline = pipeline;
    EXPECT_EQ(world.initialize(param), PFX_OK);
    ground = addGround(world);
    a = addStack(world, -3, 0, 3);
    b = addStack(world, 3, 0, 3);
  }
  void settle() {
    ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 240));
    ASSERT_TRUE(allAsleep(world, a));
    ASSERT_TRUE(allAsleep(world, b));
  }
};

// Whether the last step solved a pair of these two bodies with points (the awake pairs come
// first among the world's pairs), and no pair appears twice.
bool solvedTogether(const PfxWorld& world, PfxUInt32 idA, PfxUInt32 idB) {
  const PfxUInt64 key = pfxCreatePairKey(std::min(idA, idB), std::max(idA, idB));
  for (PfxUInt32 i = 0; i < world.getStats().numPairs; ++i) {
    const PfxConstraintPair& pair = world.getContactPair(i);
    if (pair.key == key) return world.getContactManifold(pair).getNumContacts() > 0;
  }
  return false;
}

bool pairsAreUnique(const PfxWorld& world) {
  std::vector<PfxUInt64> keys;
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    keys.push_back(world.getContactPair(i).key);
  }
  std::sort(keys.begin(), keys.end());
  return std::adjacent_find(keys.begin(), keys.end()) == keys.end();
}

std::vector<unsigned char> stateBytes(const PfxWorld& world) {
  const auto* begin = reinterpret_cast<const unsigned char*>(world.getRigidStates());
  return std::vector<unsigned char>(begin, begin + world.getNumRigidBodies() * sizeof(PfxRigidState));
}

}  // namespace

TEST(Sleep, StillIslandsFallAsleepWholeAndCostNothing) {
  for (PfxPipelineType pipeline : {kPfxPipelineSimple, kPfxPipelineStable}) {
    TwoStacks s(pipeline);
    s.settle();
    const PfxWorldStats& stats = s.world.getStats();
    EXPECT_EQ(stats.numIslands, 2u);
    EXPECT_EQ(stats.numSleepingIslands, 2u);
    EXPECT_EQ(stats.numSleepingBodies, 6u);
    EXPECT_EQ(stats.numAwakeBodies, 0u);
    const PfxIsland& island = s.world.getIsland();
    EXPECT_NE(pfxGetIslandId(island, s.a[0]), pfxGetIslandId(island, s.b[0]));
    EXPECT_EQ(pfxGetIslandId(island, s.ground), PFX_ISLAND_NONE);
    for (PfxUInt32 id : s.a) {
      EXPECT_EQ(s.world.getRigidState(id).getLinearVelocity(), PfxVector3::Zero());
      EXPECT_EQ(s.world.getRigidState(id).getAngularVelocity(), PfxVector3::Zero());
      EXPECT_NEAR(s.world.getRigidState(id).getPosition().x(), -3, 1e-3);
    }
    // Asleep, nothing is detected or solved, the pairs wait aside with their points, and
    // nothing moves.
    const std::vector<unsigned char> before = stateBytes(s.world);
    for (int i = 0; i < 30; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
    EXPECT_EQ(stats.numPairs, 0u);
    EXPECT_EQ(stats.numSleepingPairs, 6u);  // each box with the one below, or the ground
    EXPECT_EQ(s.world.getNumContactPairs(), 6u);
    // The contacts still count in the statistics.
    PfxUInt32 points = 0;
    for (PfxUInt32 i = 0; i < s.world.getNumContactPairs(); ++i) {
      const PfxConstraintPair& pair = s.world.getContactPair(i);
      EXPECT_GT(s.world.getContactManifold(pair).getNumContacts(), 0u);
      points += s.world.getContactManifold(pair).getNumContacts();
    }
    EXPECT_EQ(stats.numContactPairs, 6u);
    EXPECT_EQ(stats.numContactPoints, points);
    EXPECT_EQ(stateBytes(s.world), before) << "pipeline " << int(pipeline);
  }
}

// A sleeping body costs the broad phase nothing: its proxy is built and sorted in the step
// after it fell asleep, then kept until it wakes; the ground's is built every step.
TEST(Sleep, ASleepingPilesProxiesAreKeptNotUpdated) {
  TwoStacks s;
  s.settle();
  const PfxWorldStats& stats = s.world.getStats();
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 7u);  // the ground, and the six boxes set aside
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(s.world.step(), PFX_OK);
    EXPECT_EQ(stats.numProxiesUpdated, 1u);
  }
  // A box dropped on stack a: its own proxy every step, until it wakes the stack, which
  // then sleeps again with it.
  PfxBodyInit init;
  init.position = PfxVector3(-3, 2.5f, 0);
  PfxUInt32 dropped = 0;
  ASSERT_EQ(pfxAddBody(s.world, pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f)), init, &dropped), PFX_OK);
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 2u + 6u);  // the sleeping set is rebuilt once
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 2u);
  ASSERT_TRUE(stepUntil(s.world, [&] { return s.world.getRigidState(s.a[0]).isAwake(); }, 120));
  EXPECT_TRUE(allAwake(s.world, s.a));
  EXPECT_TRUE(allAsleep(s.world, s.b));
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 1u + 4u + 3u);  // awake: the ground, stack a, the box
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 1u + 4u);
  ASSERT_TRUE(stepUntil(s.world, [&] { return everythingAsleep(s.world); }, 600));
  ASSERT_EQ(s.world.step(), PFX_OK);
  ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_EQ(stats.numProxiesUpdated, 1u);
  EXPECT_GT(s.world.getRigidState(dropped).getPosition().y(), 1.5f);
}

// Sleeping contacts are contacts, and sleeping bodies are in the way of rays: whoever lists
// the world's contacts (getContactPair) or casts rays gets the same answers from a sleeping
// pile as from an awake one, and neither query wakes it.
TEST(Sleep, ASleepingPilesContactsAreListedAndRaysStillHitIt) {
  TwoStacks s;
  ASSERT_NO_FATAL_FAILURE(s.settle());
  for (int i = 0; i < 30; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
  ASSERT_TRUE(everythingAsleep(s.world));
  ASSERT_EQ(s.world.getStats().numPairs, 0u) << "asleep, no pair is worked on";

  // Each box rests on the one below or on the ground: its pair is listed with its points,
  // touching, pushing up, and counted in the statistics.
  const auto listed = [&](PfxUInt32 below, PfxUInt32 above) -> const PfxContactManifold* {
    const PfxUInt64 key = pfxCreatePairKey(std::min(below, above), std::max(below, above));
    for (PfxUInt32 i = 0; i < s.world.getNumContactPairs(); ++i) {
      const PfxConstraintPair& pair = s.world.getContactPair(i);
      if (pair.key == key) return &s.world.getContactManifold(pair);
    }
    return nullptr;
  };
  PfxUInt32 points = 0;
  for (const std::vector<PfxUInt32>* stack : {&s.a, &s.b}) {
    for (std::size_t level = 0; level < stack->size(); ++level) {
      const PfxUInt32 below = level == 0 ? s.ground : (*stack)[level - 1];
      const PfxContactManifold* manifold = listed(below, (*stack)[level]);
      ASSERT_NE(manifold, nullptr) << "box " << (*stack)[level] << " on " << below;
      ASSERT_GE(manifold->getNumContacts(), 3u);
      points += manifold->getNumContacts();
      for (PfxUInt32 c = 0; c < manifold->getNumContacts(); ++c) {
        const PfxContactPoint& point = manifold->getContactPoint(c);
        EXPECT_LT(point.m_distance, s.world.getParam().contactMargin);
        EXPECT_GT(std::abs(point.getNormal().y()), 0.99f);
        EXPECT_GE(point.m_constraintRow[0].m_accumImpulse, 0);
      }
    }
  }
  EXPECT_EQ(s.world.getStats().numContactPoints, points);

  // Rays down onto each stack meet its top box, sideways ones its middle box, singly and in a
  // batch large enough to be cast in Morton order.
  const auto rayDown = [](PfxFloat x, PfxFloat z) {
    PfxRayInput ray;
    ray.reset();
    ray.m_startPosition = PfxVector3(x, 5, z);
    ray.m_direction = PfxVector3(0, -10, 0);
    return ray;
  };
  PfxRayOutput hit;
  for (const std::vector<PfxUInt32>* stack : {&s.a, &s.b}) {
    const PfxVector3 top = s.world.getRigidState(stack->back()).getPosition();
    ASSERT_EQ(s.world.castRay(rayDown(top.x(), top.z()), hit), PFX_OK);
    ASSERT_TRUE(hit.m_contactFlag);
    EXPECT_EQ(hit.m_objectId, stack->back());
    EXPECT_NEAR(hit.m_contactPoint.y(), top.y() + kHalf, 1e-3f);
    PfxRayInput side;
    side.reset();
    const PfxVector3 middle = s.world.getRigidState((*stack)[1]).getPosition();
    side.m_startPosition = middle + PfxVector3(0, 0, 5);
    side.m_direction = PfxVector3(0, 0, -10);
    ASSERT_EQ(s.world.castRay(side, hit), PFX_OK);
    ASSERT_TRUE(hit.m_contactFlag);
    EXPECT_EQ(hit.m_objectId, (*stack)[1]);
  }
  std::vector<PfxRayInput> rays;
  for (int i = 0; i < 100; ++i) {
    const std::vector<PfxUInt32>& stack = i % 2 ? s.b : s.a;
    const PfxVector3 top = s.world.getRigidState(stack.back()).getPosition();
    rays.push_back(rayDown(top.x() + 0.2f * (i % 10 - 4.5f) / 4.5f, top.z() + 0.01f * (i / 10)));
  }
  std::vector<PfxRayOutput> hits(rays.size());
  ASSERT_EQ(s.world.castRays(rays.data(), hits.data(), PfxUInt32(rays.size())), PFX_OK);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(hits[i].m_contactFlag) << "ray " << i;
    EXPECT_EQ(hits[i].m_objectId, (i % 2 ? s.b : s.a).back()) << "ray " << i;
  }

  // Listing and casting woke nothing, and the next steps keep the same contacts.
  for (int i = 0; i < 10; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_TRUE(everythingAsleep(s.world));
  EXPECT_EQ(s.world.getStats().numContactPoints, points);
}

TEST(Sleep, OffKeepsEverythingAwakeAndIslandsAreStillReported) {
  PfxWorldParam param;
  param.enableSleep = false;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  addGround(world);
  const std::vector<PfxUInt32> stack = addStack(world, 0, 0, 3);
  for (int i = 0; i < 120; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(allAwake(world, stack));
  EXPECT_EQ(world.getStats().numIslands, 1u);
  EXPECT_EQ(world.getStats().numAwakeBodies, 3u);
  EXPECT_GT(world.getStats().numContactPoints, 0u);
}

TEST(Sleep, ParametersAreCheckedAndABadOneChangesNothing) {
  PfxWorld world;
  PfxWorldParam good;
  good.sleepTime = 2;
  ASSERT_EQ(world.initialize(good), PFX_OK);
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  const PfxFloat inf = std::numeric_limits<PfxFloat>::infinity();
  const auto rejects = [&](PfxWorldParam p) {
    EXPECT_EQ(world.initialize(p), PFX_ERR_INVALID_VALUE);
    EXPECT_EQ(world.getParam().sleepTime, 2);
  };
  PfxWorldParam p = good;
  p.sleepLinearVelocity = -0.1f;
  rejects(p);
  p = good;
  p.sleepLinearVelocity = nan;
  rejects(p);
  p = good;
  p.sleepAngularVelocity = inf;
  rejects(p);
  p = good;
  p.sleepTime = -1;
  rejects(p);
  p = good;
  p.sleepTime = nan;
  rejects(p);
  p = good;
  p.sleepTime = 2000;  // 120,000 steps: more than a body's sleep count holds
  rejects(p);
}

TEST(Sleep, KeyframeAndOneWayBodiesSleepAndAKeyframeKeepsItsMotion) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addGround(world);
  const PfxUInt32 oneWay = addBox(world, PfxVector3(-2, kHalf, 0), kPfxMotionTypeOneWay);
  const PfxUInt32 still = addBox(world, PfxVector3(0, 3, 0), kPfxMotionTypeKeyframe);
  const PfxUInt32 moving = addBox(world, PfxVector3(2, 3, 0), kPfxMotionTypeKeyframe);
  PfxRigidState slow = world.getRigidState(moving);
  slow.setLinearVelocity(PfxVector3(0, 0, 0.01f));  // far below the sleep threshold
  ASSERT_EQ(world.setRigidState(moving, slow), PFX_OK);
  ASSERT_TRUE(stepUntil(
      world,
      [&] { return world.getRigidState(oneWay).isAsleep() && world.getRigidState(still).isAsleep(); },
      120));
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_TRUE(world.getRigidState(moving).isAwake());
  EXPECT_GT(world.getRigidState(moving).getPosition().z(), 0.015f);
  // Held at its pose, a keyframe body stays asleep; moved, it wakes.
  ASSERT_EQ(world.setKeyframeTarget(still, PfxVector3(0, 3, 0), PfxQuat::Identity()), PFX_OK);
  EXPECT_TRUE(world.getRigidState(still).isAsleep());
  ASSERT_EQ(world.setKeyframeTarget(still, PfxVector3(0, 3.1f, 0), PfxQuat::Identity()), PFX_OK);
  EXPECT_TRUE(world.getRigidState(still).isAwake());
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getRigidState(still).getPosition().y(), 3.1f, 1e-5);
}

TEST(Sleep, AThrownBodyWakesTheIslandItHitsInTheStepItTouches) {
  for (PfxPipelineType pipeline : {kPfxPipelineSimple, kPfxPipelineStable}) {
    TwoStacks s(pipeline);
    s.settle();
    PfxBodyInit init;
    init.position = PfxVector3(-3, 3, 0);
    init.linearVelocity = PfxVector3(0, -6, 0);
    PfxUInt32 thrown = 0;
    ASSERT_EQ(pfxAddBody(s.world, pfxMakeShape(PfxBox(0.2f, 0.2f, 0.2f)), init, &thrown), PFX_OK);
    const PfxUInt32 top = s.a.back();
    bool touched = false;
    for (int i = 0; i < 60 && !touched; ++i) {
      ASSERT_EQ(s.world.step(), PFX_OK);
      EXPECT_TRUE(allAsleep(s.world, s.b));
      for (PfxUInt32 p = 0; p < s.world.getNumContactPairs(); ++p) {
        const PfxConstraintPair& pair = s.world.getContactPair(p);
        const bool thrownOnTop = pfxGetObjectIdA(pair) == top && pfxGetObjectIdB(pair) == thrown;
        touched = touched || (thrownOnTop && s.world.getContactManifold(pair).getNumContacts() > 0);
      }
      EXPECT_TRUE(pairsAreUnique(s.world));
      // Woken no later than the step in which the box first touches it, and as a whole,
      // with its own contacts back in the same step: it did not drop through its support.
      if (touched) {
        EXPECT_TRUE(allAwake(s.world, s.a)) << "pipeline " << int(pipeline);
        EXPECT_TRUE(solvedTogether(s.world, s.ground, s.a[0]));
        EXPECT_TRUE(solvedTogether(s.world, s.a[0], s.a[1]));
        EXPECT_NEAR(s.world.getRigidState(s.a[0]).getPosition().y(), kHalf, 0.01f);
      }
    }
    ASSERT_TRUE(touched);
    // The hit was felt: the stack gave way a little, it did not stand frozen.
    PfxFloat fastest = s.world.getRigidState(top).getLinearVelocity().norm();
    for (int i = 0; i < 10; ++i) {
      ASSERT_EQ(s.world.step(), PFX_OK);
      fastest = std::max(fastest, s.world.getRigidState(top).getLinearVelocity().norm());
    }
    EXPECT_GT(fastest, 0.01f);
    // Then everything settles and sleeps again, the thrown box on top.
    ASSERT_TRUE(stepUntil(s.world, [&] { return everythingAsleep(s.world); }, 600));
    EXPECT_GT(s.world.getRigidState(thrown).getPosition().y(), 1.5f);
  }
}

TEST(Sleep, AMovingKeyframeWakesWhatItRunsInto) {
  TwoStacks s;
  const PfxUInt32 pusher = addBox(s.world, PfxVector3(-7, 0.3f, 0), kPfxMotionTypeKeyframe);
  PfxRigidState moving = s.world.getRigidState(pusher);
  moving.setLinearVelocity(PfxVector3(1, 0, 0));
  ASSERT_EQ(s.world.setRigidState(pusher, moving), PFX_OK);
  ASSERT_TRUE(stepUntil(s.world, [&] { return allAsleep(s.world, s.a) && allAsleep(s.world, s.b); },
                        120));
  ASSERT_LT(s.world.getRigidState(pusher).getPosition().x(), -4);
  bool woke = false;
  for (int i = 0; i < 240 && !woke; ++i) {
    ASSERT_EQ(s.world.step(), PFX_OK);
    woke = allAwake(s.world, s.a);
  }
  EXPECT_TRUE(woke);
  EXPECT_TRUE(allAsleep(s.world, s.b));
  // Pushed, not passed through.
  for (int i = 0; i < 30; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_GT(s.world.getRigidState(s.a[0]).getPosition().x(),
            s.world.getRigidState(pusher).getPosition().x() + 0.4f);
}

TEST(Sleep, ApplicationChangesWakeExactlyTheChangedIsland) {
  TwoStacks s;
  s.settle();
  const auto expectOnlyAWoke = [&](const char* what) {
    EXPECT_TRUE(allAwake(s.world, s.a)) << what;
    EXPECT_TRUE(allAsleep(s.world, s.b)) << what;
    ASSERT_EQ(s.world.step(), PFX_OK);
    EXPECT_TRUE(allAsleep(s.world, s.b)) << what;
    ASSERT_TRUE(stepUntil(s.world, [&] { return everythingAsleep(s.world); }, 240)) << what;
  };
  // A zero force wakes nothing.
  ASSERT_EQ(s.world.applyForce(s.a[1], PfxVector3::Zero(), PfxVector3::Zero()), PFX_OK);
  EXPECT_TRUE(allAsleep(s.world, s.a));
  ASSERT_EQ(s.world.applyForce(s.a[1], PfxVector3(0, 0, 1), PfxVector3::Zero()), PFX_OK);
  expectOnlyAWoke("applyForce");
  ASSERT_EQ(s.world.applyForce(s.a[1], PfxVector3::Zero(), PfxVector3(0, 0.1f, 0)), PFX_OK);
  expectOnlyAWoke("applyForce torque");
  const PfxUInt32 numPairs = s.world.getNumContactPairs();
  ASSERT_EQ(s.world.setRigidState(s.a[2], s.world.getRigidState(s.a[2])), PFX_OK);
  EXPECT_EQ(s.world.getNumContactPairs(), numPairs);
  EXPECT_TRUE(pairsAreUnique(s.world));
  expectOnlyAWoke("setRigidState");
  ASSERT_EQ(s.world.setRigidBody(s.a[0], s.world.getRigidBody(s.a[0])), PFX_OK);
  expectOnlyAWoke("setRigidBody");
  // A rejected call wakes nothing.
  PfxRigidState bad = s.world.getRigidState(s.a[2]);
  bad.setPosition(PfxVector3(std::numeric_limits<PfxFloat>::quiet_NaN(), 0, 0));
  EXPECT_EQ(s.world.setRigidState(s.a[2], bad), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(s.world.applyForce(s.a[2], PfxVector3(std::numeric_limits<PfxFloat>::infinity(), 0, 0),
                               PfxVector3::Zero()),
            PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(allAsleep(s.world, s.a));
}

TEST(Sleep, JointAndCouplingChangesWakeTheirIslands) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 ground = addGround(world);
  const std::vector<PfxUInt32> stack = addStack(world, -3, 0, 2);
  // Two pendulums hanging from a fixed beam, their hinges coupled: linked only through the
  // coupling, they are one island.
  const PfxUInt32 beam = addBox(world, PfxVector3(3, 3, 0), kPfxMotionTypeFixed,
                                PfxVector3(1, 0.1f, 0.1f));
  const PfxUInt32 bobs[2] = {addBox(world, PfxVector3(2.5f, 2, 0)), addBox(world, PfxVector3(3.5f, 2, 0))};
  PfxUInt32 hinges[2];
  for (int i = 0; i < 2; ++i) {
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = PfxVector3(2.5f + i, 2.9f, 0);
    PfxJoint joint;
    ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(beam),
                                      world.getRigidState(bobs[i]), hinge),
              PFX_OK);
    ASSERT_EQ(world.addJoint(joint, &hinges[i]), PFX_OK);
  }
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = hinges[0];
  coupling.m_followerJointId = hinges[1];
  coupling.m_leaderAxis = coupling.m_followerAxis = kPfxJointAxisTwist;
  PfxUInt32 couplingId = 0;
  ASSERT_EQ(world.addJointCoupling(coupling, &couplingId), PFX_OK);
  const std::vector<PfxUInt32> pendulums(bobs, bobs + 2);
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
  EXPECT_EQ(pfxGetIslandId(world.getIsland(), bobs[0]), pfxGetIslandId(world.getIsland(), bobs[1]));
  EXPECT_EQ(world.getStats().numSleepingIslands, 2u);

  ASSERT_EQ(world.setJoint(hinges[1], world.getJoint(hinges[1])), PFX_OK);
  EXPECT_TRUE(allAwake(world, pendulums));
  EXPECT_TRUE(allAsleep(world, stack));
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));

  ASSERT_EQ(world.setJointCoupling(couplingId, world.getJointCoupling(couplingId)), PFX_OK);
  EXPECT_TRUE(allAwake(world, pendulums));
  EXPECT_TRUE(allAsleep(world, stack));
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));

  // A new joint between the stack's top and a pendulum wakes both islands.
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(0, 2, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(stack[1]),
                                   world.getRigidState(bobs[0]), ball),
            PFX_OK);
  joint.m_active = 0;  // wakes them, but holds nothing
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  EXPECT_TRUE(allAwake(world, stack));
  EXPECT_TRUE(allAwake(world, pendulums));
  EXPECT_EQ(pfxGetIslandId(world.getIsland(), ground), PFX_ISLAND_NONE);
}

TEST(Sleep, AKeyframeThatMovesWakesWhatRestsOnIt) {
  TwoStacks s;
  const PfxUInt32 platform = addBox(s.world, PfxVector3(0, 1, 0), kPfxMotionTypeKeyframe,
                                    PfxVector3(0.6f, 0.1f, 0.6f));
  const std::vector<PfxUInt32> carried = addStack(s.world, 0, 1.1f, 2);
  s.settle();
  ASSERT_TRUE(s.world.getRigidState(platform).isAsleep());
  // Lowered by 5 cm over the next step: the boxes on it wake and follow it down.
  ASSERT_EQ(s.world.setKeyframeTarget(platform, PfxVector3(0, 0.95f, 0), PfxQuat::Identity()),
            PFX_OK);
  EXPECT_TRUE(allAwake(s.world, carried));
  EXPECT_TRUE(allAsleep(s.world, s.a));
  EXPECT_TRUE(allAsleep(s.world, s.b));
  ASSERT_EQ(s.world.step(), PFX_OK);
  ASSERT_EQ(s.world.setKeyframeTarget(platform, PfxVector3(0, 0.95f, 0), PfxQuat::Identity()),
            PFX_OK);  // and stops there
  for (int i = 0; i < 60; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_NEAR(s.world.getRigidState(platform).getPosition().y(), 0.95f, 1e-5);
  EXPECT_NEAR(s.world.getRigidState(carried[0]).getPosition().y(), 0.95f + 0.1f + kHalf, 0.01f);
  EXPECT_TRUE(allAsleep(s.world, s.a));
}

TEST(Sleep, ADeformedMeshWakesTheIslandsOnIt) {
  const pfx_test::MeshSource grid = pfx_test::makeFlatGrid(8, PfxFloat(0.5));
  pfx_test::MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_BVH, PfxFloat(0.3))),
            PFX_OK);
  TwoStacks s;
  // The mesh floor lies 2 m up, 6 m away from both stacks, carrying a stack of its own.
  PfxShape meshShape;
  meshShape.reset();
  meshShape.setLargeTriMesh(&owner.mesh);
  PfxBodyInit init;
  init.mass = 0;
  init.position = PfxVector3(0, 2, 6);
  PfxUInt32 floor = 0;
  ASSERT_EQ(pfxAddBody(s.world, &meshShape, 1, init, &floor), PFX_OK);
  const std::vector<PfxUInt32> onMesh = addStack(s.world, 0, 2, 2, 6);
  s.settle();
  ASSERT_TRUE(allAsleep(s.world, onMesh));
  std::vector<PfxFloat> lifted = grid.vertices;
  for (std::size_t v = 1; v < lifted.size(); v += 3) lifted[v] += PfxFloat(0.05);
  ASSERT_EQ(s.world.updateLargeTriMesh(floor, owner.mesh, lifted.data(), grid.numVertices()),
            PFX_OK);
  EXPECT_TRUE(allAwake(s.world, onMesh));
  EXPECT_TRUE(allAsleep(s.world, s.a));
  EXPECT_TRUE(allAsleep(s.world, s.b));
  for (int i = 0; i < 30; ++i) ASSERT_EQ(s.world.step(), PFX_OK);
  EXPECT_NEAR(s.world.getRigidState(onMesh[0]).getPosition().y(), 2.05f + kHalf, 0.01f);
}

TEST(Sleep, NothingStaysAsleepInMidAirWhenItsSupportGoes) {
  // On the ground: stack A. On a fixed shelf 2 m up: stack C. Stack D's bottom box, and
  // the shelf, were added last, so that truncate can take them away.
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addGround(world);
  const std::vector<PfxUInt32> a = addStack(world, -3, 0, 2);
  const std::vector<PfxUInt32> c = addStack(world, 0, 2, 2);
  const PfxUInt32 dTop = addBox(world, PfxVector3(3, 3 * kHalf, 0));
  const PfxUInt32 dBottom = addBox(world, PfxVector3(3, kHalf, 0));
  addBox(world, PfxVector3(0, 1.9f, 0), kPfxMotionTypeFixed, PfxVector3(0.5f, 0.1f, 0.5f));
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
  const PfxFloat dTopBefore = world.getRigidState(dTop).getPosition().y();
  ASSERT_EQ(world.truncate(dBottom, world.getNumJoints(), world.getNumJointCouplings()), PFX_OK);
  ASSERT_EQ(world.getNumRigidBodies(), dBottom);
  EXPECT_TRUE(world.getRigidState(dTop).isAwake());
  EXPECT_TRUE(allAwake(world, c));
  EXPECT_TRUE(allAsleep(world, a));
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
  EXPECT_NEAR(world.getRigidState(dTop).getPosition().y(), kHalf, 0.01f);
  EXPECT_LT(world.getRigidState(dTop).getPosition().y(), dTopBefore - 0.4f);
  EXPECT_NEAR(world.getRigidState(c[0]).getPosition().y(), kHalf, 0.01f);  // fell to the ground

  // A fixed shelf moved away by the application: what stood on it falls too.
  const PfxUInt32 shelf2 = addBox(world, PfxVector3(0, 1.9f, 5), kPfxMotionTypeFixed,
                                  PfxVector3(0.5f, 0.1f, 0.5f));
  const std::vector<PfxUInt32> e = addStack(world, 0, 2, 1, 5);
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
  PfxRigidState moved = world.getRigidState(shelf2);
  moved.setPosition(PfxVector3(0, 1.9f, 9));
  ASSERT_EQ(world.setRigidState(shelf2, moved), PFX_OK);
  EXPECT_TRUE(allAwake(world, e));
  EXPECT_TRUE(allAsleep(world, a));
  ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
  EXPECT_NEAR(world.getRigidState(e[0]).getPosition().y(), kHalf, 0.01f);
}

TEST(Sleep, ASettledPileSleepsWithinFiveSecondsOfComingToRest) {
  // 125 boxes dropped into a bin (tests/extreme has 1,000).
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  pfx_test::expectPileSleepsWithinFiveSecondsOfRest(world, 125, 60 * 30);
}

TEST(Sleep, SleepingAndWakingAllocateNothingOnceWarm) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addGround(world);
  const std::vector<PfxUInt32> stack = addStack(world, 0, 0, 2);
  const std::vector<PfxUInt32> other = addStack(world, 6, 0, 2);
  const PfxUInt32 slider =
      addBox(world, PfxVector3(0, 0.2f, -3), kPfxMotionTypeActive, PfxVector3::Constant(0.2f));
  // One cycle: the slider, parked aside, falls asleep alone; then it slides against the
  // stack, which wakes on the touch, settles and sleeps again.
  const auto place = [&](const PfxVector3& position, const PfxVector3& velocity) {
    PfxRigidState state = world.getRigidState(slider);
    state.setPosition(position);
    state.setOrientation(PfxQuat::Identity());
    state.setLinearVelocity(velocity);
    state.setAngularVelocity(PfxVector3::Zero());
    ASSERT_EQ(world.setRigidState(slider, state), PFX_OK);
  };
  const auto cycle = [&] {
    place(PfxVector3(0, 0.2f, -3), PfxVector3::Zero());
    ASSERT_TRUE(stepUntil(world, [&] { return everythingAsleep(world); }, 300));
    const PfxFloat stackX = world.getRigidState(stack[0]).getPosition().x();
    place(PfxVector3(stackX - 0.5f, 0.2f, 0), PfxVector3(1, 0, 0));
    EXPECT_TRUE(allAsleep(world, stack));
    bool stackWoke = false;
    for (int i = 0; i < 600 && !(stackWoke && everythingAsleep(world)); ++i) {
      ASSERT_EQ(world.step(), PFX_OK);
      stackWoke = stackWoke || allAwake(world, stack);
    }
    EXPECT_TRUE(stackWoke);
    EXPECT_TRUE(everythingAsleep(world));
    EXPECT_TRUE(allAsleep(world, other));
  };
  cycle();
  cycle();
  const long before = pfx_test::pfxAllocationCount();
  cycle();
  ASSERT_EQ(world.applyForce(other[0], PfxVector3(0, 0, 1), PfxVector3::Zero()), PFX_OK);
  for (int i = 0; i < 10; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_EQ(pfx_test::pfxAllocationCount() - before, 0);
}
