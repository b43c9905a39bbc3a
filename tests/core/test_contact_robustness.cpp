// The narrow phase under random and degenerate input, compounds, and rejected input.
#include <random>

#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx_contact_test_util.h"

namespace pfx_test {
namespace {

class ContactRobustness : public ::testing::Test {
 protected:
  void SetUp() override {
    m_boxMesh = buildMesh(makeBoxTriangles(0.6f, 0.3f, 0.4f));
    m_tetMesh = buildMesh(makeTetrahedronTriangles());
    m_icoMesh = buildMesh(makeIcosahedronTriangles());
  }

  // A shape of `type` with random sizes; one in eight sizes is exactly zero.
  PfxShape randomShape(int type, std::mt19937& rng) {
    std::uniform_real_distribution<PfxFloat> size(0.05f, 1.0f);
    std::uniform_int_distribution<int> eighth(0, 7);
    const auto s = [&]() { return eighth(rng) == 0 ? PfxFloat(0) : size(rng); };
    switch (type) {
      case kPfxShapeSphere: return makeSphere(s());
      case kPfxShapeBox: return makeBox(s(), s(), s());
      case kPfxShapeCapsule: return makeCapsule(s(), s());
      case kPfxShapeCylinder: return makeCylinder(s(), s());
      default: {
        const PfxConvexMesh* meshes[3] = {&m_boxMesh, &m_tetMesh, &m_icoMesh};
        return makeMeshShape(meshes[eighth(rng) % 3]);
      }
    }
  }

