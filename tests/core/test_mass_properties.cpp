#include <gtest/gtest.h>

#include <cmath>

#include "pfx/base_level/collision/pfx_mass_properties.h"
#include "pfx/base_level/collision/pfx_shape.h"
#include "pfx_test_meshes.h"

using namespace pfx;

namespace {

PfxMatrix3 diag(PfxFloat x, PfxFloat y, PfxFloat z) {
  return PfxVector3(x, y, z).asDiagonal().toDenseMatrix();
}

void expectMatrixNear(const PfxMatrix3& actual, const PfxMatrix3& expected, PfxFloat tol) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(actual(r, c), expected(r, c), tol) << "(" << r << "," << c << ")\nactual\n"
                                                     << actual << "\nexpected\n" << expected;
    }
  }
}

PfxConvexMesh buildMesh(const pfx_test::TriangleList& list) {
  PfxConvexMesh mesh;
  EXPECT_EQ(pfxCreateConvexMesh(mesh, list.vertices.data(), list.numVertices(), list.indices.data(),
                                list.numIndices()),
            PFX_OK);
  return mesh;
}

PfxShape boxShape(const PfxVector3& half, const PfxVector3& position = PfxVector3::Zero(),
                  const PfxQuat& orientation = PfxQuat::Identity()) {
  PfxShape shape;
  shape.reset();
  shape.setBox(PfxBox(half));
  shape.setOffsetPosition(position);
  shape.setOffsetOrientation(orientation);
  return shape;
}

// Inertia per unit mass of a capsule along X by the midpoint rule on a grid over one octant
// (the other seven are mirror images): cells whose centre lies within `radius` of the
// segment count as solid.
PfxVector3 integrateCapsuleInertiaPerMass(double halfLength, double radius, int cellsPerRadius) {
  const double cell = radius / cellsPerRadius;
  const int nx = static_cast<int>(std::ceil((halfLength + radius) / cell));
  double count = 0, axial = 0, transverse = 0;
  for (int i = 0; i < nx; ++i) {
    const double x = (i + 0.5) * cell;
    const double beyond = std::max(x - halfLength, 0.0);
    for (int j = 0; j < cellsPerRadius; ++j) {
      const double y = (j + 0.5) * cell;
      for (int k = 0; k < cellsPerRadius; ++k) {
        const double z = (k + 0.5) * cell;
        if (beyond * beyond + y * y + z * z > radius * radius) continue;
        count += 1;
        axial += y * y + z * z;
        transverse += x * x + z * z;
      }
    }
  }
  return PfxVector3(PfxFloat(axial / count), PfxFloat(transverse / count),
                    PfxFloat(transverse / count));
}

}  // namespace

TEST(InertiaFormulas, SphereBoxCylinder) {
  // Sphere: (2/5) m r² = 0.4 * 5 * 4 = 8.
  expectMatrixNear(pfxCalcInertiaSphere(2, 5), diag(8, 8, 8), 1e-5f);
  // Box, full extents 2,4,6 and mass 6: m(b²+c²)/12 = 6(16+36)/12 = 26, 6(4+36)/12 = 20,
  // 6(4+16)/12 = 10.
  expectMatrixNear(pfxCalcInertiaBox(PfxVector3(1, 2, 3), 6), diag(26, 20, 10), 1e-5f);
  // Cylinder along X, half length 2 (L = 4), radius 1, mass 3: axial m r²/2 = 1.5,
  // transverse m(3r² + L²)/12 = 3 * 19 / 12 = 4.75.
  expectMatrixNear(pfxCalcInertiaCylinder(2, 1, 3), diag(1.5f, 4.75f, 4.75f), 1e-5f);
}

