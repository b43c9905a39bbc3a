#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "pfx/base_level/collision/pfx_contact_manifold.h"

using namespace pfx;

namespace {

PfxContactCandidate makeCandidate(const PfxVector3& pointA, PfxFloat distance,
                                  const PfxVector3& normal = PfxVector3(0, 0, 1),
                                  PfxUInt8 shapeIdA = 0, PfxUInt8 shapeIdB = 0) {
  PfxContactCandidate c;
  c.m_normal = normal;
  c.m_pointA = pointA;
  c.m_pointB = pointA + normal * distance;
  c.m_distance = distance;
  c.m_shapeIdA = shapeIdA;
  c.m_shapeIdB = shapeIdB;
  return c;
}

std::vector<PfxUInt32> sortedChoice(const PfxUInt32* chosen, PfxUInt32 n) {
  std::vector<PfxUInt32> v(chosen, chosen + n);
  std::sort(v.begin(), v.end());
  return v;
}

PfxTransform3 translation(PfxFloat x, PfxFloat y, PfxFloat z) {
  return pfxMakeTransform(PfxQuat::Identity(), PfxVector3(x, y, z));
}

}  // namespace

TEST(ReduceContactCandidates, FourOrFewerAreAllKeptInOrder) {
  PfxContactCandidate c[3] = {makeCandidate({0, 0, 0}, -0.1f), makeCandidate({1, 0, 0}, -0.3f),
                              makeCandidate({0, 1, 0}, -0.2f)};
  PfxUInt32 chosen[4];
  ASSERT_EQ(pfxReduceContactCandidates(c, 3, chosen), 3u);
  EXPECT_EQ(chosen[0], 0u);
  EXPECT_EQ(chosen[1], 1u);
  EXPECT_EQ(chosen[2], 2u);
  EXPECT_EQ(pfxReduceContactCandidates(c, 0, chosen), 0u);
  EXPECT_EQ(pfxReduceContactCandidates(nullptr, 3, chosen), 0u);
}

