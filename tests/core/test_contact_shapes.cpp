// Known answers of the narrow phase for every pair of convex shapes. Each expected value is
// derived in the comment above it; analytic and SAT pairs are held to 1e-5, GJK/EPA pairs
// to 1e-3.
#include "pfx_contact_test_util.h"

namespace pfx_test {
namespace {

constexpr PfxFloat kExact = 1e-5f;
constexpr PfxFloat kIterative = 1e-3f;
const PfxFloat kSqrt2 = std::sqrt(PfxFloat(2));

// ---------------------------------------------------------------- sphere and capsule pairs

TEST(ContactSphereSphere, OverlapGivesDepthNormalAndSurfacePoints) {
  // Centres 0.7 apart, radii 0.5 + 0.3 = 0.8: depth 0.1 along +X; A's surface at x = 0.5,
  // B's at 0.7 - 0.3 = 0.4.
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3(0, 0, 0)), makeSphere(0.3f),
                             pose(PfxVector3(0.7f, 0, 0)));
  expectSingle(r, -0.1f, PfxVector3(1, 0, 0), PfxVector3(0.5f, 0, 0), PfxVector3(0.4f, 0, 0),
               kExact);
}

TEST(ContactSphereSphere, SpeculativeWithinThresholdAndNothingBeyond) {
  // Gap 0.81 - 0.8 = 0.01 < threshold 0.02: a speculative contact; gap 0.05 is too far.
  const Contacts near = collide(makeSphere(0.5f), pose(PfxVector3::Zero()), makeSphere(0.3f),
                                pose(PfxVector3(0, 0.81f, 0)));
  expectSingle(near, 0.01f, PfxVector3(0, 1, 0), PfxVector3(0, 0.5f, 0),
               PfxVector3(0, 0.51f, 0), kExact);
  EXPECT_EQ(collide(makeSphere(0.5f), pose(PfxVector3::Zero()), makeSphere(0.3f),
                    pose(PfxVector3(0, 0.85f, 0)))
                .n,
            0u);
}

TEST(ContactSphereSphere, CoincidentCentresPushAlongAsPlusY) {
  // No direction between the centres: the documented choice is A's +Y, rotated with A
  // (A turned 90 degrees about Z has its +Y along world -X). Depth is the sum of radii.
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3(1, 2, 3), rotZ(PFX_PI / 2)),
                             makeSphere(0.25f), pose(PfxVector3(1, 2, 3)));
  expectSingle(r, -0.75f, PfxVector3(-1, 0, 0), PfxVector3(0.5f, 2, 3),
               PfxVector3(1.25f, 2, 3), kExact);
}

TEST(ContactSphereSphere, ZeroRadiusSphereIsAPoint) {
  // A point 0.4 from the centre of a radius-0.5 sphere is 0.1 deep; the normal points from
  // the sphere (A) to the point (B).
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3::Zero()), makeSphere(0),
                             pose(PfxVector3(0, 0, 0.4f)));
  expectSingle(r, -0.1f, PfxVector3(0, 0, 1), PfxVector3(0, 0, 0.5f), PfxVector3(0, 0, 0.4f),
               kExact);
}

TEST(ContactSphereCapsule, SideOfCapsule) {
  // Capsule along X (half length 1, radius 0.2) at the origin; sphere radius 0.5 at
  // (0.5, 0.6, 0). Closest axis point (0.5, 0, 0), 0.6 away: depth 0.7 - 0.6 = 0.1. The
  // normal points from the sphere (A) down to the capsule (B).
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3(0.5f, 0.6f, 0)),
                             makeCapsule(1, 0.2f), pose(PfxVector3::Zero()));
  expectSingle(r, -0.1f, PfxVector3(0, -1, 0), PfxVector3(0.5f, 0.1f, 0),
               PfxVector3(0.5f, 0.2f, 0), kExact);
}

TEST(ContactSphereCapsule, BeyondTheEndCap) {
  // Sphere radius 0.3 at (1.6, 0, 0): the capsule's end point (1, 0, 0) is 0.6 away,
  // radii 0.2 + 0.3 = 0.5: a gap of 0.1, beyond the threshold; at 1.48 it is 0.02 deep.
  EXPECT_EQ(collide(makeCapsule(1, 0.2f), pose(PfxVector3::Zero()), makeSphere(0.3f),
                    pose(PfxVector3(1.6f, 0, 0)))
                .n,
            0u);
  const Contacts r = collide(makeCapsule(1, 0.2f), pose(PfxVector3::Zero()), makeSphere(0.3f),
                             pose(PfxVector3(1.48f, 0, 0)));
  expectSingle(r, -0.02f, PfxVector3(1, 0, 0), PfxVector3(1.2f, 0, 0), PfxVector3(1.18f, 0, 0),
               kExact);
}

TEST(ContactCapsuleCapsule, CrossingAxesGiveOnePoint) {
  // A along X, B along Z (turned about Y), B's centre 0.3 above: the axes cross at a
  // distance 0.3, radii 0.2 + 0.2: depth 0.1 along +Y.
  const Contacts r = collide(makeCapsule(1, 0.2f), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.2f), pose(PfxVector3(0, 0.3f, 0), rotY(PFX_PI / 2)));
  expectSingle(r, -0.1f, PfxVector3(0, 1, 0), PfxVector3(0, 0.2f, 0), PfxVector3(0, 0.1f, 0),
               kExact);
}

TEST(ContactCapsuleCapsule, SideBySideGiveTheEndsOfTheOverlap) {
  // Parallel axes 0.35 apart (radii sum 0.4: 0.05 deep); B is shifted by 0.5 along X, so
  // the axes overlap for x in [-0.5, 1]: two contacts, at those ends.
  const Contacts r = collide(makeCapsule(1, 0.2f), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.2f), pose(PfxVector3(0.5f, 0.35f, 0)));
  ASSERT_EQ(r.n, 2u);
  for (const PfxFloat x : {-0.5f, 1.0f}) {
    const PfxContactCandidate& c = r.nearestA(PfxVector3(x, 0.2f, 0));
    EXPECT_NEAR(c.m_distance, -0.05f, kExact);
    expectVecNear(c.m_normal, PfxVector3(0, 1, 0), kExact);
    expectVecNear(c.m_pointA, PfxVector3(x, 0.2f, 0), kExact);
    expectVecNear(c.m_pointB, PfxVector3(x, 0.15f, 0), kExact);
  }
}