TEST(InertiaFormulas, CapsuleAgainstTextbookFormula) {
  // h = 0.5, r = 1, m = 7. Volumes: cylinder π r² 2h = π, caps (4/3)π; mass shares 3/7 and
  // 4/7, so cylinder 3 and caps 4.
  // Axial: 3 * r²/2 + 4 * (2/5) r² = 1.5 + 1.6 = 3.1.
  // Transverse: cylinder 3 (r²/4 + h²/3) = 3 (0.25 + 1/12) = 1;
  //   caps 4 (2r²/5 + h² + 3hr/4) = 4 (0.4 + 0.25 + 0.375) = 4.1; total 5.1.
  // (Moving each cap's (2/5) m r² straight to its centroid at h + 3r/8 would give 4.6625 for
  // the caps, which this test tells apart.)
  expectMatrixNear(pfxCalcInertiaCapsule(0.5f, 1, 7), diag(3.1f, 5.1f, 5.1f), 1e-5f);
}

TEST(InertiaFormulas, CapsuleAgainstNumericalIntegration) {
  for (const auto& size : {std::make_pair(0.5, 1.0), std::make_pair(2.0, 0.3)}) {
    const PfxVector3 numeric = integrateCapsuleInertiaPerMass(size.first, size.second, 200);
    const PfxMatrix3 formula = pfxCalcInertiaCapsule(PfxFloat(size.first), PfxFloat(size.second), 1);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(formula(axis, axis), numeric[axis], 1e-3f * numeric[axis])
          << "h " << size.first << " r " << size.second << " axis " << axis;
    }
  }
}

TEST(InertiaFormulas, CapsuleLimits) {
  // No radius: a thin rod of length 2h, m (2h)²/12 across. No length: a sphere.
  expectMatrixNear(pfxCalcInertiaCapsule(3, 0, 2), diag(0, 6, 6), 1e-5f);
  expectMatrixNear(pfxCalcInertiaCapsule(0, 2, 5), pfxCalcInertiaSphere(2, 5), 1e-5f);
  expectMatrixNear(pfxCalcInertiaCapsule(0, 0, 5), PfxMatrix3::Zero(), 0);
}

TEST(MassTranslate, ParallelAxisTheorem) {
  // A point of mass 2 at (1,2,0): I = m(|d|² E - d dᵀ) = 2 * [[4,-2,0],[-2,1,0],[0,0,5]].
  PfxMatrix3 expected;
  expected << 8, -4, 0, -4, 2, 0, 0, 0, 10;
  expectMatrixNear(pfxMassTranslate(2, PfxMatrix3::Zero(), PfxVector3(1, 2, 0)), expected, 1e-5f);
  // A shift along z adds m d² about x and y only.
  expectMatrixNear(pfxMassTranslate(3, diag(1, 1, 1), PfxVector3(0, 0, 2)), diag(13, 13, 1), 1e-5f);
}

TEST(Volume, OfEachShape) {
  PfxShape shape;
  shape.reset();
  shape.setSphere(PfxSphere(2));
  EXPECT_NEAR(pfxCalcVolume(shape), 4.0f / 3.0f * PFX_PI * 8, 1e-4f);
  shape.setBox(PfxBox(1, 2, 3));
  EXPECT_NEAR(pfxCalcVolume(shape), 48, 1e-4f);
  shape.setCylinder(PfxCylinder(2, 0.5f));  // π r² 2h = π * 0.25 * 4 = π
  EXPECT_NEAR(pfxCalcVolume(shape), PFX_PI, 1e-5f);
  shape.setCapsule(PfxCapsule(2, 0.5f));  // π + (4/3) π / 8 = (7/6) π
  EXPECT_NEAR(pfxCalcVolume(shape), 7.0f / 6.0f * PFX_PI, 1e-5f);
  int ground = 0;  // never read: a large mesh has no volume whatever it holds
  shape.setLargeTriMesh(reinterpret_cast<const PfxLargeTriMesh*>(&ground));
  EXPECT_EQ(pfxCalcVolume(shape), 0.0f);
  const PfxConvexMesh tet = buildMesh(pfx_test::makeTetrahedronTriangles());
  shape.setConvexMesh(&tet);
  EXPECT_NEAR(pfxCalcVolume(shape), 8.0f / 3.0f, 1e-5f);
}

