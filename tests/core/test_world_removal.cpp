// PfxWorld::removeRigidBody and removeJoint: what stood on a removed body falls, what slept
// on it wakes, its joints and couplings go with it, rays, queries and pairs forget it, ids
// of the others stay as they were, the result is the same bits on any thread count and
// after a save and a load, a warm step still allocates nothing, and bad ids change nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_debug_render.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/low_level/pfx_error_detail.h"
#include "pfx_allocation_counter.h"
#include "pfx_serialize_test_world.h"

using namespace pfx;

namespace {

constexpr int kStackHeight = 4;

// A ground (id 0) and a stack of boxes on it (ids 1..kStackHeight), a little off centre so
// that contacts are not symmetric.
void buildStack(PfxWorld& world, PfxUInt32 numThreads = 1) {
  PfxWorldParam param;
  param.numThreads = numThreads;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  for (int i = 0; i < kStackHeight; ++i) {
    PfxBodyInit box;
    box.position = PfxVector3(PfxFloat(0.02) * i, PfxFloat(0.5 + 1.0 * i), 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5, 0.5, 0.5)), box), PFX_OK);
  }
}

void stepFor(PfxWorld& world, int steps) {
  for (int i = 0; i < steps; ++i) ASSERT_EQ(world.step(), PFX_OK);
}

std::vector<unsigned char> allStateBytes(const PfxWorld& world) {
  const auto* begin = reinterpret_cast<const unsigned char*>(world.getRigidStates());
  return std::vector<unsigned char>(begin,
                                    begin + world.getNumRigidBodies() * sizeof(PfxRigidState));
}

bool anyPairNames(const PfxWorld& world, PfxUInt32 id) {
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    const PfxConstraintPair& pair = world.getContactPair(i);
    if (pfxGetObjectIdA(pair) == id || pfxGetObjectIdB(pair) == id) return true;
  }
  return false;
}

PfxRayOutput castDown(PfxWorld& world, const PfxVector3& from) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = from;
  ray.m_direction = PfxVector3(0, -20, 0);
  PfxRayOutput out;
  EXPECT_EQ(world.castRay(ray, out), PFX_OK);
  return out;
}

// A fixed anchor (id 0) and three spheres hanging below it in a chain of ball joints
// (joints 0, 1, 2: anchor-1, 1-2, 2-3).
void buildChain(PfxWorld& world) {
  PfxWorldParam param;
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit anchor;
  anchor.mass = 0;
  anchor.position = PfxVector3(0, 5, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.1, 0.1, 0.1)), anchor), PFX_OK);
  for (int i = 1; i <= 3; ++i) {
    PfxBodyInit link;
    link.position = PfxVector3(PfxFloat(0.5) * i, 5, 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.1)), link), PFX_OK);
    PfxBallJointInitParam ball;
    ball.anchorPoint = PfxVector3(PfxFloat(0.5) * i - PfxFloat(0.25), 5, 0);
    PfxJoint joint;
    ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(i - 1), world.getRigidState(i),
                                     ball),
              PFX_OK);
    ASSERT_EQ(world.addJoint(joint), PFX_OK);
  }
}

}  // namespace

TEST(WorldRemoval, BoxesAboveARemovedBoxFall) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 60);
  const PfxUInt32 top = kStackHeight;
  const PfxFloat restingTop = world.getRigidState(top).getPosition().y();
  ASSERT_NEAR(restingTop, 0.5 + (kStackHeight - 1), 0.05);

  ASSERT_EQ(world.removeRigidBody(2), PFX_OK);
  EXPECT_FALSE(world.hasRigidBody(2));
  EXPECT_TRUE(world.hasRigidBody(top));
  EXPECT_EQ(world.getNumRigidBodies(), PfxUInt32(kStackHeight + 1));  // ids do not move
  EXPECT_EQ(world.getNumRemovedRigidBodies(), 1u);
  EXPECT_FALSE(anyPairNames(world, 2));
  stepFor(world, 90);
  // The boxes above came down by one box height and rest on box 1 again.
  EXPECT_NEAR(world.getRigidState(top).getPosition().y(), restingTop - 1, 0.05);
  EXPECT_NEAR(world.getRigidState(3).getPosition().y(), 1.5, 0.05);
  EXPECT_FALSE(anyPairNames(world, 2));
}