TEST(ReduceContactCandidates, SquareCornersAndMidpointsKeepTheCorners) {
  // Corners (indices 1,3,5,7) and edge midpoints (0,2,4,6) of the square [-1,1]^2, the
  // corner 5 slightly deeper. The best quadrilateral through corner 5 is the square itself
  // (area 4); any midpoint would cut a corner triangle off it.
  const PfxVector3 p[8] = {{0, -1, 0}, {1, -1, 0}, {1, 0, 0}, {1, 1, 0},
                           {0, 1, 0},  {-1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  PfxContactCandidate c[8];
  for (int i = 0; i < 8; ++i) c[i] = makeCandidate(p[i], i == 5 ? -0.02f : -0.01f);
  PfxUInt32 chosen[4];
  ASSERT_EQ(pfxReduceContactCandidates(c, 8, chosen), 4u);
  EXPECT_EQ(chosen[0], 5u);
  EXPECT_EQ(sortedChoice(chosen, 4), (std::vector<PfxUInt32>{1, 3, 5, 7}));
}

TEST(ReduceContactCandidates, DeepestIsKeptEvenInsideThePolygon) {
  // A deep point in the middle of a square of shallow ones: it must stay, and the other
  // three span the largest triangle with it, which uses two opposite corners (area 1 with
  // the centre; a third corner adds area 1 more).
  PfxContactCandidate c[5] = {makeCandidate({1, 1, 0}, -0.01f), makeCandidate({-1, 1, 0}, -0.01f),
                              makeCandidate({-1, -1, 0}, -0.01f), makeCandidate({1, -1, 0}, -0.01f),
                              makeCandidate({0, 0, 0}, -0.5f)};
  PfxUInt32 chosen[4];
  ASSERT_EQ(pfxReduceContactCandidates(c, 5, chosen), 4u);
  EXPECT_EQ(chosen[0], 4u);
  // Farthest from the centre: all corners tie, the lowest index wins (0). Largest triangle
  // with the centre and corner 0 (1,1): corners 1 (-1,1) and 3 (1,-1) tie at area 1, 1 wins.
  // Hull of centre, (1,1), (-1,1) with corner 2 (-1,-1) is the triangle of the three corners
  // (the centre lies on its edge), area 2; with corner 3 it is two unit triangles, area 2:
  // tie again, 2 wins.
  EXPECT_EQ(chosen[1], 0u);
  EXPECT_EQ(chosen[2], 1u);
  EXPECT_EQ(chosen[3], 2u);
}

TEST(ReduceContactCandidates, DeepestTieGoesToLowestIndexAndIsDeterministic) {
  PfxContactCandidate c[6];
  for (int i = 0; i < 6; ++i) {
    c[i] = makeCandidate(PfxVector3(std::cos(i * PFX_PI / 3), std::sin(i * PFX_PI / 3), 0), -0.1f);
  }
  PfxUInt32 first[4], second[4];
  ASSERT_EQ(pfxReduceContactCandidates(c, 6, first), 4u);
  ASSERT_EQ(pfxReduceContactCandidates(c, 6, second), 4u);
  EXPECT_EQ(first[0], 0u);
  EXPECT_EQ(first[1], 3u);  // diametrically opposite
  for (int i = 0; i < 4; ++i) EXPECT_EQ(first[i], second[i]);
}

TEST(ReduceContactCandidates, LineContactKeepsTwoPoints) {
  // Five collinear points (a cylinder lying on a face): after the two ends no point adds
  // area, so no redundant point is kept.
  PfxContactCandidate c[5];
  for (int i = 0; i < 5; ++i) c[i] = makeCandidate(PfxVector3(PfxFloat(i), 0, 0), -0.01f);
  c[2].m_distance = -0.05f;
  PfxUInt32 chosen[4];
  ASSERT_EQ(pfxReduceContactCandidates(c, 5, chosen), 2u);
  EXPECT_EQ(chosen[0], 2u);
  EXPECT_EQ(chosen[1], 0u);  // ends at distance 2 tie; lower index
}

TEST(ReduceContactCandidates, AreaIsMeasuredInTheContactPlane) {
  // Points spread along the normal (z) but not across it cover no area.
  PfxContactCandidate c[5];
  for (int i = 0; i < 5; ++i) c[i] = makeCandidate(PfxVector3(0, 0, PfxFloat(i)), -0.01f);
  PfxUInt32 chosen[4];
  EXPECT_EQ(pfxReduceContactCandidates(c, 5, chosen), 1u);
}

TEST(ContactManifold, ResetClearsEverything) {
  PfxContactManifold m;
  m.reset(3, 7);
  EXPECT_EQ(m.getRigidBodyIdA(), 3u);
  EXPECT_EQ(m.getRigidBodyIdB(), 7u);
  EXPECT_EQ(m.getNumContacts(), 0u);
  EXPECT_EQ(m.getCompositeFriction(), 0.0f);
  EXPECT_EQ(m.getPenetrationDepth(), 0.0f);
}

TEST(ContactManifold, UpdateStoresLocalAnchorsAndInitialisesPoints) {
  PfxContactManifold m;
  m.reset(0, 1);
  // A at (1,0,0) turned 90° about z; B at (0,0,2). World point (1,1,0) is (1,0,0) in A's
  // frame (A's local x maps to world y). pointB = pointA + normal * distance = (1,1,0.1),
  // which is (1,1,-1.9) in B's frame.
  const PfxTransform3 ta = pfxMakeTransform(
      PfxQuat(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ())), PfxVector3(1, 0, 0));
  const PfxTransform3 tb = translation(0, 0, 2);
  PfxContactCandidate c = makeCandidate({1, 1, 0}, -0.1f, PfxVector3(0, 0, -1), 2, 5);
  m.update(&c, 1, ta, tb, 0.01f);
  ASSERT_EQ(m.getNumContacts(), 1u);
  const PfxContactPoint& p = m.getContactPoint(0);
  EXPECT_TRUE(p.m_localPointA.isApprox(PfxVector3(1, 0, 0), 1e-5f));
  EXPECT_TRUE(p.m_localPointB.isApprox(PfxVector3(1, 1, -1.9f), 1e-5f));
  EXPECT_FLOAT_EQ(p.m_distance, -0.1f);
  EXPECT_EQ(p.getNormal(), PfxVector3(0, 0, -1));
  EXPECT_EQ(p.m_shapeIdA, 2);
  EXPECT_EQ(p.m_shapeIdB, 5);
  EXPECT_EQ(p.m_duration, 0u);
  EXPECT_EQ(p.m_maxImpulse, 0.0f);
  for (int row = 0; row < 3; ++row) EXPECT_EQ(p.m_constraintRow[row].m_accumImpulse, 0.0f);
  // Friction directions complete the normal to an orthonormal basis.
  EXPECT_NEAR(p.m_constraintRow[1].m_normal.dot(p.getNormal()), 0, 1e-6f);
  EXPECT_NEAR(p.m_constraintRow[2].m_normal.dot(p.getNormal()), 0, 1e-6f);
  EXPECT_NEAR(p.m_constraintRow[1].m_normal.norm(), 1, 1e-6f);
  EXPECT_FLOAT_EQ(m.getPenetrationDepth(), 0.1f);
}

TEST(ContactManifold, WarmStartInheritsImpulsesOfNearbyPoints) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate first[2] = {makeCandidate({0, 0, 0}, -0.01f),
                                  makeCandidate({1, 0, 0}, -0.01f)};
  m.update(first, 2, identity, identity, 0.01f);
  for (int row = 0; row < 3; ++row) {
    m.getContactPoint(0).m_constraintRow[row].m_accumImpulse = 1.0f + row;
    m.getContactPoint(1).m_constraintRow[row].m_accumImpulse = 10.0f + row;
  }
  m.getContactPoint(0).m_duration = 4;

  // Point near the old point 0 (moved 0.05 < 0.1), one new far away, and one near old
  // point 1 but on another shape of the compound.
  PfxContactCandidate second[3] = {makeCandidate({5, 0, 0}, -0.01f),
                                   makeCandidate({0.05f, 0, 0}, -0.01f),
                                   makeCandidate({1, 0, 0}, -0.01f, PfxVector3(0, 0, 1), 1, 0)};
  m.update(second, 3, identity, identity, 0.01f);
  ASSERT_EQ(m.getNumContacts(), 3u);
  const PfxContactPoint& far = m.getContactPoint(0);
  const PfxContactPoint& near = m.getContactPoint(1);
  const PfxContactPoint& otherShape = m.getContactPoint(2);
  for (int row = 0; row < 3; ++row) {
    EXPECT_EQ(far.m_constraintRow[row].m_accumImpulse, 0.0f);
    EXPECT_EQ(near.m_constraintRow[row].m_accumImpulse, 1.0f + row);
    EXPECT_EQ(otherShape.m_constraintRow[row].m_accumImpulse, 0.0f);
  }
  EXPECT_EQ(near.m_duration, 5u);
  EXPECT_EQ(far.m_duration, 0u);
  EXPECT_EQ(otherShape.m_duration, 0u);
}