TEST(ContactCapsuleCapsule, CoincidentCrossingAxesUseTheirCommonPerpendicular) {
  // A along X and B along Z through the same point: the cores touch, and the least
  // penetration is along X cross Z = -Y, turned towards A's +Y: +Y, depth 0.4.
  const Contacts r = collide(makeCapsule(1, 0.2f), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.2f), pose(PfxVector3::Zero(), rotY(PFX_PI / 2)));
  expectSingle(r, -0.4f, PfxVector3(0, 1, 0), PfxVector3(0, 0.2f, 0), PfxVector3(0, -0.2f, 0),
               kExact);
}

// ---------------------------------------------------------------- sphere and capsule on a box

TEST(ContactSphereBox, FaceEdgeAndInside) {
  const PfxShape box = makeBox(1, 1, 1);
  // Over the +Y face: centre 1.4 high, radius 0.5: 0.1 deep.
  expectSingle(collide(box, pose(PfxVector3::Zero()), makeSphere(0.5f),
                       pose(PfxVector3(0, 1.4f, 0))),
               -0.1f, PfxVector3(0, 1, 0), PfxVector3(0, 1, 0), PfxVector3(0, 0.9f, 0), kExact);
  // Beside the edge x = y = 1: centre (1.3, 1.4, 0) is (0.3, 0.4, 0) from the edge, 0.5
  // away; radius 0.6 makes it 0.1 deep along (0.6, 0.8, 0).
  expectSingle(collide(box, pose(PfxVector3::Zero()), makeSphere(0.6f),
                       pose(PfxVector3(1.3f, 1.4f, 0))),
               -0.1f, PfxVector3(0.6f, 0.8f, 0), PfxVector3(1, 1, 0),
               PfxVector3(1.3f - 0.36f, 1.4f - 0.48f, 0), kExact);
  // Centre inside at (0, 0.8, 0): the nearest face is +Y, 0.2 away: depth 0.2 + 0.5.
  expectSingle(collide(box, pose(PfxVector3::Zero()), makeSphere(0.5f),
                       pose(PfxVector3(0, 0.8f, 0))),
               -0.7f, PfxVector3(0, 1, 0), PfxVector3(0, 1, 0), PfxVector3(0, 0.3f, 0), kExact);
}

TEST(ContactSphereBox, CoincidentCentresLeaveAlongTheBoxsPlusX) {
  // Every face is 1 away: the documented tie-break is the box's +X (here world +Z, the box
  // being turned -90 degrees about Y). Depth 1 + 0.5; the normal is from the sphere (A).
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3::Zero()), makeBox(1, 1, 1),
                             pose(PfxVector3::Zero(), rotY(-PFX_PI / 2)));
  expectSingle(r, -1.5f, PfxVector3(0, 0, -1), PfxVector3(0, 0, -0.5f), PfxVector3(0, 0, 1),
               kExact);
}

TEST(ContactSphereBox, ZeroSizeBoxIsAPoint) {
  // A box of zero size at (0, 0.4, 0) inside a sphere of radius 0.5: the point is 0.1 deep.
  const Contacts r = collide(makeSphere(0.5f), pose(PfxVector3::Zero()), makeBox(0, 0, 0),
                             pose(PfxVector3(0, 0.4f, 0)));
  expectSingle(r, -0.1f, PfxVector3(0, 1, 0), PfxVector3(0, 0.5f, 0), PfxVector3(0, 0.4f, 0),
               kExact);
}

TEST(ContactCapsuleBox, LyingOnAFaceGivesBothEnds) {
  // Box half (2, 0.5, 2); capsule along X, half length 1, radius 0.25, centre 0.74 high:
  // 0.74 - 0.5 - 0.25 = -0.01 at both ends x = +-1.
  const Contacts r = collide(makeBox(2, 0.5f, 2), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.25f), pose(PfxVector3(0, 0.74f, 0)));
  ASSERT_EQ(r.n, 2u);
  for (const PfxFloat x : {-1.0f, 1.0f}) {
    const PfxContactCandidate& c = r.nearestA(PfxVector3(x, 0.5f, 0));
    EXPECT_NEAR(c.m_distance, -0.01f, kExact);
    expectVecNear(c.m_normal, PfxVector3(0, 1, 0), kExact);
    expectVecNear(c.m_pointA, PfxVector3(x, 0.5f, 0), kExact);
    expectVecNear(c.m_pointB, PfxVector3(x, 0.49f, 0), kExact);
  }
}

TEST(ContactCapsuleBox, HoveringWithinThresholdGivesSpeculativeEnds) {
  // The same capsule 0.01 above the face, threshold 0.02: both ends, each 0.01 away.
  const Contacts r = collide(makeBox(2, 0.5f, 2), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.25f), pose(PfxVector3(0, 0.76f, 0)));
  ASSERT_EQ(r.n, 2u);
  EXPECT_NEAR(r.c[0].m_distance, 0.01f, kExact);
  EXPECT_NEAR(r.c[1].m_distance, 0.01f, kExact);
  EXPECT_NEAR(std::abs(r.c[0].m_pointB.x() - r.c[1].m_pointB.x()), 2, kExact);
}

TEST(ContactCapsuleBox, OverhangingCapsuleIsClippedToTheFace) {
  // Box half (1, 0.5, 1); capsule centred at x = 1.5 (ends at 0.5 and 2.5), 0.05 deep.
  // Only x in [0.5, 1] lies over the face: contacts at x = 0.5 and x = 1.
  const Contacts r = collide(makeBox(1, 0.5f, 1), pose(PfxVector3::Zero()),
                             makeCapsule(1, 0.25f), pose(PfxVector3(1.5f, 0.7f, 0)));
  ASSERT_EQ(r.n, 2u);
  expectVecNear(r.nearestA(PfxVector3(0.5f, 0.5f, 0)).m_pointA, PfxVector3(0.5f, 0.5f, 0), kExact);
  expectVecNear(r.nearestA(PfxVector3(1, 0.5f, 0)).m_pointA, PfxVector3(1, 0.5f, 0), kExact);
  EXPECT_NEAR(r.deepest().m_distance, -0.05f, kExact);
}