TEST(WorldRemoval, RemovingTheSupportOfASleepingStackWakesIt) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 240);
  for (PfxUInt32 id = 1; id <= kStackHeight; ++id) {
    ASSERT_TRUE(world.getRigidState(id).isAsleep()) << "body " << id;
  }
  ASSERT_EQ(world.removeRigidBody(1), PFX_OK);
  for (PfxUInt32 id = 2; id <= kStackHeight; ++id) {
    EXPECT_TRUE(world.getRigidState(id).isAwake()) << "body " << id;
  }
  stepFor(world, 1);
  EXPECT_EQ(world.getStats().numSleepingBodies, 0u);
  EXPECT_EQ(world.getStats().numAwakeBodies, PfxUInt32(kStackHeight - 1));
}

TEST(WorldRemoval, SameBitsOnOneTwoAndFourThreads) {
  std::vector<unsigned char> reference;
  for (const PfxUInt32 threads : {1u, 2u, 4u}) {
    PfxWorld world;
    buildStack(world, threads);
    stepFor(world, 20);
    ASSERT_EQ(world.removeRigidBody(2), PFX_OK);
    stepFor(world, 20);
    ASSERT_EQ(world.removeRigidBody(1), PFX_OK);
    PfxBodyInit late;
    late.position = PfxVector3(0.3f, 6, 0.1f);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.4f)), late), PFX_OK);
    stepFor(world, 40);
    const std::vector<unsigned char> bytes = allStateBytes(world);
    if (reference.empty()) {
      reference = bytes;
    } else {
      EXPECT_EQ(bytes, reference) << threads << " threads";
    }
  }
}

TEST(WorldRemoval, RemovingAJointedBodyRemovesItsJointsOnly) {
  PfxWorld world;
  buildChain(world);
  stepFor(world, 30);
  ASSERT_EQ(world.removeRigidBody(3), PFX_OK);
  EXPECT_TRUE(world.hasJoint(0));
  EXPECT_TRUE(world.hasJoint(1));
  EXPECT_FALSE(world.hasJoint(2));
  EXPECT_EQ(world.getNumJoints(), 3u);
  EXPECT_EQ(world.getNumRemovedJoints(), 1u);
  stepFor(world, 120);
  // The rest of the chain still hangs together from its anchor.
  EXPECT_LT(world.getStats().maxJointGap, 0.01);
  const PfxFloat reach = (world.getRigidState(2).getPosition() - PfxVector3(0, 5, 0)).norm();
  EXPECT_LT(reach, 1.0 + 0.02);
  EXPECT_LT(world.getRigidState(2).getPosition().y(), 5 - 0.5);  // swung down

  ASSERT_EQ(world.removeRigidBody(1), PFX_OK);
  EXPECT_FALSE(world.hasJoint(0));
  EXPECT_FALSE(world.hasJoint(1));
  // Body 2 no longer hangs from anything: it falls freely.
  const PfxFloat before = world.getRigidState(2).getPosition().y();
  stepFor(world, 30);
  EXPECT_LT(world.getRigidState(2).getPosition().y(), before - 1);
}