TEST(ContactManifold, EachOldPointIsInheritedOnceClosestFirst) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate old = makeCandidate({0, 0, 0}, -0.01f);
  m.update(&old, 1, identity, identity, 1.0f);
  m.getContactPoint(0).m_constraintRow[0].m_accumImpulse = 7.0f;

  // Both new points are within reach of the one old point; the closer one (index 1) takes it.
  PfxContactCandidate next[2] = {makeCandidate({0.2f, 0, 0}, -0.01f),
                                 makeCandidate({0.1f, 0, 0}, -0.01f)};
  m.update(next, 2, identity, identity, 1.0f);
  EXPECT_EQ(m.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 0.0f);
  EXPECT_EQ(m.getContactPoint(1).m_constraintRow[0].m_accumImpulse, 7.0f);
  EXPECT_EQ(m.getContactPoint(1).m_duration, 1u);
}

TEST(ContactManifold, ZeroMatchDistanceNeverInherits) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate c = makeCandidate({0, 0, 0}, -0.01f);
  m.update(&c, 1, identity, identity, 0.0f);
  m.getContactPoint(0).m_constraintRow[0].m_accumImpulse = 3.0f;
  m.getContactPoint(0).m_duration = 9;
  m.update(&c, 1, identity, identity, 0.0f);  // exactly the same point
  EXPECT_EQ(m.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 0.0f);
  EXPECT_EQ(m.getContactPoint(0).m_duration, 0u);
}