TEST(ContactCapsuleBox, AxisInsideTheBoxNearAFace) {
  // The axis runs along Z at (0.95, 0.9) inside a unit box and out through both Z faces.
  // Least overlap: the +X face, 1 - 0.95 = 0.05 (+Y would need 0.1), plus radius 0.1. The
  // axis clipped to the face's rectangle ends at z = -1 and z = 1.
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeCapsule(2, 0.1f),
                             pose(PfxVector3(0.95f, 0.9f, 0), rotY(PFX_PI / 2)));
  ASSERT_EQ(r.n, 2u);
  for (const PfxFloat z : {-1.0f, 1.0f}) {
    const PfxContactCandidate& c = r.nearestA(PfxVector3(1, 0.9f, z));
    EXPECT_NEAR(c.m_distance, -0.15f, kExact);
    expectVecNear(c.m_normal, PfxVector3(1, 0, 0), kExact);
    expectVecNear(c.m_pointA, PfxVector3(1, 0.9f, z), kExact);
    expectVecNear(c.m_pointB, PfxVector3(0.85f, 0.9f, z), kExact);
  }
}

TEST(ContactCapsuleBox, AxisCrossingAnEdge) {
  // The axis runs along (1, -1, 0)/sqrt2 through (0.95, 0.95, 0), crossing the box edge
  // x = y = 1 at right angles. On the axis L = (1, 1, 0)/sqrt2 the box reaches sqrt2 and
  // the segment sits at 1.9/sqrt2: overlap (2 - 1.9)/sqrt2 = 0.0707, far less than through
  // any face. Contact at the edge point (1, 1, 0), depth 0.0707 + radius 0.1.
  const PfxFloat overlap = 0.1f / kSqrt2;
  const PfxVector3 n(1 / kSqrt2, 1 / kSqrt2, 0);
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeCapsule(1, 0.1f),
                             pose(PfxVector3(0.95f, 0.95f, 0), rotZ(-PFX_PI / 4)));
  expectSingle(r, -overlap - 0.1f, n, PfxVector3(1, 1, 0), PfxVector3(0.95f, 0.95f, 0) - n * 0.1f,
               kExact);
}

TEST(ContactCapsuleBox, AlongAnEdgeOutsideTheBox) {
  // Capsule along Z at (1.1, 1.1): 0.1 sqrt2 = 0.1414 from the edge x = y = 1; radius 0.2
  // makes it 0.0586 deep along (1, 1, 0)/sqrt2.
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeCapsule(0.5f, 0.2f),
                             pose(PfxVector3(1.1f, 1.1f, 0), rotY(PFX_PI / 2)));
  ASSERT_EQ(r.n, 1u);
  EXPECT_NEAR(r.c[0].m_distance, 0.1f * kSqrt2 - 0.2f, kExact);
  expectVecNear(r.c[0].m_normal, PfxVector3(1 / kSqrt2, 1 / kSqrt2, 0), kExact);
  EXPECT_NEAR(r.c[0].m_pointA.x(), 1, kExact);
  EXPECT_NEAR(r.c[0].m_pointA.y(), 1, kExact);
}

// ---------------------------------------------------------------- box and box

TEST(ContactBoxBox, SmallBoxOnBigBoxGivesItsFourCorners) {
  // A half (1, 1, 1); B half 0.5, centre 1.49 high: B's bottom at 0.99, 0.01 deep. The
  // smaller face is clipped by nothing: its four corners (+-0.5, ., +-0.5).
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()),
                             makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0, 1.49f, 0)));
  ASSERT_EQ(r.n, 4u);
  for (const PfxFloat x : {-0.5f, 0.5f}) {
    for (const PfxFloat z : {-0.5f, 0.5f}) {
      const PfxContactCandidate& c = r.nearestA(PfxVector3(x, 1, z));
      EXPECT_NEAR(c.m_distance, -0.01f, kExact);
      expectVecNear(c.m_normal, PfxVector3(0, 1, 0), kExact);
      expectVecNear(c.m_pointA, PfxVector3(x, 1, z), kExact);
      expectVecNear(c.m_pointB, PfxVector3(x, 0.99f, z), kExact);
    }
  }
}

TEST(ContactBoxBox, HoveringBoxGivesSpeculativeFacePoints) {
  // 1 cm above the face with a 2 cm threshold: the four corners, each 0.01 away.
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()),
                             makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0, 1.51f, 0)));
  ASSERT_EQ(r.n, 4u);
  for (PfxUInt32 i = 0; i < r.n; ++i) EXPECT_NEAR(r.c[i].m_distance, 0.01f, kExact);
  EXPECT_EQ(collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeBox(0.5f, 0.5f, 0.5f),
                    pose(PfxVector3(0, 1.53f, 0)))
                .n,
            0u);
}

TEST(ContactBoxBox, OffsetEqualBoxesGiveTheOverlapRectangle) {
  // Two unit boxes, B at (1, 1.95, 0.5): faces overlap over x in [0, 1], z in [-0.5, 1],
  // 0.05 deep at all four corners of that rectangle.
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeBox(1, 1, 1),
                             pose(PfxVector3(1, 1.95f, 0.5f)));
  ASSERT_EQ(r.n, 4u);
  for (const PfxFloat x : {0.0f, 1.0f}) {
    for (const PfxFloat z : {-0.5f, 1.0f}) {
      const PfxContactCandidate& c = r.nearestA(PfxVector3(x, 1, z));
      EXPECT_NEAR(c.m_distance, -0.05f, kExact);
      expectVecNear(c.m_pointA, PfxVector3(x, 1, z), kExact);
    }
  }
}

TEST(ContactBoxBox, YawedBoxOnBoxKeepsItsRotatedCorners) {
  // B (half 0.5) turned 45 degrees about Y: its corners lie at distance 0.5 sqrt2 on the
  // X and Z axes, all inside A's top face; 0.02 deep.
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()),
                             makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0, 1.48f, 0), rotY(PFX_PI / 4)));
  ASSERT_EQ(r.n, 4u);
  const PfxFloat d = 0.5f * kSqrt2;
  for (const PfxVector3& corner : {PfxVector3(d, 1, 0), PfxVector3(-d, 1, 0),
                                   PfxVector3(0, 1, d), PfxVector3(0, 1, -d)}) {
    expectVecNear(r.nearestA(corner).m_pointA, corner, kExact);
    EXPECT_NEAR(r.nearestA(corner).m_distance, -0.02f, kExact);
  }
}

TEST(ContactBoxBox, CrossedEdgesGiveOnePoint) {
  // A turned 45 degrees about Z: its top edge runs along Z at height sqrt2. B turned 45
  // degrees about X: its bottom edge runs along X, sqrt2 below its centre. With B's centre
  // at 2 sqrt2 - 0.1 the edges cross 0.1 deep at (0, sqrt2, 0).
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero(), rotZ(PFX_PI / 4)),
                             makeBox(1, 1, 1),
                             pose(PfxVector3(0, 2 * kSqrt2 - 0.1f, 0), rotX(PFX_PI / 4)));
  expectSingle(r, -0.1f, PfxVector3(0, 1, 0), PfxVector3(0, kSqrt2, 0),
               PfxVector3(0, kSqrt2 - 0.1f, 0), 2e-5f);
}

