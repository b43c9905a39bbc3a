// PfxWorldBatch: worlds stepped together give, world for world, the bits of the same worlds
// stepped one by one, on any number of threads; the states are gathered in world order;
// bad input is refused with nothing changed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "pfx/pfx.h"

using namespace pfx;

namespace {

// A ragdoll dropped, tilted by `tilt` radians, onto a ground box: different tilts make
// different worlds that fall differently.
void buildRagdollWorld(PfxWorld& world, PfxFloat tilt) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, -9.81f);
  param.timeStep = PfxFloat(1) / 120;
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, 0, -0.5f);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(PfxVector3(5, 5, 0.5f))), ground), PFX_OK);
  const PfxQuat tilted(Eigen::AngleAxis<PfxFloat>(tilt, PfxVector3::UnitX()));
  PfxRagdoll ragdoll;
  ASSERT_EQ(pfxAddRagdoll(world, PfxVector3(0, 0, 1.2f), tilted, &ragdoll), PFX_OK);
}

std::vector<PfxFloat> gatherOneByOne(const std::vector<PfxWorld*>& worlds) {
  std::vector<PfxFloat> rows;
  for (const PfxWorld* world : worlds) {
    for (PfxUInt32 b = 0; b < world->getNumRigidBodies(); ++b) {
      const PfxRigidState& s = world->getRigidState(b);
      rows.insert(rows.end(), s.getPosition().data(), s.getPosition().data() + 3);
      rows.insert(rows.end(), s.getOrientation().coeffs().data(),
                  s.getOrientation().coeffs().data() + 4);
      rows.insert(rows.end(), s.getLinearVelocity().data(), s.getLinearVelocity().data() + 3);
      rows.insert(rows.end(), s.getAngularVelocity().data(), s.getAngularVelocity().data() + 3);
    }
  }
  return rows;
}

std::vector<PfxFloat> gather(PfxWorldBatch& batch) {
  std::vector<PfxFloat> rows(std::size_t(batch.getNumRigidBodies()) * PFX_BATCH_STATE_FLOATS);
  EXPECT_EQ(batch.gatherStates(rows.data(), rows.size()), PFX_OK);
  return rows;
}

bool sameBits(const std::vector<PfxFloat>& a, const std::vector<PfxFloat>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PfxFloat)) == 0;
}

constexpr PfxUInt32 kSteps = 60;
const PfxFloat kTilts[] = {0.0f, 0.3f, -0.6f, 1.1f, 0.8f};

}  // namespace

TEST(WorldBatch, DifferentWorldsMatchOneByOneOnAnyThreadCount) {
  constexpr int kWorlds = sizeof(kTilts) / sizeof(kTilts[0]);
  std::vector<PfxWorld> alone(kWorlds);
  std::vector<PfxWorld*> alonePointers;
  for (int i = 0; i < kWorlds; ++i) {
    buildRagdollWorld(alone[i], kTilts[i]);
    for (PfxUInt32 s = 0; s < kSteps; ++s) ASSERT_EQ(alone[i].step(), PFX_OK);
    alonePointers.push_back(&alone[i]);
  }
  const std::vector<PfxFloat> expected = gatherOneByOne(alonePointers);
  // The worlds fell apart from one another: a batch stepping one world for all would fail.
  ASSERT_FALSE(sameBits(gatherOneByOne({&alone[0]}), gatherOneByOne({&alone[1]})));

  for (PfxUInt32 threads : {1u, 2u, 4u}) {
    std::vector<PfxWorld> batched(kWorlds);
    PfxWorldBatch batch;
    ASSERT_EQ(batch.setNumThreads(threads), PFX_OK);
    for (int i = 0; i < kWorlds; ++i) {
      buildRagdollWorld(batched[i], kTilts[i]);
      PfxUInt32 index = 99;
      ASSERT_EQ(batch.addWorld(batched[i], &index), PFX_OK);
      EXPECT_EQ(index, PfxUInt32(i));
    }
    // Steps in two calls, as a learner does between actions.
    ASSERT_EQ(batch.step(kSteps / 3), PFX_OK);
    ASSERT_EQ(batch.step(kSteps - kSteps / 3), PFX_OK);
    EXPECT_TRUE(sameBits(gather(batch), expected)) << threads << " threads";
    EXPECT_EQ(batch.getFirstBody(2), 2 * alone[0].getNumRigidBodies());
  }
}