TEST(ContactManifold, UpdateMatchesInBodyFrameNotWorld) {
  // Both bodies move 10 units together: the anchor has not moved in A's frame, so the
  // impulse carries over even though the world point moved far.
  PfxContactManifold m;
  m.reset(0, 1);
  PfxContactCandidate c = makeCandidate({0, 0, 0}, -0.01f);
  m.update(&c, 1, translation(0, 0, -1), translation(0, 0, 1), 1e-4f);
  m.getContactPoint(0).m_constraintRow[0].m_accumImpulse = 2.0f;
  PfxContactCandidate moved = makeCandidate({10, 0, 0}, -0.01f);
  m.update(&moved, 1, translation(10, 0, -1), translation(10, 0, 1), 1e-4f);
  EXPECT_EQ(m.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 2.0f);
}

TEST(ContactManifold, RefreshRecomputesDistanceAndDropsBrokenPoints) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate c[4] = {makeCandidate({0, 0, 0}, -0.01f), makeCandidate({1, 0, 0}, -0.01f),
                              makeCandidate({1, 1, 0}, -0.01f), makeCandidate({0, 1, 0}, -0.01f)};
  m.update(c, 4, identity, identity, 0.0f);

  // B rises by 0.015 along the normal: distance -0.01 + 0.015 = 0.005 <= 0.02, all stay.
  m.refresh(identity, translation(0, 0, 0.015f), 0.02f);
  ASSERT_EQ(m.getNumContacts(), 4u);
  for (PfxUInt32 i = 0; i < 4; ++i) EXPECT_NEAR(m.getContactPoint(i).m_distance, 0.005f, 1e-6f);

  // B rises to 0.04: distance 0.03 > 0.02, all break.
  PfxContactManifold lifted = m;
  lifted.refresh(identity, translation(0, 0, 0.04f), 0.02f);
  EXPECT_EQ(lifted.getNumContacts(), 0u);

  // B turns 90° about z around the origin: the anchor at the origin stays, the others slide
  // sideways by 1 or more and break.
  const PfxTransform3 turned = pfxMakeTransform(
      PfxQuat(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ())), PfxVector3::Zero());
  PfxContactManifold slid = m;
  slid.refresh(identity, turned, 0.02f);
  ASSERT_EQ(slid.getNumContacts(), 1u);
  EXPECT_TRUE(slid.getContactPoint(0).m_localPointA.isZero());
}