TEST(ContactBoxBox, DeepAndCoincident) {
  // Coincident unit boxes: every axis overlaps by 2; faces win ties, A's +X face first.
  const Contacts same = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeBox(1, 1, 1),
                                pose(PfxVector3::Zero()));
  ASSERT_EQ(same.n, 4u);
  for (PfxUInt32 i = 0; i < same.n; ++i) {
    EXPECT_NEAR(same.c[i].m_distance, -2, kExact);
    expectVecNear(same.c[i].m_normal, PfxVector3(1, 0, 0), kExact);
  }
  // B (half 0.5) 0.9 deep into the top face: distance -0.9 at its four bottom corners.
  const Contacts deep = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()),
                                makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0, 0.6f, 0)));
  ASSERT_EQ(deep.n, 4u);
  EXPECT_NEAR(deep.deepest().m_distance, -0.9f, kExact);
}

TEST(ContactBoxBox, ZeroSizeBoxOnAFace) {
  // A point-sized box 0.05 above the top face is beyond the threshold; 0.01 above, it is
  // one contact 0.01 away (its four coincident corners count once).
  EXPECT_EQ(collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeBox(0, 0, 0),
                    pose(PfxVector3(0.3f, 1.05f, 0)))
                .n,
            0u);
  const Contacts r = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeBox(0, 0, 0),
                             pose(PfxVector3(0.3f, 1.01f, 0)));
  expectSingle(r, 0.01f, PfxVector3(0, 1, 0), PfxVector3(0.3f, 1, 0), PfxVector3(0.3f, 1.01f, 0),
               kExact);
}

TEST(ContactBoxBox, MatchesTheGeneralPolyhedraRoutine) {
  // Boxes take their own closed-form routine; the same boxes as convex meshes take the
  // general polyhedra routine. Over random sizes, turns and near-touching placements both
  // must give the same contacts.
  std::srand(11);
  const auto uniform = [](PfxFloat lo, PfxFloat hi) {
    return lo + (hi - lo) * PfxFloat(std::rand()) / PfxFloat(RAND_MAX);
  };
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const PfxVector3 halfA{uniform(0.1f, 1), uniform(0.1f, 1), uniform(0.1f, 1)};
    const PfxVector3 halfB{uniform(0.1f, 1), uniform(0.1f, 1), uniform(0.1f, 1)};
    const PfxQuat qa = PfxQuat(PfxVector4::Random()).normalized();
    const PfxQuat qb = PfxQuat(PfxVector4::Random()).normalized();
    // Along a random direction, at a distance between deep overlap and just apart.
    const PfxVector3 direction = PfxVector3::Random().normalized();
    const PfxFloat reach = halfA.norm() + halfB.norm();
    const PfxTransform3 ta = pose(PfxVector3::Random(), qa);
    const PfxTransform3 tb = pose(ta.translation() + direction * uniform(0.3f, 1.0f) * reach, qb);
    const PfxConvexMesh meshA = buildMesh(makeBoxTriangles(halfA.x(), halfA.y(), halfA.z()));
    const PfxConvexMesh meshB = buildMesh(makeBoxTriangles(halfB.x(), halfB.y(), halfB.z()));
    const Contacts boxes = collide(makeBox(halfA.x(), halfA.y(), halfA.z()), ta,
                                   makeBox(halfB.x(), halfB.y(), halfB.z()), tb);
    const Contacts meshes = collide(makeMeshShape(&meshA), ta, makeMeshShape(&meshB), tb);
    SCOPED_TRACE(trial);
    ASSERT_EQ(boxes.n, meshes.n);
    if (boxes.n == 0) continue;
    ++compared;
    const PfxFloat tol = 2e-4f;
    EXPECT_NEAR(boxes.deepest().m_distance, meshes.deepest().m_distance, tol);
    for (PfxUInt32 i = 0; i < boxes.n; ++i) {
      const PfxContactCandidate& twin = meshes.nearestA(boxes.c[i].m_pointA);
      expectVecNear(twin.m_pointA, boxes.c[i].m_pointA, tol);
      expectVecNear(twin.m_pointB, boxes.c[i].m_pointB, tol);
      expectVecNear(twin.m_normal, boxes.c[i].m_normal, tol);
      EXPECT_NEAR(twin.m_distance, boxes.c[i].m_distance, tol);
    }
  }
  // Most placements touch, so the comparison is not empty.
  EXPECT_GT(compared, 200);
}

// ---------------------------------------------------------------- convex meshes

class ContactMesh : public ::testing::Test {
 protected:
  void SetUp() override {
    m_boxMesh = buildMesh(makeBoxTriangles(1, 1, 1));
    m_smallBoxMesh = buildMesh(makeBoxTriangles(0.5f, 0.5f, 0.5f));
    m_tetMesh = buildMesh(makeTetrahedronTriangles());
  }
  PfxConvexMesh m_boxMesh, m_smallBoxMesh, m_tetMesh;
};

TEST_F(ContactMesh, BoxMeshOnBoxMatchesBoxOnBox) {
  // The same configuration as SmallBoxOnBigBoxGivesItsFourCorners, with meshes.
  const PfxShape big = makeMeshShape(&m_boxMesh);
  const PfxShape small = makeMeshShape(&m_smallBoxMesh);
  for (const bool bigIsMesh : {true, false}) {
    const Contacts r = collide(bigIsMesh ? big : makeBox(1, 1, 1), pose(PfxVector3::Zero()),
                               bigIsMesh ? small : small, pose(PfxVector3(0, 1.49f, 0)));
    ASSERT_EQ(r.n, 4u);
    for (PfxUInt32 i = 0; i < r.n; ++i) {
      EXPECT_NEAR(r.c[i].m_distance, -0.01f, kExact);
      EXPECT_NEAR(std::abs(r.c[i].m_pointA.x()), 0.5f, kExact);
      EXPECT_NEAR(std::abs(r.c[i].m_pointA.z()), 0.5f, kExact);
    }
  }
}

TEST_F(ContactMesh, CrossedMeshEdges) {
  // As CrossedEdgesGiveOnePoint, both boxes as meshes.
  const PfxShape box = makeMeshShape(&m_boxMesh);
  const Contacts r = collide(box, pose(PfxVector3::Zero(), rotZ(PFX_PI / 4)), box,
                             pose(PfxVector3(0, 2 * kSqrt2 - 0.1f, 0), rotX(PFX_PI / 4)));
  expectSingle(r, -0.1f, PfxVector3(0, 1, 0), PfxVector3(0, kSqrt2, 0),
               PfxVector3(0, kSqrt2 - 0.1f, 0), 2e-5f);
}