TEST(WorldBatch, CopiesContinueAsTheSourceWould) {
  PfxWorld source;
  buildRagdollWorld(source, 0.4f);
  for (int s = 0; s < 30; ++s) ASSERT_EQ(source.step(), PFX_OK);  // contacts to carry over

  PfxWorldBatch batch;
  ASSERT_EQ(batch.setNumThreads(2), PFX_OK);
  ASSERT_EQ(batch.addCopies(source, 6), PFX_OK);
  ASSERT_EQ(batch.getNumWorlds(), 6u);
  // One copy gets a push; it alone must leave the others' path.
  ASSERT_EQ(batch.getWorld(3).applyForce(1, PfxVector3(500, 0, 0), PfxVector3::Zero()), PFX_OK);
  ASSERT_EQ(batch.step(kSteps), PFX_OK);
  for (PfxUInt32 s = 0; s < kSteps; ++s) ASSERT_EQ(source.step(), PFX_OK);

  const std::vector<PfxFloat> states = gather(batch);
  const std::size_t perWorld = std::size_t(source.getNumRigidBodies()) * PFX_BATCH_STATE_FLOATS;
  const std::vector<PfxFloat> expected = gatherOneByOne({&source});
  for (PfxUInt32 w = 0; w < batch.getNumWorlds(); ++w) {
    const std::vector<PfxFloat> world(states.begin() + w * perWorld,
                                      states.begin() + (w + 1) * perWorld);
    EXPECT_EQ(sameBits(world, expected), w != 3) << "world " << w;
    EXPECT_EQ(batch.getWorld(w).getSimulatedTime(), source.getSimulatedTime());
  }
}

TEST(WorldBatch, BadInputChangesNothing) {
  PfxWorld world;
  buildRagdollWorld(world, 0);
  PfxWorldBatch batch;
  EXPECT_EQ(batch.setNumThreads(PFX_MAX_THREADS + 1), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(batch.getNumThreads(), 1u);
  ASSERT_EQ(batch.addWorld(world), PFX_OK);
  EXPECT_EQ(batch.addWorld(world), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find("already"), std::string::npos);
  EXPECT_EQ(batch.getNumWorlds(), 1u);

  std::vector<PfxFloat> tooSmall(PFX_BATCH_STATE_FLOATS * world.getNumRigidBodies() - 1, -7);
  EXPECT_EQ(batch.gatherStates(tooSmall.data(), tooSmall.size()), PFX_ERR_OUT_OF_BUFFER);
  for (PfxFloat value : tooSmall) ASSERT_EQ(value, -7);
  EXPECT_EQ(batch.gatherStates(nullptr, 1000), PFX_ERR_NULL_POINTER);
}

TEST(WorldBatch, BytesWithAnythingPastTheWorldAreRefused) {
  PfxWorld source;
  buildRagdollWorld(source, 0.2f);
  std::vector<PfxUInt8> bytes;
  ASSERT_EQ(pfxSaveWorldToBytes(source, bytes), PFX_OK);
  PfxWorld target;
  buildRagdollWorld(target, 0.9f);
  const std::vector<PfxFloat> before = gatherOneByOne({&target});
  PfxSerializedMeshes meshes;
  std::string error;
  std::vector<PfxUInt8> longer = bytes;
  longer.push_back(0);
  EXPECT_EQ(pfxLoadWorldFromBytes(target, longer.data(), longer.size(), meshes, &error),
            PFX_ERR_OUT_OF_BUFFER);
  EXPECT_NE(error.find("announces"), std::string::npos) << error;
  EXPECT_EQ(pfxLoadWorldFromBytes(target, bytes.data(), bytes.size() - 1, meshes, &error),
            PFX_ERR_OUT_OF_BUFFER);
  EXPECT_TRUE(sameBits(gatherOneByOne({&target}), before));
  ASSERT_EQ(pfxLoadWorldFromBytes(target, bytes.data(), bytes.size(), meshes), PFX_OK);
  EXPECT_TRUE(sameBits(gatherOneByOne({&target}), gatherOneByOne({&source})));
}

TEST(WorldBatch, StateHashFollowsEveryBit) {
  PfxWorld a, b;
  buildRagdollWorld(a, 0.3f);
  buildRagdollWorld(b, 0.3f);
  EXPECT_EQ(pfxHashRigidStates(a), pfxHashRigidStates(b));
  PfxRigidState state = b.getRigidState(4);
  PfxVector3 velocity = state.getLinearVelocity();
  velocity.x() = std::nextafter(velocity.x(), PfxFloat(1));  // one bit of one value
  state.setLinearVelocity(velocity);
  ASSERT_EQ(b.setRigidState(4, state), PFX_OK);
  EXPECT_NE(pfxHashRigidStates(a), pfxHashRigidStates(b));
}
