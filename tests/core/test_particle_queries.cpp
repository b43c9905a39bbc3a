// Particles in the world's queries: rays (one and in batches) hit a rope's particles and a
// cloth's triangles, nearer bodies and particles win, filters apply; the contacts particles
// make with bodies are listed, also after the group falls asleep; bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"

using namespace pfx;

namespace {

constexpr PfxFloat kRadius = PfxFloat(0.02);

PfxParticleGroupBuilder::Material material() {
  PfxParticleGroupBuilder::Material m;
  m.particleMass = PfxFloat(0.01);
  m.radius = kRadius;
  return m;
}

PfxRayInput downward(const PfxVector3& above, PfxFloat length) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = above;
  ray.m_direction = PfxVector3(0, -length, 0);
  return ray;
}

// A rope of 21 particles pinned at both ends 1 m apart, hung for 3 s.
PfxUInt32 addHangingRope(PfxWorld& world) {
  PfxParticleGroupBuilder rope;
  rope.addRope(PfxVector3(-0.5, 2, 0), PfxVector3(0.5, 2, 0), 21, material());
  rope.pinToWorld(0);
  rope.pinToWorld(20);
  PfxUInt32 id = 0;
  EXPECT_EQ(world.addParticleGroup(rope.desc(), &id), PFX_OK);
  for (int i = 0; i < 180; ++i) EXPECT_EQ(world.step(), PFX_OK);
  return id;
}

// A flat cloth of 11 x 11 particles, 1 m square at height y, held where it is (no mass).
PfxUInt32 addFlatCloth(PfxWorld& world, PfxFloat y) {
  PfxParticleGroupBuilder cloth;
  PfxParticleGroupBuilder::Material m = material();
  cloth.addCloth(PfxVector3(-0.5, y, -0.5), PfxVector3(1, 0, 0), PfxVector3(0, 0, 1), 11, 11, m);
  for (PfxUInt32 i = 0; i < cloth.particles.size(); ++i) cloth.setMass(i, 0);
  PfxUInt32 id = 0;
  EXPECT_EQ(world.addParticleGroup(cloth.desc(), &id), PFX_OK);
  return id;
}

PfxUInt32 addBox(PfxWorld& world, const PfxVector3& position, const PfxVector3& half) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = position;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(half)), init, &id), PFX_OK);
  return id;
}

}  // namespace

TEST(ParticleQueries, RayDownOntoAHangingRopeHitsTheParticleSurface) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 id = addHangingRope(world);
  const PfxParticleGroup& group = *world.getParticleGroup(id);
  for (PfxUInt32 k : {3u, 10u, 16u}) {
    const PfxVector3 centre = group.particles[k].m_position;
    ASSERT_LT(centre.y(), 1.9);  // it hangs
    PfxRayOutput hit;
    ASSERT_EQ(world.castRay(downward(centre + PfxVector3(0, 1, 0), 2), hit), PFX_OK);
    ASSERT_TRUE(hit.m_contactFlag);
    EXPECT_EQ(hit.m_particleGroupId, id);
    EXPECT_EQ(hit.m_particleIndex, k);
    EXPECT_EQ(hit.m_objectId, PFX_RAY_NO_OBJECT);
    EXPECT_EQ(hit.m_triangleIndex, PFX_RAY_NO_TRIANGLE);
    const PfxVector3 top = centre + PfxVector3(0, kRadius, 0);
    EXPECT_LT((hit.m_contactPoint - top).norm(), 1e-5);
    EXPECT_LT((hit.m_contactNormal - PfxVector3(0, 1, 0)).norm(), 1e-5);
    EXPECT_NEAR(hit.m_variable, (1 - kRadius) / 2, 1e-5);
  }
}

TEST(ParticleQueries, RayThroughAClothSquareHitsItsPlaneFromEitherSide) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 id = addFlatCloth(world, 1);
  // Between particles, where a sphere test would find nothing.
  PfxRayOutput hit;
  ASSERT_EQ(world.castRay(downward(PfxVector3(0.13, 3, -0.27), 4), hit), PFX_OK);
  ASSERT_TRUE(hit.m_contactFlag);
  EXPECT_EQ(hit.m_particleGroupId, id);
  EXPECT_NE(hit.m_triangleIndex, PFX_RAY_NO_TRIANGLE);
  EXPECT_LT(hit.m_triangleIndex, 200u);
  EXPECT_LT((hit.m_contactPoint - PfxVector3(0.13, 1, -0.27)).norm(), 1e-5);
  EXPECT_LT((hit.m_contactNormal - PfxVector3(0, 1, 0)).norm(), 1e-5);
  // The nearest corner of the triangle hit: particle (i, j) = (6, 2) at (0.1, 1, -0.3).
  EXPECT_EQ(hit.m_particleIndex, 6u + 2u * 11u);

  PfxRayInput up = downward(PfxVector3(-0.31, 0, 0.42), -4);
  ASSERT_EQ(world.castRay(up, hit), PFX_OK);
  ASSERT_TRUE(hit.m_contactFlag);
  EXPECT_LT((hit.m_contactPoint - PfxVector3(-0.31, 1, 0.42)).norm(), 1e-5);
  EXPECT_LT((hit.m_contactNormal - PfxVector3(0, -1, 0)).norm(), 1e-5);

  // A slanted ray meets the plane where the line does.
  PfxRayInput slanted;
  slanted.reset();
  slanted.m_startPosition = PfxVector3(-0.2, 2, 0);
  slanted.m_direction = PfxVector3(0.6, -2, 0.2);
  ASSERT_EQ(world.castRay(slanted, hit), PFX_OK);
  ASSERT_TRUE(hit.m_contactFlag);
  EXPECT_NEAR(hit.m_variable, 0.5, 1e-6);
  EXPECT_LT((hit.m_contactPoint - PfxVector3(0.1, 1, 0.1)).norm(), 1e-5);
}