TEST_F(ContactMesh, TetrahedronVertexIntoBoxFace) {
  // The tetrahedron's vertex (1, 1, 1), turned to point down, pokes 0.1 into a box top.
  // Turning (1,1,1)/sqrt3 onto -Y puts the vertex sqrt3 below the tetrahedron's centre.
  const PfxQuat down = PfxQuat::FromTwoVectors(PfxVector3(1, 1, 1).normalized(),
                                                PfxVector3(0, -1, 0));
  const PfxFloat h = std::sqrt(PfxFloat(3));
  const Contacts r = collide(makeBox(2, 1, 2), pose(PfxVector3::Zero()),
                             makeMeshShape(&m_tetMesh), pose(PfxVector3(0, 1 + h - 0.1f, 0), down));
  ASSERT_GE(r.n, 1u);
  EXPECT_NEAR(r.deepest().m_distance, -0.1f, 2e-5f);
  expectVecNear(r.deepest().m_normal, PfxVector3(0, 1, 0), kExact);
  expectVecNear(r.deepest().m_pointB, PfxVector3(0, 0.9f, 0), 2e-5f);
}

TEST_F(ContactMesh, SphereOnTetrahedronFace) {
  // The face opposite (1, 1, 1) has outward normal -(1,1,1)/sqrt3 and lies 1/sqrt3 from
  // the centre. A sphere of radius 0.5 centred 0.4 outside its centroid (-1,-1,-1)/3 is
  // 0.1 deep.
  const PfxVector3 n = -PfxVector3(1, 1, 1).normalized();
  const PfxVector3 onFace = PfxVector3(-1, -1, -1) / 3;
  const Contacts r = collide(makeMeshShape(&m_tetMesh), pose(PfxVector3::Zero()),
                             makeSphere(0.5f), pose(onFace + n * 0.4f));
  expectSingle(r, -0.1f, n, onFace, onFace - n * 0.1f, kIterative);
}

TEST_F(ContactMesh, CapsuleLyingOnMeshBox) {
  // A capsule (half length 0.5, radius 0.25) along X, 0.01 deep on the mesh box's top:
  // both ends x = +-0.5.
  const Contacts r = collide(makeMeshShape(&m_boxMesh), pose(PfxVector3::Zero()),
                             makeCapsule(0.5f, 0.25f), pose(PfxVector3(0, 1.24f, 0)));
  ASSERT_GE(r.n, 2u);
  EXPECT_NEAR(r.deepest().m_distance, -0.01f, kIterative);
  expectVecNear(r.nearestA(PfxVector3(0.5f, 1, 0)).m_pointA, PfxVector3(0.5f, 1, 0), kIterative);
  expectVecNear(r.nearestA(PfxVector3(-0.5f, 1, 0)).m_pointA, PfxVector3(-0.5f, 1, 0),
                kIterative);
}

TEST_F(ContactMesh, CylinderStandingOnMesh) {
  // Cylinder (half length 0.5, radius 0.4) turned upright, its cap 0.01 into the mesh
  // box's top: cap points on the rim, all 0.01 deep.
  const Contacts r = collide(makeMeshShape(&m_boxMesh), pose(PfxVector3::Zero()),
                             makeCylinder(0.5f, 0.4f), pose(PfxVector3(0, 1.49f, 0), rotZ(PFX_PI / 2)));
  ASSERT_GE(r.n, 3u);
  for (PfxUInt32 i = 0; i < r.n; ++i) {
    EXPECT_NEAR(r.c[i].m_distance, -0.01f, kIterative);
    EXPECT_NEAR(r.c[i].m_pointA.y(), 1, kIterative);
    EXPECT_LE(std::hypot(r.c[i].m_pointA.x(), r.c[i].m_pointA.z()), 0.4f + kIterative);
  }
}

// ---------------------------------------------------------------- cylinders (GJK / EPA)

TEST(ContactCylinder, StandingOnABoxGivesCapPoints) {
  // Upright cylinder (axis X turned onto Y), radius 0.5, bottom cap at 0.99 on a box top
  // at 1: every cap point 0.01 deep, on the rim circle of radius 0.5.
  const Contacts r = collide(makeBox(2, 1, 2), pose(PfxVector3::Zero()), makeCylinder(0.5f, 0.5f),
                             pose(PfxVector3(0, 1.49f, 0), rotZ(PFX_PI / 2)));
  ASSERT_GE(r.n, 3u);
  for (PfxUInt32 i = 0; i < r.n; ++i) {
    EXPECT_NEAR(r.c[i].m_distance, -0.01f, kIterative);
    expectVecNear(r.c[i].m_normal, PfxVector3(0, 1, 0), kIterative);
    EXPECT_NEAR(r.c[i].m_pointB.y(), 0.99f, kIterative);
    EXPECT_LE(std::hypot(r.c[i].m_pointB.x(), r.c[i].m_pointB.z()), 0.5f + kIterative);
  }
}

TEST(ContactCylinder, CapOnASmallerBoxIsClippedToTheBox) {
  // A big upright cylinder (radius 2) resting on a box top of half 0.5: the cap covers the
  // face, so the contacts are the box's four top corners, 0.01 deep.
  const Contacts r = collide(makeCylinder(0.5f, 2), pose(PfxVector3(0, 1.49f, 0), rotZ(PFX_PI / 2)),
                             makeBox(0.5f, 1, 0.5f), pose(PfxVector3::Zero()));
  ASSERT_GE(r.n, 4u);
  for (const PfxFloat x : {-0.5f, 0.5f}) {
    for (const PfxFloat z : {-0.5f, 0.5f}) {
      const PfxContactCandidate& c = r.nearestA(PfxVector3(x, 0.99f, z));
      expectVecNear(c.m_pointB, PfxVector3(x, 1, z), kIterative);
      EXPECT_NEAR(c.m_distance, -0.01f, kIterative);
      expectVecNear(c.m_normal, PfxVector3(0, -1, 0), kIterative);
    }
  }
}