TEST(ConvexMeshMass, BoxMeshMatchesBoxFormula) {
  const PfxConvexMesh mesh = buildMesh(pfx_test::makeBoxTriangles(1, 2, 3));
  const PfxMassProperties mp = pfxCalcMassPropertiesConvexMesh(mesh, 0.5f);
  EXPECT_NEAR(mp.mass, 24, 1e-4f);  // 0.5 * 48
  EXPECT_NEAR(mp.centerOfMass.norm(), 0, 1e-5f);
  expectMatrixNear(mp.inertia, pfxCalcInertiaBox(PfxVector3(1, 2, 3), 24), 1e-4f);
}

TEST(ConvexMeshMass, OffCentreMeshHasItsCentreAndTheSameInertia) {
  pfx_test::TriangleList box = pfx_test::makeBoxTriangles(1, 2, 3);
  const PfxVector3 shift(5, -1, 2);
  for (size_t i = 0; i < box.vertices.size(); ++i) box.vertices[i] += shift[i % 3];
  const PfxMassProperties mp = pfxCalcMassPropertiesConvexMesh(buildMesh(box), 1);
  EXPECT_NEAR(mp.mass, 48, 1e-3f);
  EXPECT_TRUE(mp.centerOfMass.isApprox(shift, 1e-5f));
  expectMatrixNear(mp.inertia, pfxCalcInertiaBox(PfxVector3(1, 2, 3), 48), 1e-3f);
}

TEST(ConvexMeshMass, RegularSolids) {
  // Regular tetrahedron of edge a: I = m a² / 20 about any axis through the centroid;
  // here a² = 8 and the volume is 8/3.
  const PfxMassProperties tet =
      pfxCalcMassPropertiesConvexMesh(buildMesh(pfx_test::makeTetrahedronTriangles()), 3);
  EXPECT_NEAR(tet.mass, 8, 1e-5f);
  EXPECT_NEAR(tet.centerOfMass.norm(), 0, 1e-6f);
  expectMatrixNear(tet.inertia, diag(3.2f, 3.2f, 3.2f), 1e-5f);

  // Regular icosahedron of edge a = 2: volume (5/12)(3 + √5) a³, I = (φ²/10) m a².
  const PfxMassProperties ico =
      pfxCalcMassPropertiesConvexMesh(buildMesh(pfx_test::makeIcosahedronTriangles()), 1);
  const double phi = (1 + std::sqrt(5.0)) / 2;
  const double volume = 5.0 / 12.0 * (3 + std::sqrt(5.0)) * 8;
  EXPECT_NEAR(ico.mass, volume, 1e-4 * volume);
  const PfxFloat moment = PfxFloat(phi * phi / 10 * volume * 4);
  expectMatrixNear(ico.inertia, diag(moment, moment, moment), 1e-4f * moment);
}

TEST(ShapeMass, OffsetPoseRotatesInertiaAndMovesCentre) {
  // Box 1x2x3 half extents turned 90° about z: its local x axis becomes the body's y, so
  // the body-frame inertia swaps the first two diagonal entries.
  const PfxQuat turn(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ()));
  const PfxMassProperties mp = pfxCalcMassProperties(boxShape({1, 2, 3}, {1, 2, 3}, turn), 0.125f);
  EXPECT_NEAR(mp.mass, 6, 1e-5f);
  EXPECT_TRUE(mp.centerOfMass.isApprox(PfxVector3(1, 2, 3)));
  expectMatrixNear(mp.inertia, diag(20, 26, 10), 1e-4f);
}