TEST(WorldRemoval, RemovingAJointLetsItsBodiesCollideAndDropsItsCouplings) {
  PfxWorld world;
  buildChain(world);
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = 1;
  coupling.m_followerJointId = 2;
  coupling.m_leaderAxis = coupling.m_followerAxis = kPfxJointAxisTwist;
  PfxUInt32 couplingId = 0;
  ASSERT_EQ(world.addJointCoupling(coupling, &couplingId), PFX_OK);
  ASSERT_EQ(world.removeJoint(2), PFX_OK);
  EXPECT_FALSE(world.hasJoint(2));
  EXPECT_FALSE(world.hasJointCoupling(couplingId));
  EXPECT_EQ(world.getJoint(2).m_active, 0);
  EXPECT_EQ(world.removeJoint(2), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.setJoint(2, world.getJoint(2)), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.addJointCoupling(coupling), PFX_ERR_OUT_OF_RANGE);
  // Bodies 2 and 3 were held apart by the joint; now the last one falls off the chain.
  stepFor(world, 60);
  EXPECT_LT(world.getRigidState(3).getPosition().y(), 5 - 2);
}

TEST(WorldRemoval, RemovedIdsAreNotReusedAndNewBodiesCollide) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 10);
  ASSERT_EQ(world.removeRigidBody(kStackHeight), PFX_OK);
  PfxBodyInit ball;
  ball.position = PfxVector3(5, 2, 0);
  PfxUInt32 id = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.5)), ball, &id), PFX_OK);
  EXPECT_EQ(id, PfxUInt32(kStackHeight + 1));
  EXPECT_FALSE(world.hasRigidBody(kStackHeight));
  EXPECT_TRUE(world.hasRigidBody(id));
  stepFor(world, 90);
  EXPECT_NEAR(world.getRigidState(id).getPosition().y(), 0.5, 0.05);  // on the ground
  EXPECT_EQ(world.removeRigidBody(id), PFX_OK);
  EXPECT_EQ(world.getNumRemovedRigidBodies(), 2u);
}

TEST(WorldRemoval, RaysAndQueriesNeverReportARemovedBody) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 30);
  ASSERT_EQ(castDown(world, PfxVector3(0.06f, 10, 0)).m_objectId, PfxUInt32(kStackHeight));
  for (PfxUInt32 id = kStackHeight; id >= 1; --id) {
    ASSERT_EQ(world.removeRigidBody(id), PFX_OK);
    EXPECT_EQ(castDown(world, PfxVector3(0.06f, 10, 0)).m_objectId, id - 1);
    // Also at the world's centre, where a removed slot waits.
    EXPECT_EQ(castDown(world, PfxVector3(0, 0.5, 0)).m_objectId, 0u);
  }
  PfxCollidable probe;
  probe.reset();
  probe.addShape(pfxMakeShape(PfxBox(3, 3, 3)));
  probe.finish();
  PfxContactQueryInput query;
  query.collidable = &probe;
  query.contactThreshold = 1;
  PfxQueryContact contacts[64];
  PfxQueryContactsResult result;
  ASSERT_EQ(world.queryContacts(query, contacts, 64, result), PFX_OK);
  ASSERT_GT(result.numContacts, 0u);
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) EXPECT_EQ(contacts[i].m_rigidBodyId, 0u);
  stepFor(world, 5);
  EXPECT_EQ(world.getNumContactPairs(), 0u);
}