TEST(ContactCylinder, LyingOnABoxGivesALine) {
  // Cylinder along X (half length 1, radius 0.5), axis 1.49 high over a box top at 1:
  // a line contact from x = -1 to 1, 0.01 deep.
  const Contacts r = collide(makeBox(2, 1, 2), pose(PfxVector3::Zero()), makeCylinder(1, 0.5f),
                             pose(PfxVector3(0, 1.49f, 0)));
  ASSERT_GE(r.n, 2u);
  EXPECT_NEAR(r.deepest().m_distance, -0.01f, kIterative);
  expectVecNear(r.nearestA(PfxVector3(1, 1, 0)).m_pointA, PfxVector3(1, 1, 0), kIterative);
  expectVecNear(r.nearestA(PfxVector3(-1, 1, 0)).m_pointA, PfxVector3(-1, 1, 0), kIterative);
  for (PfxUInt32 i = 0; i < r.n; ++i) EXPECT_NEAR(r.c[i].m_distance, -0.01f, kIterative);
}

TEST(ContactCylinder, HoveringCylinderGivesSpeculativeCapPoints) {
  // The upright cylinder 0.01 above the box: speculative cap points; 0.05 above: none.
  const Contacts near = collide(makeBox(2, 1, 2), pose(PfxVector3::Zero()),
                                makeCylinder(0.5f, 0.5f),
                                pose(PfxVector3(0, 1.51f, 0), rotZ(PFX_PI / 2)));
  ASSERT_GE(near.n, 3u);
  for (PfxUInt32 i = 0; i < near.n; ++i) EXPECT_NEAR(near.c[i].m_distance, 0.01f, kIterative);
  EXPECT_EQ(collide(makeBox(2, 1, 2), pose(PfxVector3::Zero()), makeCylinder(0.5f, 0.5f),
                    pose(PfxVector3(0, 1.55f, 0), rotZ(PFX_PI / 2)))
                .n,
            0u);
}

// A sphere of `radius` at `centre` against the cylinder along X of half length 1 and radius
// 0.8 at the origin: one contact, its point on the sphere `radius` back from the centre.
void expectSphereOnCylinder(const PfxVector3& centre, PfxFloat radius, PfxFloat distance,
                            const PfxVector3& normal, const PfxVector3& onCylinder) {
  expectSingle(collide(makeCylinder(1, 0.8f), pose(PfxVector3::Zero()), makeSphere(radius),
                       pose(centre)),
               distance, normal, onCylinder, centre - normal * radius, kExact);
}

TEST(ContactCylinder, SphereOnTheSide) {
  // Sphere radius 0.5 at height 1.2: 0.1 deep along +Y.
  expectSphereOnCylinder(PfxVector3(0.3f, 1.2f, 0), 0.5f, -0.1f, PfxVector3(0, 1, 0),
                         PfxVector3(0.3f, 0.8f, 0));
}

TEST(ContactCylinder, SphereOnTheCapAndBeyondTheRim) {
  // Sphere radius 0.3 at (1.2, 0.1, 0): over the +X cap (x = 1), 0.1 deep.
  expectSphereOnCylinder(PfxVector3(1.2f, 0.1f, 0), 0.3f, -0.1f, PfxVector3(1, 0, 0),
                         PfxVector3(1, 0.1f, 0));
  // Beyond the rim: centre (1.3, 1.2, 0) is (0.3, 0.4, 0) from the rim point (1, 0.8, 0),
  // 0.5 away; radius 0.6: 0.1 deep along (0.6, 0.8, 0).
  expectSphereOnCylinder(PfxVector3(1.3f, 1.2f, 0), 0.6f, -0.1f, PfxVector3(0.6f, 0.8f, 0),
                         PfxVector3(1, 0.8f, 0));
}

TEST(ContactCylinder, SphereCentreOnTheSideLeavesAlongTheRadius) {
  // Cylinder along X, radius 0.8, turned 0.3 rad about Z; sphere radius 0.15 whose centre
  // lies on the side at local (0.2, 0.48, 0.64) (0.48² + 0.64² = 0.8²): 0.15 deep along the
  // local radius (0, 0.6, 0.8). EPA tilted this normal by up to 0.02 rad.
  const PfxQuat turn = rotZ(0.3f);
  const PfxVector3 centre = turn * PfxVector3(0.2f, 0.48f, 0.64f);
  const PfxVector3 normal = turn * PfxVector3(0, 0.6f, 0.8f);
  expectSingle(collide(makeCylinder(1, 0.8f), pose(PfxVector3::Zero(), turn), makeSphere(0.15f),
                       pose(centre)),
               -0.15f, normal, centre, centre - normal * 0.15f, kExact);
}

TEST(ContactCylinder, SphereCentreInsideLeavesByTheNearerCapOrSide) {
  // Sphere radius 0.1. Centre (0.9, 0.5, 0): 0.1 from the +X cap, 0.3 from the side: 0.2
  // deep along +X.
  expectSphereOnCylinder(PfxVector3(0.9f, 0.5f, 0), 0.1f, -0.2f, PfxVector3(1, 0, 0),
                         PfxVector3(1, 0.5f, 0));
  // Centre (-0.2, 0, -0.6): 0.2 from the side, 0.8 from the -X cap: 0.3 deep along -Z.
  expectSphereOnCylinder(PfxVector3(-0.2f, 0, -0.6f), 0.1f, -0.3f, PfxVector3(0, 0, -1),
                         PfxVector3(-0.2f, 0, -0.8f));
}

TEST(ContactCylinder, CrossedCylinders) {
  // A along X, B along Z, both radius 0.5, B's axis 0.95 above A's: 0.05 deep at one point.
  const Contacts r = collide(makeCylinder(1, 0.5f), pose(PfxVector3::Zero()),
                             makeCylinder(1, 0.5f), pose(PfxVector3(0, 0.95f, 0), rotY(PFX_PI / 2)));
  expectSingle(r, -0.05f, PfxVector3(0, 1, 0), PfxVector3(0, 0.5f, 0), PfxVector3(0, 0.45f, 0),
               kIterative);
}

TEST(ContactCylinder, ParallelCylindersGiveTheOverlapLine) {
  // Parallel cylinders, B shifted 0.5 along X and 0.95 up: line contact over x in
  // [-0.5, 1], 0.05 deep.
  const Contacts r = collide(makeCylinder(1, 0.5f), pose(PfxVector3::Zero()),
                             makeCylinder(1, 0.5f), pose(PfxVector3(0.5f, 0.95f, 0)));
  ASSERT_GE(r.n, 2u);
  EXPECT_NEAR(r.deepest().m_distance, -0.05f, kIterative);
  expectVecNear(r.nearestA(PfxVector3(-0.5f, 0.5f, 0)).m_pointA, PfxVector3(-0.5f, 0.5f, 0),
                kIterative);
  expectVecNear(r.nearestA(PfxVector3(1, 0.5f, 0)).m_pointA, PfxVector3(1, 0.5f, 0), kIterative);
}