TEST(ContactManifold, RefreshKeepsTheOrderOfSurvivors) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate c[3] = {makeCandidate({0, 0, 0}, -0.01f), makeCandidate({1, 0, 0}, -0.01f),
                              makeCandidate({2, 0, 0}, -0.01f)};
  m.update(c, 3, identity, identity, 0.0f);
  // Tilt B about the y axis through x = 2 by asin(0.02): B's anchors lift by 0.02 per unit
  // of distance from the pivot, so distances become 0.03 (x = 0, breaks), 0.01 (x = 1) and
  // -0.01 (x = 2), up to cos(angle) ~ 0.9998; the sideways slip stays below 0.001.
  const PfxFloat angle = std::asin(0.02f);
  const PfxTransform3 tilt = translation(2, 0, 0) *
                             PfxTransform3(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3::UnitY())) *
                             translation(-2, 0, 0);
  m.refresh(identity, tilt, 0.02f);
  ASSERT_EQ(m.getNumContacts(), 2u);
  EXPECT_NEAR(m.getContactPoint(0).m_localPointA.x(), 1.0f, 1e-6f);
  EXPECT_NEAR(m.getContactPoint(1).m_localPointA.x(), 2.0f, 1e-6f);
}

TEST(ContactManifold, RemoveContactPointKeepsOrder) {
  PfxContactManifold m;
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  PfxContactCandidate c[3] = {makeCandidate({0, 0, 0}, -0.01f), makeCandidate({1, 0, 0}, -0.03f),
                              makeCandidate({2, 0, 0}, -0.02f)};
  m.update(c, 3, identity, identity, 0.0f);
  m.removeContactPoint(7);  // out of range: nothing happens
  ASSERT_EQ(m.getNumContacts(), 3u);
  m.removeContactPoint(0);
  ASSERT_EQ(m.getNumContacts(), 2u);
  EXPECT_EQ(m.getContactPoint(0).m_localPointA.x(), 1.0f);
  EXPECT_EQ(m.getContactPoint(1).m_localPointA.x(), 2.0f);
  EXPECT_FLOAT_EQ(m.getPenetrationDepth(), 0.03f);
  m.clearContacts();
  EXPECT_EQ(m.getPenetrationDepth(), 0.0f);
}

TEST(ContactManifold, SpeculativePointsHaveNoPenetration) {
  PfxContactManifold m;
  m.reset(0, 1);
  PfxContactCandidate c = makeCandidate({0, 0, 0}, 0.05f);
  m.update(&c, 1, PfxTransform3::Identity(), PfxTransform3::Identity(), 0.0f);
  EXPECT_EQ(m.getPenetrationDepth(), 0.0f);
}

// A manifold keeps its points in room given to it (PfxWorld's pools); when the points found
// do not fit, it is left as it was and says how many there were.
TEST(ContactManifold, UpdateThatDoesNotFitLeavesTheManifoldAsItWas) {
  PfxContactPoint room[1];
  PfxContactManifold m(room, 1);
  EXPECT_EQ(m.getCapacity(), 1u);
  m.reset(0, 1);
  const PfxTransform3 identity = PfxTransform3::Identity();
  const PfxContactCandidate one = makeCandidate({0, 0, 0}, -0.01f);
  EXPECT_EQ(m.update(&one, 1, identity, identity, 0.0004f), 1u);
  ASSERT_EQ(m.getNumContacts(), 1u);
  EXPECT_EQ(&m.getContactPoint(0), &room[0]);
  m.getContactPoint(0).m_constraintRow[0].m_accumImpulse = 2;

  const PfxContactCandidate three[3] = {makeCandidate({0, 0, 0}, -0.02f),
                                        makeCandidate({1, 0, 0}, -0.02f),
                                        makeCandidate({0, 1, 0}, -0.02f)};
  EXPECT_EQ(m.update(three, 3, identity, identity, 0.0004f), 3u);
  ASSERT_EQ(m.getNumContacts(), 1u);
  EXPECT_EQ(m.getContactPoint(0).m_distance, -0.01f);
  EXPECT_EQ(m.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 2.0f);

  // Given room for four, the same update fits and the old point's impulse carries over.
  PfxContactPoint larger[PFX_NUM_CONTACTS_PER_MANIFOLD];
  m.moveContactPoints(larger, PFX_NUM_CONTACTS_PER_MANIFOLD);
  EXPECT_EQ(m.getCapacity(), PFX_NUM_CONTACTS_PER_MANIFOLD);
  EXPECT_EQ(m.update(three, 3, identity, identity, 0.0004f), 3u);
  ASSERT_EQ(m.getNumContacts(), 3u);
  EXPECT_EQ(&m.getContactPoint(0), &larger[0]);
  EXPECT_EQ(m.getContactPoint(0).m_constraintRow[0].m_accumImpulse, 2.0f);

  PfxContactManifold none(nullptr, 0);
  EXPECT_EQ(none.getCapacity(), 0u);
  EXPECT_EQ(none.update(&one, 1, identity, identity, 0.0004f), 1u);
  EXPECT_EQ(none.getNumContacts(), 0u);
}