TEST(ShapeMass, OffsetMeshCentreIsRotatedToo) {
  // A cube mesh whose own centre is at (2,0,0) in the mesh frame, placed at (0,0,1) and
  // turned 90° about z: the centre lands at (0,0,1) + R (2,0,0) = (0,2,1).
  pfx_test::TriangleList box = pfx_test::makeBoxTriangles(0.5f, 0.5f, 0.5f);
  for (size_t i = 0; i < box.vertices.size(); i += 3) box.vertices[i] += 2;
  const PfxConvexMesh mesh = buildMesh(box);
  PfxShape shape;
  shape.reset();
  shape.setConvexMesh(&mesh);
  shape.setOffsetPosition(PfxVector3(0, 0, 1));
  shape.setOffsetOrientation(PfxQuat(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ())));
  const PfxMassProperties mp = pfxCalcMassProperties(shape, 2);
  EXPECT_NEAR(mp.mass, 2, 1e-5f);
  EXPECT_TRUE(mp.centerOfMass.isApprox(PfxVector3(0, 2, 1), 1e-5f));
  // About its own centre, not the body origin: a unit cube's m/6 on each axis.
  expectMatrixNear(mp.inertia, diag(1.0f / 3, 1.0f / 3, 1.0f / 3), 1e-5f);
}

TEST(CompoundMass, TwoOffCentreBoxes) {
  // Unit cube of mass 1 at the origin and one of mass 2 at (3,0,0): centre at
  // (0*1 + 3*2)/3 = (2,0,0). Each cube alone has m/6 on every axis. About x the offsets
  // are along x and add nothing: 1/6 + 2/6 = 0.5. About y and z: 1/6 + 1*2² + 2/6 + 2*1² =
  // 6.5.
  const PfxShape shapes[2] = {boxShape({0.5f, 0.5f, 0.5f}), boxShape({0.5f, 0.5f, 0.5f}, {3, 0, 0})};
  const PfxFloat densities[2] = {1, 2};
  const PfxMassProperties mp = pfxCalcMassPropertiesCompound(shapes, densities, 2);
  EXPECT_NEAR(mp.mass, 3, 1e-5f);
  EXPECT_TRUE(mp.centerOfMass.isApprox(PfxVector3(2, 0, 0)));
  expectMatrixNear(mp.inertia, diag(0.5f, 6.5f, 6.5f), 1e-4f);
}

TEST(CompoundMass, TwoHalvesMakeTheWhole) {
  // Boxes [-1,0]x[-1,1]² and [0,1]x[-1,1]² together are the box of half extents 1,1,1.
  const PfxShape shapes[2] = {boxShape({0.5f, 1, 1}, {-0.5f, 0, 0}),
                              boxShape({0.5f, 1, 1}, {0.5f, 0, 0})};
  const PfxFloat densities[2] = {1, 1};
  const PfxMassProperties mp = pfxCalcMassPropertiesCompound(shapes, densities, 2);
  EXPECT_NEAR(mp.mass, 8, 1e-5f);
  EXPECT_NEAR(mp.centerOfMass.norm(), 0, 1e-6f);
  expectMatrixNear(mp.inertia, pfxCalcInertiaBox(PfxVector3(1, 1, 1), 8), 1e-4f);
}

TEST(CompoundMass, LargeMeshesAddNothing) {
  int ground = 0;
  PfxShape shapes[2];
  shapes[0].reset();
  shapes[0].setLargeTriMesh(reinterpret_cast<const PfxLargeTriMesh*>(&ground));
  shapes[0].setOffsetPosition(PfxVector3(10, 10, 10));
  shapes[1] = boxShape({1, 1, 1}, {0, 0, 1});
  const PfxFloat densities[2] = {5, 1};
  const PfxMassProperties mp = pfxCalcMassPropertiesCompound(shapes, densities, 2);
  EXPECT_NEAR(mp.mass, 8, 1e-5f);
  EXPECT_TRUE(mp.centerOfMass.isApprox(PfxVector3(0, 0, 1)));

  const PfxMassProperties onlyGround = pfxCalcMassPropertiesCompound(shapes, densities, 1);
  EXPECT_EQ(onlyGround.mass, 0.0f);
  EXPECT_TRUE(onlyGround.inertia.isZero());
  EXPECT_EQ(pfxCalcMassPropertiesCompound(nullptr, densities, 2).mass, 0.0f);
}