TEST(ContactCylinder, CapsuleLyingAcrossTheSide) {
  // Capsule along Z (radius 0.2) over a cylinder along X (radius 0.5), axis 0.65 high:
  // 0.05 deep at the top of the cylinder.
  const Contacts r = collide(makeCylinder(1, 0.5f), pose(PfxVector3::Zero()), makeCapsule(1, 0.2f),
                             pose(PfxVector3(0, 0.65f, 0), rotY(PFX_PI / 2)));
  expectSingle(r, -0.05f, PfxVector3(0, 1, 0), PfxVector3(0, 0.5f, 0), PfxVector3(0, 0.45f, 0),
               kIterative);
}

TEST(ContactCylinder, CapsuleLyingOnTheCap) {
  // Upright cylinder (cap at y = 0.5, radius 1); a capsule along X (half length 0.5,
  // radius 0.25) lies 0.02 deep on the cap: both ends, x = +-0.5.
  const Contacts r = collide(makeCylinder(0.5f, 1), pose(PfxVector3::Zero(), rotZ(PFX_PI / 2)),
                             makeCapsule(0.5f, 0.25f), pose(PfxVector3(0, 0.73f, 0)));
  ASSERT_GE(r.n, 2u);
  EXPECT_NEAR(r.deepest().m_distance, -0.02f, kIterative);
  expectVecNear(r.nearestA(PfxVector3(0.5f, 0.5f, 0)).m_pointA, PfxVector3(0.5f, 0.5f, 0),
                kIterative);
  expectVecNear(r.nearestA(PfxVector3(-0.5f, 0.5f, 0)).m_pointA, PfxVector3(-0.5f, 0.5f, 0),
                kIterative);
}

TEST(ContactCylinder, CoincidentAndZeroSize) {
  // Coincident identical cylinders: the least overlap is through the side, 2 radii = 1
  // (the caps would need 2 half lengths = 2). The side is curved, so EPA's normal is only
  // known to a few hundredths; it must lie across the axis, not along it.
  const Contacts same = collide(makeCylinder(1, 0.5f), pose(PfxVector3::Zero()),
                                makeCylinder(1, 0.5f), pose(PfxVector3::Zero()));
  ASSERT_GE(same.n, 1u);
  // Every direction across the axis is equally deep here, so EPA's polytope never settles
  // on one: the depth is good to about 1 %.
  EXPECT_NEAR(same.deepest().m_distance, -1, 1e-2f);
  EXPECT_LT(std::abs(same.deepest().m_normal.x()), 0.05f);
  // A cylinder of zero size is a point: 0.1 inside a box top.
  const Contacts point = collide(makeBox(1, 1, 1), pose(PfxVector3::Zero()), makeCylinder(0, 0),
                                 pose(PfxVector3(0.2f, 0.9f, 0)));
  expectSingle(point, -0.1f, PfxVector3(0, 1, 0), PfxVector3(0.2f, 1, 0), PfxVector3(0.2f, 0.9f, 0),
               kIterative);
}

// ---------------------------------------------------------------- symmetry and rotation

struct PairCase {
  const char* name;
  PfxShape a;
  PfxTransform3 ta;
  PfxShape b;
  PfxTransform3 tb;
  PfxFloat tol;
};

std::vector<PairCase> referenceCases(const PfxConvexMesh* boxMesh, const PfxConvexMesh* tetMesh) {
  const PfxQuat tilt = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f, PfxVector3(1, 2, 3).normalized()));
  return {
      {"sphere-sphere", makeSphere(0.5f), pose(PfxVector3::Zero()), makeSphere(0.3f),
       pose(PfxVector3(0.4f, 0.5f, 0.1f)), kExact},
      {"sphere-capsule", makeSphere(0.5f), pose(PfxVector3(0.5f, 0.6f, 0)), makeCapsule(1, 0.2f),
       pose(PfxVector3::Zero(), tilt), kExact},
      {"capsule-capsule", makeCapsule(1, 0.2f), pose(PfxVector3::Zero()), makeCapsule(1, 0.2f),
       pose(PfxVector3(0.2f, 0.3f, 0), rotY(1.0f)), kExact},
      {"sphere-box", makeSphere(0.6f), pose(PfxVector3(1.3f, 1.4f, 0.2f)), makeBox(1, 1, 1),
       pose(PfxVector3::Zero(), tilt), kExact},
      {"capsule-box", makeCapsule(1, 0.25f), pose(PfxVector3(0, 0.74f, 0)), makeBox(2, 0.5f, 2),
       pose(PfxVector3::Zero()), kExact},
      {"box-box", makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0.2f, 1.45f, 0), rotY(0.4f)),
       makeBox(1, 1, 1), pose(PfxVector3::Zero()), kExact},
      {"box-box-edges", makeBox(1, 1, 1), pose(PfxVector3::Zero(), rotZ(PFX_PI / 4)),
       makeBox(1, 1, 1), pose(PfxVector3(0, 2 * kSqrt2 - 0.1f, 0), rotX(PFX_PI / 4)), 2e-5f},
      {"mesh-box", makeMeshShape(boxMesh), pose(PfxVector3(0.3f, 1.9f, 0), tilt), makeBox(1, 1, 1),
       pose(PfxVector3::Zero()), 2e-5f},
      {"mesh-mesh", makeMeshShape(tetMesh), pose(PfxVector3(0.1f, 1.8f, 0.2f), tilt),
       makeMeshShape(boxMesh), pose(PfxVector3::Zero()), 2e-5f},
      {"sphere-cylinder", makeSphere(0.5f), pose(PfxVector3(0.3f, 1.2f, 0.1f)),
       makeCylinder(1, 0.8f), pose(PfxVector3::Zero()), kIterative},
      {"capsule-cylinder", makeCapsule(1, 0.2f), pose(PfxVector3(0, 0.65f, 0), rotY(1.1f)),
       makeCylinder(1, 0.5f), pose(PfxVector3::Zero()), kIterative},
      {"box-cylinder", makeBox(0.5f, 0.5f, 0.5f), pose(PfxVector3(0.2f, 0.95f, 0.1f), tilt),
       makeCylinder(1, 0.5f), pose(PfxVector3::Zero()), kIterative},
      {"cylinder-cylinder", makeCylinder(1, 0.5f), pose(PfxVector3::Zero()), makeCylinder(1, 0.5f),
       pose(PfxVector3(0, 0.95f, 0), rotY(1.2f)), kIterative},
      {"mesh-cylinder", makeMeshShape(tetMesh), pose(PfxVector3(0.1f, 1.3f, 0.2f), tilt),
       makeCylinder(1, 0.5f), pose(PfxVector3::Zero()), kIterative},
      {"sphere-mesh", makeSphere(0.5f), pose(PfxVector3(0.2f, 1.4f, 0.3f)), makeMeshShape(boxMesh),
       pose(PfxVector3::Zero()), kIterative},
      {"capsule-mesh", makeCapsule(0.5f, 0.25f), pose(PfxVector3(0.2f, 1.2f, 0.1f), tilt),
       makeMeshShape(boxMesh), pose(PfxVector3::Zero()), kIterative},
  };
}