TEST(ContactManifold, CopyHasRoomOfItsOwn) {
  PfxContactPoint room[1];
  PfxContactManifold m(room, 1);
  m.reset(2, 5);
  const PfxTransform3 identity = PfxTransform3::Identity();
  const PfxContactCandidate one = makeCandidate({0, 0, 0}, -0.01f);
  m.update(&one, 1, identity, identity, 0);
  PfxContactManifold copy = m;
  EXPECT_NE(copy.getContactPoints(), m.getContactPoints());
  EXPECT_EQ(copy.getCapacity(), PFX_NUM_CONTACTS_PER_MANIFOLD);
  EXPECT_EQ(copy.getRigidBodyIdB(), 5u);
  ASSERT_EQ(copy.getNumContacts(), 1u);
  copy.getContactPoint(0).m_distance = 1;
  EXPECT_EQ(m.getContactPoint(0).m_distance, -0.01f);
  // Assigned, a manifold keeps its room when the points fit, and takes its own when not.
  PfxContactManifold four;
  four.reset(0, 0);
  const PfxContactCandidate three[3] = {makeCandidate({0, 0, 0}, -0.02f),
                                        makeCandidate({1, 0, 0}, -0.02f),
                                        makeCandidate({0, 1, 0}, -0.02f)};
  four.update(three, 3, identity, identity, 0);
  m = copy;
  EXPECT_EQ(m.getContactPoints(), room);
  EXPECT_EQ(m.getContactPoint(0).m_distance, 1.0f);
  m = four;
  EXPECT_EQ(m.getCapacity(), PFX_NUM_CONTACTS_PER_MANIFOLD);
  EXPECT_EQ(m.getNumContacts(), 3u);
  EXPECT_EQ(room[0].m_distance, 1.0f) << "the room it had is left alone";
}

// A manifold without room (the world's shared empty one) is reset, copied and assigned
// without handing a null pointer to memset or memcpy (UndefinedBehaviorSanitizer checks
// this in the sanitizer build).
TEST(ContactManifold, ManifoldWithoutRoomResetsCopiesAndMoves) {
  PfxContactManifold none(nullptr, 0);
  none.reset(3, 4);
  EXPECT_EQ(none.getContactPoints(), nullptr);
  EXPECT_EQ(none.getRigidBodyIdB(), 4u);
  PfxContactManifold alsoNone(nullptr, 0);
  alsoNone = none;
  EXPECT_EQ(alsoNone.getContactPoints(), nullptr) << "no points to copy, so no room taken";
  EXPECT_EQ(alsoNone.getRigidBodyIdA(), 3u);
  PfxContactManifold copy = none;
  EXPECT_EQ(copy.getNumContacts(), 0u);
  EXPECT_EQ(copy.getCapacity(), PFX_NUM_CONTACTS_PER_MANIFOLD);
  PfxContactManifold moved = std::move(alsoNone);
  EXPECT_EQ(moved.getCapacity(), 0u);
  moved.moveContactPoints(nullptr, 0);
  EXPECT_EQ(moved.getNumContacts(), 0u);
}