TEST(WorldRemoval, BadIdsAreRejectedAndChangeNothing) {
  PfxWorld world;
  buildChain(world);
  stepFor(world, 10);
  ASSERT_EQ(world.removeRigidBody(3), PFX_OK);
  const std::vector<unsigned char> before = allStateBytes(world);
  const PfxUInt32 pairs = world.getNumContactPairs();

  EXPECT_EQ(world.removeRigidBody(3), PFX_ERR_OUT_OF_RANGE);  // already removed
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find("no body has id 3"), std::string::npos);
  EXPECT_EQ(world.removeRigidBody(4), PFX_ERR_OUT_OF_RANGE);  // never added
  EXPECT_EQ(world.removeRigidBody(0xffffffffu), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.removeJoint(3), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.removeJoint(2), PFX_ERR_OUT_OF_RANGE);  // went with body 3
  // Every call that takes a body id refuses the removed one.
  PfxRigidState state = world.getRigidState(2);
  EXPECT_EQ(world.setRigidState(3, state), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.setRigidBody(3, world.getRigidBody(2)), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.applyForce(3, PfxVector3(1, 0, 0), PfxVector3::Zero()), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.excludeCollision(2, 3), PFX_ERR_OUT_OF_RANGE);
  PfxJoint joint = world.getJoint(1);
  joint.m_rigidBodyIdB = 3;
  EXPECT_EQ(world.addJoint(joint), PFX_ERR_OUT_OF_RANGE);

  // Particles pinned to a body keep it; a pin to a removed body is refused.
  PfxParticle particle;
  particle.m_position = particle.m_previousPosition = PfxVector3(0.5f, 4.8f, 0);
  PfxParticlePin pin;
  pin.m_rigidBodyId = 1;
  PfxParticleGroupDesc desc;
  desc.particles = &particle;
  desc.numParticles = 1;
  desc.pins = &pin;
  desc.numPins = 1;
  PfxUInt32 group = 0;
  ASSERT_EQ(world.addParticleGroup(desc, &group), PFX_OK);
  EXPECT_EQ(world.removeRigidBody(1), PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(world.hasRigidBody(1));
  EXPECT_TRUE(world.hasJoint(0));
  pin.m_rigidBodyId = 3;
  EXPECT_EQ(world.addParticleGroup(desc), PFX_ERR_OUT_OF_RANGE);
  ASSERT_EQ(world.removeParticleGroup(group), PFX_OK);

  EXPECT_EQ(allStateBytes(world), before);
  EXPECT_EQ(world.getNumContactPairs(), pairs);
  EXPECT_EQ(world.getNumRemovedRigidBodies(), 1u);
  EXPECT_EQ(world.getNumRemovedJoints(), 1u);
  EXPECT_EQ(world.removeRigidBody(1), PFX_OK);  // without its pin it can go
}

TEST(WorldRemoval, SaveAndLoadKeepTheSlotsAndTheBits) {
  PfxWorld world;
  buildStack(world);
  PfxBodyInit hanging;
  hanging.position = PfxVector3(3, 2, 0);
  PfxUInt32 a = 0, b = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.2f)), hanging, &a), PFX_OK);
  hanging.position = PfxVector3(3.5f, 2, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.2f)), hanging, &b), PFX_OK);
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(3.25f, 2, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(a), world.getRigidState(b), ball),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  ASSERT_EQ(world.excludeCollision(1, 2), PFX_OK);
  stepFor(world, 30);
  ASSERT_EQ(world.removeRigidBody(2), PFX_OK);
  ASSERT_EQ(world.removeRigidBody(b), PFX_OK);
  stepFor(world, 5);

  const pfx_test::Bytes bytes = pfx_test::saveWorld(world);
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  ASSERT_EQ(pfx_test::loadWorld(loaded, meshes, bytes, &error), PFX_OK) << error;
  EXPECT_EQ(loaded.getNumRigidBodies(), world.getNumRigidBodies());
  EXPECT_FALSE(loaded.hasRigidBody(2));
  EXPECT_FALSE(loaded.hasRigidBody(b));
  EXPECT_FALSE(loaded.hasJoint(0));
  EXPECT_EQ(loaded.getNumRemovedRigidBodies(), 2u);
  EXPECT_EQ(loaded.getNumRemovedJoints(), 1u);
  EXPECT_EQ(loaded.removeRigidBody(2), PFX_ERR_OUT_OF_RANGE);
  stepFor(world, 60);
  stepFor(loaded, 60);
  EXPECT_EQ(allStateBytes(loaded), allStateBytes(world));
}

TEST(WorldRemoval, AWarmStepAfterRemovalsAllocatesNothing) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 20);
  ASSERT_EQ(world.removeRigidBody(2), PFX_OK);
  ASSERT_EQ(world.removeRigidBody(4), PFX_OK);
  stepFor(world, 20);
  const long before = pfx_test::pfxAllocationCount();
  ASSERT_EQ(world.removeRigidBody(3), PFX_OK);
  stepFor(world, 5);
  EXPECT_EQ(pfx_test::pfxAllocationCount(), before);
}