TEST_F(ContactMesh, SwappingShapesFlipsNormalsAndSwapsPoints) {
  for (const PairCase& c : referenceCases(&m_boxMesh, &m_tetMesh)) {
    SCOPED_TRACE(c.name);
    expectSymmetric(c.a, c.ta, c.b, c.tb, c.tol);
  }
}

TEST_F(ContactMesh, RotatingTheWholeSceneRotatesTheAnswer) {
  std::srand(7);
  for (const PairCase& c : referenceCases(&m_boxMesh, &m_tetMesh)) {
    SCOPED_TRACE(c.name);
    const Contacts base = collide(c.a, c.ta, c.b, c.tb);
    ASSERT_GT(base.n, 0u);
    for (int trial = 0; trial < 5; ++trial) {
      const PfxQuat q = PfxQuat(PfxVector4::Random()).normalized();
      const PfxTransform3 world = pose(PfxVector3::Random(), q);
      const Contacts moved = collide(c.a, world * c.ta, c.b, world * c.tb);
      ASSERT_EQ(moved.n, base.n);
      const PfxFloat tol = c.tol * 5;
      EXPECT_NEAR(moved.deepest().m_distance, base.deepest().m_distance, tol);
      expectVecNear(moved.deepest().m_normal, world.linear() * base.deepest().m_normal, tol);
      for (PfxUInt32 i = 0; i < base.n; ++i) {
        const PfxVector3 expectedA = world * base.c[i].m_pointA;
        const PfxContactCandidate& twin = moved.nearestA(expectedA);
        expectVecNear(twin.m_pointA, expectedA, tol);
        expectVecNear(twin.m_pointB, world * base.c[i].m_pointB, tol);
      }
    }
  }
}

// A thin cylinder lying on a 100 m slab (the pose where it was caught): the slab's far side
// faces must not stand in for its top. The whole slab gave no contact 1 and 2 cm deep and,
// a millimetre lower, nine points 50 m deep along a side face.
TEST(ContactCylinder, SmallCylinderOnAHugeSlabMeetsItsTop) {
  const PfxShape slab = makeBox(50, 0.5f, 50);
  const PfxTransform3 slabPose = pose(PfxVector3(0, -0.5f, 0));
  const PfxShape cylinder = makeCylinder(0.143f, 0.028f);
  const PfxQuat lying = PfxQuat(0.0162796583f, 0.693896532f, -0.0176124498f, 0.719675303f).normalized();
  const PfxVector3 axis = lying * PfxVector3::UnitX();
  const PfxFloat reachBelowCentre =
      std::abs(axis.y()) * 0.143f + 0.028f * std::sqrt(1 - axis.y() * axis.y());
  for (const PfxFloat height : {-0.0017f, 0.0f, 0.01f, 0.02f, 0.03f}) {
    SCOPED_TRACE(height);
    const PfxFloat trueDistance = height - reachBelowCentre;
    const Contacts r = collide(slab, slabPose, cylinder, pose(PfxVector3(-0.06f, height, -0.07f), lying));
    ASSERT_GE(r.n, 1u);
    PfxFloat deepest = 1;
    for (PfxUInt32 i = 0; i < r.n; ++i) {
      EXPECT_GT(r.c[i].m_normal.y(), 0.99f);
      deepest = std::min(deepest, r.c[i].m_distance);
    }
    EXPECT_NEAR(deepest, trueDistance, kIterative);
  }
}

// A stretched tetrahedron 3.77 cm from a cylinder's rim (the pose where the cross-check
// caught it, bits included; the reference's separating direction bounds the gap from below
// at 0.0377 m). GJK's last support point lay a tenth of a millimetre from the previous
// one, the tetrahedron they made was so flat that the origin seemed inside it, and the
// pair was reported as overlapping by 2 cm along a side of the cylinder.
TEST(ContactCylinder, MeshApartFromTheRimIsNoOverlap) {
  TriangleList tetrahedron = makeTetrahedronTriangles();
  tetrahedron.vertices = {0x1.c9f53ap-5f,  0x1.0e15b6p-3f,  0x1.baaa6ep-5f,  0x1.c9f53ap-5f,
                          -0x1.0e15b6p-3f, -0x1.baaa6ep-5f, -0x1.c9f53ap-5f, 0x1.0e15b6p-3f,
                          -0x1.baaa6ep-5f, -0x1.c9f53ap-5f, -0x1.0e15b6p-3f, 0x1.baaa6ep-5f};
  const PfxConvexMesh mesh = buildMesh(tetrahedron);
  const PfxQuat meshTurn(-0x1.5e53ccp-4f, 0x1.824ee4p-1f, -0x1.628d5cp-2f, -0x1.1a12d2p-1f);
  const PfxQuat cylinderTurn(0x1.6a35cep-3f, 0x1.a82228p-1f, -0x1.1016b2p-1f, -0x1.326538p-7f);
  const PfxTransform3 meshPose =
      pose(PfxVector3(-0.19248721f, -0.226248652f, -0.041954983f), meshTurn.normalized());
  const PfxTransform3 cylinderPose =
      pose(PfxVector3(-0.672648013f, -0.194538102f, -0.381341666f), cylinderTurn.normalized());
  const PfxShape cylinder = makeCylinder(0.198734865f, 0.490582705f);
  for (const bool meshFirst : {true, false}) {
    SCOPED_TRACE(meshFirst);
    const Contacts r = meshFirst ? collide(makeMeshShape(&mesh), meshPose, cylinder, cylinderPose, 0.05f)
                                 : collide(cylinder, cylinderPose, makeMeshShape(&mesh), meshPose, 0.05f);
    ASSERT_GE(r.n, 1u);
    EXPECT_NEAR(r.deepest().m_distance, 0.0377f, 2e-4f);
  }
}

}  // namespace
}  // namespace pfx_test
