// Helpers for the narrow-phase tests: shape makers, one call that runs a pair, and
// checks that every candidate keeps the conventions of PfxContactCandidate.
#pragma once

#include <gtest/gtest.h>

#include <cmath>

#include "pfx/base_level/collision/pfx_contact_shapes.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx_test_meshes.h"

namespace pfx_test {

using namespace pfx;

inline PfxShape makeSphere(PfxFloat r) {
  PfxShape s;
  s.reset();
  s.setSphere(PfxSphere(r));
  return s;
}
inline PfxShape makeBox(PfxFloat hx, PfxFloat hy, PfxFloat hz) {
  PfxShape s;
  s.reset();
  s.setBox(PfxBox(hx, hy, hz));
  return s;
}
inline PfxShape makeCapsule(PfxFloat halfLen, PfxFloat r) {
  PfxShape s;
  s.reset();
  s.setCapsule(PfxCapsule(halfLen, r));
  return s;
}
inline PfxShape makeCylinder(PfxFloat halfLen, PfxFloat r) {
  PfxShape s;
  s.reset();
  s.setCylinder(PfxCylinder(halfLen, r));
  return s;
}
inline PfxShape makeMeshShape(const PfxConvexMesh* mesh) {
  PfxShape s;
  s.reset();
  s.setConvexMesh(mesh);
  return s;
}
inline PfxConvexMesh buildMesh(const TriangleList& tris) {
  PfxConvexMesh mesh;
  EXPECT_EQ(pfxCreateConvexMesh(mesh, tris.vertices.data(), tris.numVertices(),
                                tris.indices.data(), tris.numIndices()),
            PFX_OK);
  return mesh;
}

inline PfxTransform3 pose(const PfxVector3& p, const PfxQuat& q = PfxQuat::Identity()) {
  return pfxMakeTransform(q, p);
}
inline PfxQuat rotX(PfxFloat a) { return PfxQuat(Eigen::AngleAxis<PfxFloat>(a, PfxVector3::UnitX())); }
inline PfxQuat rotY(PfxFloat a) { return PfxQuat(Eigen::AngleAxis<PfxFloat>(a, PfxVector3::UnitY())); }
inline PfxQuat rotZ(PfxFloat a) { return PfxQuat(Eigen::AngleAxis<PfxFloat>(a, PfxVector3::UnitZ())); }

struct Contacts {
  PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
  PfxUInt32 n = 0;

  const PfxContactCandidate& deepest() const {
    PfxUInt32 best = 0;
    for (PfxUInt32 i = 1; i < n; ++i) {
      if (c[i].m_distance < c[best].m_distance) best = i;
    }
    return c[best];
  }
  // The candidate whose point on A is nearest `p`.
  const PfxContactCandidate& nearestA(const PfxVector3& p) const {
    PfxUInt32 best = 0;
    for (PfxUInt32 i = 1; i < n; ++i) {
      if ((c[i].m_pointA - p).norm() < (c[best].m_pointA - p).norm()) best = i;
    }
    return c[best];
  }
};

// Every candidate: finite, unit normal, distance equal to the gap along the normal, and
// within the threshold.
inline void expectWellFormed(const Contacts& r, PfxFloat threshold, PfxFloat tol = 1e-4f) {
  ASSERT_LE(r.n, PFX_MAX_CONTACT_CANDIDATES);
  for (PfxUInt32 i = 0; i < r.n; ++i) {
    const PfxContactCandidate& c = r.c[i];
    ASSERT_TRUE(pfxIsFinite(c.m_normal) && pfxIsFinite(c.m_pointA) && pfxIsFinite(c.m_pointB) &&
                pfxIsFinite(c.m_distance));
    EXPECT_NEAR(c.m_normal.norm(), 1, 1e-4);
    EXPECT_NEAR(c.m_distance, (c.m_pointB - c.m_pointA).dot(c.m_normal), tol);
    EXPECT_LT(c.m_distance, threshold);
  }
}

inline Contacts collide(const PfxShape& a, const PfxTransform3& ta, const PfxShape& b,
                        const PfxTransform3& tb, PfxFloat threshold = 0.02f) {
  Contacts r;
  r.n = pfxContactConvexShapes(a, ta, b, tb, threshold, r.c, PFX_MAX_CONTACT_CANDIDATES);
  expectWellFormed(r, threshold);
  return r;
}

inline void expectVecNear(const PfxVector3& actual, const PfxVector3& expected, PfxFloat tol) {
  EXPECT_NEAR(actual[0], expected[0], tol) << actual.transpose() << " vs " << expected.transpose();
  EXPECT_NEAR(actual[1], expected[1], tol) << actual.transpose() << " vs " << expected.transpose();
  EXPECT_NEAR(actual[2], expected[2], tol) << actual.transpose() << " vs " << expected.transpose();
}

// Expects one candidate with the given answer.
inline void expectSingle(const Contacts& r, PfxFloat distance, const PfxVector3& normal,
                         const PfxVector3& pointA, const PfxVector3& pointB, PfxFloat tol) {
  ASSERT_EQ(r.n, 1u);
  EXPECT_NEAR(r.c[0].m_distance, distance, tol);
  expectVecNear(r.c[0].m_normal, normal, tol);
  expectVecNear(r.c[0].m_pointA, pointA, tol);
  expectVecNear(r.c[0].m_pointB, pointB, tol);
}

// Swapping A and B must flip every normal and swap the points (same set of contacts).
inline void expectSymmetric(const PfxShape& a, const PfxTransform3& ta, const PfxShape& b,
                            const PfxTransform3& tb, PfxFloat tol, PfxFloat threshold = 0.02f) {
  const Contacts ab = collide(a, ta, b, tb, threshold);
  const Contacts ba = collide(b, tb, a, ta, threshold);
  ASSERT_GT(ab.n, 0u);
  ASSERT_GT(ba.n, 0u);
  EXPECT_NEAR(ab.deepest().m_distance, ba.deepest().m_distance, tol);
  expectVecNear(ab.deepest().m_normal, -ba.deepest().m_normal, tol);
  // Every contact of A-B has a mirrored twin in B-A.
  for (PfxUInt32 i = 0; i < ab.n; ++i) {
    const PfxContactCandidate& twin = ba.nearestA(ab.c[i].m_pointB);
    expectVecNear(twin.m_pointA, ab.c[i].m_pointB, tol);
    expectVecNear(twin.m_pointB, ab.c[i].m_pointA, tol);
    EXPECT_NEAR(twin.m_distance, ab.c[i].m_distance, tol);
  }
}

}  // namespace pfx_test