TEST(WorldRemoval, AFileWhoseRemovedSlotsDoNotHoldIsRejected) {
  PfxWorld world;
  buildStack(world);
  stepFor(world, 10);
  ASSERT_EQ(world.removeRigidBody(2), PFX_OK);
  const pfx_test::Bytes bytes = pfx_test::saveWorld(world);
  // GONE: the count of removed bodies, then their ids.
  const std::size_t ids = pfx_test::sectionPayload(bytes, "GONE") + 4;
  ASSERT_EQ(pfx_test::getU32(bytes, ids), 2u);
  struct Damage {
    PfxUInt32 id;
    PfxInt32 code;
    const char* says;
  };
  const Damage damages[] = {
      {99, PFX_ERR_OUT_OF_RANGE, "removed slots/bodies: holds 99, which is not increasing or not below 5"},
      {1, PFX_ERR_INVALID_VALUE, "removed slots/bodies: body 1 is removed but not inert"}};
  for (const Damage& damage : damages) {
    pfx_test::Bytes changed = bytes;
    pfx_test::putU32(changed, ids, damage.id);
    pfx_test::resealChecksum(changed);
    PfxWorld target;
    buildStack(target);
    const std::vector<unsigned char> before = allStateBytes(target);
    PfxSerializedMeshes meshes;
    std::string error;
    EXPECT_EQ(pfx_test::loadWorld(target, meshes, changed, &error), damage.code) << error;
    EXPECT_NE(error.find(damage.says), std::string::npos) << error;
    EXPECT_EQ(allStateBytes(target), before);
    EXPECT_EQ(target.getNumRemovedRigidBodies(), 0u);
  }
}

TEST(WorldRemoval, DebugDrawingLeavesRemovedBodiesAndJointsOut) {
  PfxWorld world;
  buildChain(world);
  stepFor(world, 5);
  PfxDebugRender render;
  int drawn = 0;
  render.setDebugRenderLineFunc([&](const PfxVector3&, const PfxVector3&, const PfxVector3&) { ++drawn; });
  render.setDebugRenderArcFunc([&](const PfxVector3&, const PfxVector3&, const PfxVector3&, PfxFloat,
                                   PfxFloat, PfxFloat, const PfxVector3&) { ++drawn; });
  render.setDebugRenderBoxFunc([&](const PfxTransform3&, const PfxVector3&, const PfxVector3&) { ++drawn; });
  render.setDebugRenderAabbFunc([&](const PfxVector3&, const PfxVector3&, const PfxVector3&) { ++drawn; });
  const auto count = [&](auto&& draw) {
    drawn = 0;
    draw();
    return drawn;
  };
  const auto shapes = [&] { render.renderShapes(world); };
  const auto boxes = [&] { render.renderAabb(world); };
  const auto joints = [&] { render.renderJoint(world); };
  const int sphereLines = count(shapes) - count([&] {
    render.renderShapes(world.getRigidStates(), &world.getCollidable(0), 3);
  });
  ASSERT_GT(sphereLines, 0);  // what the last sphere alone draws
  const int boxesBefore = count(boxes), jointsBefore = count(joints);
  ASSERT_EQ(world.removeJoint(2), PFX_OK);  // body 3 now hangs from nothing
  const int oneJoint = jointsBefore - count(joints);
  EXPECT_GT(oneJoint, 0);
  const int shapesBefore = count(shapes);
  ASSERT_EQ(world.removeRigidBody(3), PFX_OK);
  EXPECT_EQ(count(shapes), shapesBefore - sphereLines);
  EXPECT_EQ(count(boxes), boxesBefore - 1);
  EXPECT_EQ(count(joints), jointsBefore - oneJoint);
}