TEST(ParticleQueries, RaysMissBesideShortOfAndAlongTheCloth) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addFlatCloth(world, 1);
  const PfxRayInput rays[] = {downward(PfxVector3(0.6, 3, 0), 4),     // beside
                              downward(PfxVector3(0, 3, 0), PfxFloat(1.9)),  // short of it
                              downward(PfxVector3(0, 0.9, 0), 4)};    // below, going down
  for (const PfxRayInput& ray : rays) {
    PfxRayOutput hit;
    ASSERT_EQ(world.castRay(ray, hit), PFX_OK);
    EXPECT_FALSE(hit.m_contactFlag);
    EXPECT_EQ(hit.m_variable, 1);
    EXPECT_EQ(hit.m_particleGroupId, PFX_RAY_NO_OBJECT);
    EXPECT_EQ(hit.m_particleIndex, PFX_RAY_NO_OBJECT);
  }
}

TEST(ParticleQueries, TheNearerOfBodyAndParticleWinsAndFiltersApply) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  const PfxUInt32 below = addBox(world, PfxVector3(0, 0, 0), PfxVector3(1, 0.5, 1));
  const PfxUInt32 above = addBox(world, PfxVector3(0.4, 2, 0.4), PfxVector3(0.05, 0.05, 0.05));
  PfxParticleGroupBuilder cloth;
  PfxParticleGroupBuilder::Material m = material();
  m.contactFilterSelf = 2;
  cloth.addCloth(PfxVector3(-0.5, 1, -0.5), PfxVector3(1, 0, 0), PfxVector3(0, 0, 1), 11, 11, m);
  for (PfxUInt32 i = 0; i < cloth.particles.size(); ++i) cloth.setMass(i, 0);
  PfxUInt32 id = 0;
  ASSERT_EQ(world.addParticleGroup(cloth.desc(), &id), PFX_OK);

  PfxRayOutput hit;
  ASSERT_EQ(world.castRay(downward(PfxVector3(0, 3, 0), 4), hit), PFX_OK);
  EXPECT_EQ(hit.m_particleGroupId, id);
  EXPECT_NEAR(hit.m_contactPoint.y(), 1, 1e-5);
  ASSERT_EQ(world.castRay(downward(PfxVector3(0.4, 3, 0.4), 4), hit), PFX_OK);
  EXPECT_EQ(hit.m_objectId, above);
  EXPECT_EQ(hit.m_particleGroupId, PFX_RAY_NO_OBJECT);

  // A ray that sees group 1 only passes through the cloth (group 2) to the box below.
  PfxRayInput ray = downward(PfxVector3(0, 3, 0), 4);
  ray.m_contactFilterTarget = 1;
  ASSERT_EQ(world.castRay(ray, hit), PFX_OK);
  EXPECT_EQ(hit.m_objectId, below);
  EXPECT_EQ(hit.m_particleGroupId, PFX_RAY_NO_OBJECT);
  EXPECT_NEAR(hit.m_contactPoint.y(), 0.5, 1e-5);
  ray.m_contactFilterTarget = 2;
  ASSERT_EQ(world.castRay(ray, hit), PFX_OK);
  EXPECT_EQ(hit.m_particleGroupId, id);
}

TEST(ParticleQueries, ABatchAnswersAsSingleRaysOnAnyThreads) {
  for (PfxUInt32 threads : {1u, 2u}) {
    PfxWorldParam param;
    param.numThreads = threads;
    PfxWorld world;
    ASSERT_EQ(world.initialize(param), PFX_OK);
    addBox(world, PfxVector3(0, 0, 0), PfxVector3(2, 0.5, 2));
    addFlatCloth(world, 1);
    addHangingRope(world);
    // A fan of 200 rays (enough to be cast in Morton order) over rope, cloth and box.
    std::vector<PfxRayInput> rays(200);
    std::vector<PfxRayOutput> batch(rays.size()), single(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const PfxFloat x = PfxFloat(-0.7) + PfxFloat(1.4) * PfxFloat(i) / PfxFloat(rays.size());
      rays[i] = downward(PfxVector3(x, 3, PfxFloat(0.001) * PfxFloat(i % 7)), 4);
      ASSERT_EQ(world.castRay(rays[i], single[i]), PFX_OK);
    }
    ASSERT_EQ(world.castRays(rays.data(), batch.data(), PfxUInt32(rays.size())), PFX_OK);
    int particleHits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      EXPECT_EQ(batch[i].m_variable, single[i].m_variable) << i;
      EXPECT_EQ(batch[i].m_objectId, single[i].m_objectId) << i;
      EXPECT_EQ(batch[i].m_particleGroupId, single[i].m_particleGroupId) << i;
      EXPECT_EQ(batch[i].m_particleIndex, single[i].m_particleIndex) << i;
      particleHits += batch[i].m_particleGroupId != PFX_RAY_NO_OBJECT;
    }
    // The rope hangs above the cloth over x in [-0.5, 0.5]; the box is hit beyond.
    EXPECT_GT(particleHits, 100);
    EXPECT_LT(particleHits, 200);
  }
}