  PfxConvexMesh m_boxMesh, m_tetMesh, m_icoMesh;
};

bool isSwept(int type) { return type == kPfxShapeSphere || type == kPfxShapeCapsule; }
bool usesEpa(const PfxShape& shape) {
  return shape.getType() == kPfxShapeCylinder ||
         (shape.getType() == kPfxShapeBox && shape.getBox().m_half.minCoeff() == 0);
}

PfxTransform3 randomPose(std::mt19937& rng, PfxFloat spread) {
  std::uniform_real_distribution<PfxFloat> unit(-1, 1);
  const PfxQuat q = PfxQuat{unit(rng), unit(rng), unit(rng), unit(rng) + 1e-3f}.normalized();
  return pose(PfxVector3{unit(rng), unit(rng), unit(rng)} * spread, q);
}

TEST_F(ContactRobustness, RandomPosesOfEveryPairGiveWellFormedContacts) {
  // Every ordered pair of the five types, shapes near each other (touching, overlapping,
  // deep, coincident, separated), some with zero sizes: no NaN, no more than the cap,
  // each distance equal to the gap along the unit normal, and swapping the shapes gives
  // the same deepest distance (two different computations: the routines see the shapes in
  // the other order).
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> pick(0, 9);
  int withContacts = 0;
  for (int typeA = 0; typeA < kPfxShapeLargeTriMesh; ++typeA) {
    for (int typeB = 0; typeB < kPfxShapeLargeTriMesh; ++typeB) {
      for (int trial = 0; trial < 400; ++trial) {
        SCOPED_TRACE(::testing::Message() << "types " << typeA << "," << typeB << " trial " << trial);
        const PfxShape a = randomShape(typeA, rng);
        const PfxShape b = randomShape(typeB, rng);
        const PfxTransform3 ta = randomPose(rng, 0.5f);
        // One in ten poses shares A's pose exactly: coincident centres and axes.
        const PfxTransform3 tb = pick(rng) == 0 ? ta : randomPose(rng, 1.0f);
        const Contacts ab = collide(a, ta, b, tb, 0.05f);
        const Contacts ba = collide(b, tb, a, ta, 0.05f);
        ASSERT_FALSE(HasFatalFailure());
        if (ab.n > 0) ++withContacts;
        if (ab.n > 0 && ba.n > 0) {
          // Pairs that go through EPA (cylinders, a sphere or capsule against a mesh, a
          // box of zero thickness) stop at a polytope that approximates a curved or flat
          // Minkowski difference; for deep overlaps, coincident centres above all, their
          // depth is good to a few per cent. The other pairs are exact.
          const PfxFloat depth = std::max(-ab.deepest().m_distance, PfxFloat(0));
          const bool viaEpa = usesEpa(a) || usesEpa(b) ||
                              ((typeA == kPfxShapeConvexMesh || typeB == kPfxShapeConvexMesh) &&
                               (isSwept(typeA) || isSwept(typeB)));
          EXPECT_NEAR(ab.deepest().m_distance, ba.deepest().m_distance,
                      2e-3f + (viaEpa ? 5e-2f * depth : 0));
        } else if (ab.n > 0 || ba.n > 0) {
          // Only a contact right at the threshold may be seen from one side alone.
          const PfxFloat d = ab.n > 0 ? ab.deepest().m_distance : ba.deepest().m_distance;
          EXPECT_GT(d, 0.05f - 2e-3f);
        }
      }
    }
  }
  // The poses are close enough that most pairs touch: the checks above saw contacts.
  EXPECT_GT(withContacts, 25 * 400 / 3);
}

TEST_F(ContactRobustness, DeepestDistanceMatchesAnIndependentMeasure) {
  // Against spheres the answer is known without the pair routines: the sphere's centre
  // is |d| from the other shape's surface. A box against a sphere (analytic) agrees
  // with a mesh box against the same sphere (GJK).
  std::mt19937 rng(99);
  std::uniform_real_distribution<PfxFloat> unit(-1, 1);
  const PfxShape box = makeBox(0.6f, 0.3f, 0.4f);
  const PfxShape meshBox = makeMeshShape(&m_boxMesh);
  for (int trial = 0; trial < 500; ++trial) {
    const PfxShape sphere = makeSphere(0.2f + 0.3f * std::abs(unit(rng)));
    const PfxTransform3 tBox = randomPose(rng, 0.3f);
    const PfxTransform3 tSphere = pose(PfxVector3{unit(rng), unit(rng), unit(rng)});
    const Contacts exact = collide(box, tBox, sphere, tSphere, 0.05f);
    const Contacts viaGjk = collide(meshBox, tBox, sphere, tSphere, 0.05f);
    ASSERT_EQ(exact.n > 0, viaGjk.n > 0) << "trial " << trial;
    if (exact.n == 0) continue;
    EXPECT_NEAR(exact.deepest().m_distance, viaGjk.deepest().m_distance, 1e-3f);
    expectVecNear(exact.deepest().m_normal, viaGjk.deepest().m_normal, 2e-2f);
  }
}

TEST(ContactCollidables, CompoundAgainstBoxFillsShapeIds) {
  // Body A: two unit spheres at x = -2 and x = +2 (shape 0 and 1). Body B: a box of half
  // (3, 0.5, 1) whose top is at y = 0.5, the spheres' centres at y = 1.45: each sphere is
  // 0.05 deep, one contact each, shape ids 0 and 1 against 0.
  PfxShape shapes[2];
  const PfxUInt16 ids[2] = {0, 1};
  PfxCollidable compound;
  ASSERT_EQ(compound.reset(shapes, ids, 2), PFX_OK);
  PfxShape s = makeSphere(1);
  s.setOffsetPosition(PfxVector3(-2, 0, 0));
  ASSERT_EQ(compound.addShape(s), PFX_OK);
  s.setOffsetPosition(PfxVector3(2, 0, 0));
  ASSERT_EQ(compound.addShape(s), PFX_OK);
  ASSERT_EQ(compound.finish(), PFX_OK);
  PfxCollidable ground;
  ground.reset();
  ASSERT_EQ(ground.addShape(makeBox(3, 0.5f, 1)), PFX_OK);
  ASSERT_EQ(ground.finish(), PFX_OK);

  PfxContactCandidate out[8];
  const PfxUInt32 n = pfxContactCollidables(compound, pose(PfxVector3(0, 1.45f, 0)), ground,
                                            pose(PfxVector3::Zero()), 0.02f, out, 8);
  ASSERT_EQ(n, 2u);
  for (PfxUInt32 i = 0; i < n; ++i) {
    EXPECT_NEAR(out[i].m_distance, -0.05f, 1e-5f);
    expectVecNear(out[i].m_normal, PfxVector3(0, -1, 0), 1e-5f);
    EXPECT_EQ(out[i].m_shapeIdB, 0);
    const PfxFloat expectedX = out[i].m_shapeIdA == 0 ? -2.0f : 2.0f;
    expectVecNear(out[i].m_pointA, PfxVector3(expectedX, 0.45f, 0), 1e-5f);
  }
  EXPECT_NE(out[0].m_shapeIdA, out[1].m_shapeIdA);

  // Room for one: the deeper sphere stays. Lower the right one (shape 1) by tilting.
  const PfxTransform3 tilted = pose(PfxVector3(0, 1.45f, 0), rotZ(-0.01f));
  PfxContactCandidate one[1];
  ASSERT_EQ(pfxContactCollidables(compound, tilted, ground, pose(PfxVector3::Zero()), 0.02f, one, 1),
            1u);
  EXPECT_EQ(one[0].m_shapeIdA, 1);
  // With the body lifted 0.1 above the threshold, the bounds test rejects both.
  EXPECT_EQ(pfxContactCollidables(compound, pose(PfxVector3(0, 1.6f, 0)), ground,
                                  pose(PfxVector3::Zero()), 0.02f, out, 8),
            0u);
}

TEST(ContactCollidables, LargeMeshShapesMeetConvexShapesOnly) {
  // A compound of a large mesh (a 2 x 2 m square 5 m below) and a sphere: against a sphere
  // beside it, only the compound's sphere (shape 1) touches. The convex-pair routine
  // itself does not take large meshes (they go through the mesh's own search).
  const PfxFloat vertices[] = {-1, -5, -1, 1, -5, -1, 1, -5, 1, -1, -5, 1};
  const PfxUInt32 triangles[] = {0, 2, 1, 0, 3, 2};
  PfxCreateLargeTriMeshParam param;
  param.m_vertices = vertices;
  param.m_numVertices = 4;
  param.m_triangles = triangles;
  param.m_numTriangles = 2;
  PfxLargeTriMesh mesh;
  ASSERT_EQ(pfxCreateLargeTriMesh(mesh, param), PFX_OK);

  PfxShape shapes[2];
  const PfxUInt16 ids[2] = {0, 1};
  PfxCollidable compound;
  ASSERT_EQ(compound.reset(shapes, ids, 2), PFX_OK);
  PfxShape large;
  large.reset();
  large.setLargeTriMesh(&mesh);
  ASSERT_EQ(compound.addShape(large), PFX_OK);
  ASSERT_EQ(compound.addShape(makeSphere(0.5f)), PFX_OK);
  ASSERT_EQ(compound.finish(), PFX_OK);
  PfxCollidable other;
  other.reset();
  ASSERT_EQ(other.addShape(makeSphere(0.5f)), PFX_OK);
  ASSERT_EQ(other.finish(), PFX_OK);
  PfxContactCandidate out[4];
  const PfxUInt32 n = pfxContactCollidables(compound, pose(PfxVector3::Zero()), other,
                                            pose(PfxVector3(0.9f, 0, 0)), 0.02f, out, 4);
  ASSERT_EQ(n, 1u);
  EXPECT_EQ(out[0].m_shapeIdA, 1);
  EXPECT_NEAR(out[0].m_distance, -0.1f, 1e-5f);

  // The same sphere resting on the square does touch the mesh (shape 0).
  const PfxUInt32 onMesh = pfxContactCollidables(compound, pose(PfxVector3::Zero()), other,
                                                 pose(PfxVector3(0, -4.52f, 0)), 0.05f, out, 4);
  ASSERT_GE(onMesh, 1u);
  EXPECT_EQ(out[0].m_shapeIdA, 0);
  EXPECT_NEAR(out[0].m_distance, -0.02f, 1e-4f);

  PfxShape sphere = makeSphere(0.5f);
  EXPECT_EQ(pfxContactConvexShapes(large, pose(PfxVector3::Zero()), sphere,
                                   pose(PfxVector3::Zero()), 0.02f, out, 4),
            0u);
  pfxReleaseLargeTriMesh(mesh);
}

TEST(ContactBadInput, RejectedCallsWriteNothing) {
  // Overlapping spheres would give one contact; each bad argument gives none and leaves
  // the output as it was.
  const PfxShape a = makeSphere(0.5f);
  const PfxShape b = makeSphere(0.5f);
  const PfxTransform3 ta = pose(PfxVector3::Zero());
  const PfxTransform3 tb = pose(PfxVector3(0.9f, 0, 0));
  PfxContactCandidate out[2];
  const auto untouched = [&]() {
    for (auto& c : out) {
      if (c.m_distance != 42.0f) return false;
    }
    return true;
  };
  const auto reset = [&]() {
    for (auto& c : out) c.m_distance = 42.0f;
  };
  reset();
  ASSERT_EQ(pfxContactConvexShapes(a, ta, b, tb, 0.02f, out, 2), 1u);

  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  reset();
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, tb, 0.02f, nullptr, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, tb, 0.02f, out, 0), 0u);
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, tb, -0.01f, out, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, tb, nan, out, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, pose(PfxVector3(nan, 0, 0)), 0.02f, out, 2), 0u);
  PfxTransform3 sheared = tb;
  sheared.linear()(0, 1) = 0.5f;
  EXPECT_EQ(pfxContactConvexShapes(a, ta, b, sheared, 0.02f, out, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(makeSphere(-1), ta, b, tb, 0.02f, out, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(makeSphere(nan), ta, b, tb, 0.02f, out, 2), 0u);
  EXPECT_EQ(pfxContactConvexShapes(makeMeshShape(nullptr), ta, b, tb, 0.02f, out, 2), 0u);
  PfxConvexMesh broken{};
  broken.m_numVerts = 200;  // beyond the layout limit
  broken.m_numFaces = 1;
  EXPECT_EQ(pfxContactConvexShapes(makeMeshShape(&broken), ta, b, tb, 0.02f, out, 2), 0u);
  EXPECT_TRUE(untouched());

  PfxCollidable ca, cb;
  ca.reset();
  cb.reset();
  ASSERT_EQ(ca.addShape(a), PFX_OK);
  ASSERT_EQ(cb.addShape(b), PFX_OK);
  EXPECT_EQ(pfxContactCollidables(ca, ta, cb, tb, 0.02f, nullptr, 2), 0u);
  EXPECT_EQ(pfxContactCollidables(ca, ta, cb, tb, nan, out, 2), 0u);
  EXPECT_EQ(pfxContactCollidables(ca, pose(PfxVector3(0, nan, 0)), cb, tb, 0.02f, out, 2), 0u);
  EXPECT_TRUE(untouched());
}

TEST(ContactBadInput, OutputNeverExceedsMaxOut) {
  // A cylinder cap on a box gives many points; a buffer of three gets the three deepest.
  const PfxShape box = makeBox(2, 1, 2);
  const PfxShape cylinder = makeCylinder(0.5f, 0.5f);
  // Tilted slightly so that the depths differ.
  const PfxTransform3 tc = pose(PfxVector3(0, 1.49f, 0), rotZ(PFX_PI / 2) * rotY(0.005f));
  Contacts all = collide(box, pose(PfxVector3::Zero()), cylinder, tc);
  ASSERT_GT(all.n, 3u);
  PfxContactCandidate three[3];
  ASSERT_EQ(pfxContactConvexShapes(box, pose(PfxVector3::Zero()), cylinder, tc, 0.02f, three, 3),
            3u);
  std::vector<PfxFloat> depths;
  for (PfxUInt32 i = 0; i < all.n; ++i) depths.push_back(all.c[i].m_distance);
  std::sort(depths.begin(), depths.end());
  for (const auto& c : three) EXPECT_LE(c.m_distance, depths[2] + 1e-6f);
}

}  // namespace
}  // namespace pfx_test