TEST(ParticleQueries, BadRaysAreRefusedWithTheOutputUntouched) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addFlatCloth(world, 1);
  PfxRayOutput hit;
  hit.m_variable = PfxFloat(0.25);
  hit.m_particleGroupId = 7;
  PfxRayInput ray = downward(PfxVector3(0, 3, 0), 4);
  ray.m_startPosition.x() = std::numeric_limits<PfxFloat>::quiet_NaN();
  EXPECT_EQ(world.castRay(ray, hit), PFX_ERR_INVALID_VALUE);
  ray = downward(PfxVector3(0, 3, 0), 0);
  EXPECT_EQ(world.castRay(ray, hit), PFX_ERR_DEGENERATE);
  EXPECT_EQ(hit.m_variable, PfxFloat(0.25));
  EXPECT_EQ(hit.m_particleGroupId, 7u);

  PfxRayInput rays[2] = {downward(PfxVector3(0, 3, 0), 4), ray};
  PfxRayOutput hits[2];
  hits[0].m_particleGroupId = 9;
  EXPECT_EQ(world.castRays(rays, hits, 2), PFX_ERR_DEGENERATE);
  EXPECT_EQ(hits[0].m_particleGroupId, 9u);

  const PfxParticle particle;
  const PfxUInt32 badTriangle[3] = {0, 1, 2};
  PfxRayOutput low = hit;
  EXPECT_EQ(pfxCastParticleRay(rays[0], &particle, 1, badTriangle, 1, low), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(pfxCastParticleRay(rays[0], nullptr, 1, nullptr, 0, low), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(low.m_variable, PfxFloat(0.25));
}

TEST(ParticleQueries, ContactsWithBodiesAreListedAlsoWhenTheGroupSleeps) {
  PfxWorldParam param;
  param.subStep = 4;
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxUInt32 box = addBox(world, PfxVector3(0, 0.25, 0), PfxVector3(0.4, 0.25, 0.4));
  PfxParticleGroupBuilder cloth;
  PfxParticleGroupBuilder::Material m = material();
  m.bendCompliance = PfxFloat(0.2);
  cloth.addCloth(PfxVector3(-0.3, 0.6, -0.3), PfxVector3(0.6, 0, 0), PfxVector3(0, 0, 0.6), 7, 7,
                 m);
  cloth.linearDamping = PfxFloat(0.5);
  PfxUInt32 id = 0;
  ASSERT_EQ(world.addParticleGroup(cloth.desc(), &id), PFX_OK);
  PfxParticleBodyContact contacts[256];
  bool sawAwake = false;
  for (int i = 0; i < 600 && !world.getParticleGroup(id)->asleep; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    sawAwake = true;
  }
  ASSERT_TRUE(sawAwake);
  ASSERT_TRUE(world.getParticleGroup(id)->asleep);
  PfxQueryContactsResult result;
  ASSERT_EQ(world.getParticleBodyContacts(contacts, 256, result), PFX_OK);
  EXPECT_FALSE(result.truncated);
  // Every particle of the cloth, which lies flat within the box's top, touches it once.
  ASSERT_EQ(result.numContacts, 49u);
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    const PfxParticleBodyContact& c = contacts[i];
    EXPECT_EQ(c.m_particleGroupId, id);
    EXPECT_EQ(c.m_rigidBodyId, box);
    EXPECT_LT((c.m_normal - PfxVector3(0, 1, 0)).norm(), 1e-4);
    EXPECT_LT(std::abs(c.m_depth), 0.006);
    const PfxVector3 centre = world.getParticleGroup(id)->particles[c.m_particle].m_position;
    EXPECT_NEAR(c.m_point.y(), 0.5, 0.006);
    EXPECT_NEAR(c.m_point.x(), centre.x(), 1e-5);
    EXPECT_GE(c.m_impulse, 0);
  }

  // Appended after what is there, and cut where the room ends.
  PfxQueryContactsResult partial;
  partial.numContacts = 250;
  ASSERT_EQ(world.getParticleBodyContacts(contacts, 256, partial), PFX_OK);
  EXPECT_EQ(partial.numContacts, 256u);
  EXPECT_TRUE(partial.truncated);
  PfxQueryContactsResult none;
  EXPECT_EQ(world.getParticleBodyContacts(nullptr, 4, none), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(none.numContacts, 0u);
}
