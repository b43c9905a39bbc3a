#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <set>
#include <utility>

#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx_test_meshes.h"

using namespace pfx;
using pfx_test::TriangleList;

namespace {

PfxInt32 build(PfxConvexMesh& mesh, const TriangleList& list) {
  return pfxCreateConvexMesh(mesh, list.vertices.data(), list.numVertices(), list.indices.data(),
                             list.numIndices());
}

PfxVector3 meshCentroid(const PfxConvexMesh& m) {
  PfxVector3 c = PfxVector3::Zero();
  for (int v = 0; v < m.m_numVerts; ++v) c += m.m_verts[v];
  return c / PfxFloat(m.m_numVerts);
}

PfxVector3 facetNormal(const PfxConvexMesh& m, int t) {
  const PfxVector3& a = m.m_verts[m.m_facetVertIds[t][0]];
  return (m.m_verts[m.m_facetVertIds[t][1]] - a).cross(m.m_verts[m.m_facetVertIds[t][2]] - a);
}

// The properties the narrow phase relies on, checked from the raw fields.
void expectWellFormed(const PfxConvexMesh& m) {
  const PfxFloat tol = 1e-4f;
  const PfxVector3 centroid = meshCentroid(m);

  // Facets face outward.
  for (int t = 0; t < m.m_numFacets; ++t) {
    const PfxVector3& a = m.m_verts[m.m_facetVertIds[t][0]];
    EXPECT_GT(facetNormal(m, t).dot(a - centroid), 0) << "facet " << t;
  }
  // Closed: V - E + F = 2 with E = 3F/2.
  EXPECT_EQ(int(m.m_numVerts) - int(m.m_numFacets) / 2, 2);

  int loopTotal = 0;
  for (int f = 0; f < m.m_numFaces; ++f) {
    const PfxVector3& n = m.m_faceNormals[f];
    const PfxFloat d = m.m_facePlaneDist[f];
    EXPECT_NEAR(n.norm(), 1, 1e-5f);
    for (int v = 0; v < m.m_numVerts; ++v) EXPECT_LE(n.dot(m.m_verts[v]), d + tol);
    const int first = m.m_faceFirstVert[f], count = m.m_faceNumVerts[f];
    EXPECT_EQ(first, loopTotal);
    loopTotal += count;
    ASSERT_GE(count, 3);
    for (int i = 0; i < count; ++i) {
      const PfxVector3& p = m.m_verts[m.m_faceVertIds[first + i]];
      const PfxVector3& q = m.m_verts[m.m_faceVertIds[first + (i + 1) % count]];
      const PfxVector3& r = m.m_verts[m.m_faceVertIds[first + (i + 2) % count]];
      EXPECT_NEAR(n.dot(p), d, tol);
      // Counter-clockwise about the outward normal, and convex: every turn is to the left.
      EXPECT_GE((q - p).cross(r - q).dot(n), -tol) << "face " << f << " corner " << i;
    }
  }

  // Each edge once, between two facets that are not coplanar.
  std::set<std::pair<int, int>> seen;
  for (int e = 0; e < m.m_numEdges; ++e) {
    const int a = m.m_edgeVertIds[e][0], b = m.m_edgeVertIds[e][1];
    EXPECT_TRUE(seen.insert({std::min(a, b), std::max(a, b)}).second) << "duplicate edge";
    std::vector<PfxVector3> normals;
    for (int t = 0; t < m.m_numFacets; ++t) {
      int hits = 0;
      for (int k = 0; k < 3; ++k) hits += (m.m_facetVertIds[t][k] == a || m.m_facetVertIds[t][k] == b);
      if (hits == 2) normals.push_back(facetNormal(m, t).normalized());
    }
    ASSERT_EQ(normals.size(), 2u);
    EXPECT_LT(normals[0].dot(normals[1]), 1 - 1e-4f);
  }

  for (int v = 0; v < m.m_numVerts; ++v) {
    EXPECT_TRUE(((m.m_verts[v] - m.m_aabbCenter).cwiseAbs().array() <=
                 m.m_aabbHalf.array() + 1e-6f).all());
  }
}

int countFacesWithNormal(const PfxConvexMesh& m, const PfxVector3& n) {
  int count = 0;
  for (int f = 0; f < m.m_numFaces; ++f) count += m.m_faceNormals[f].isApprox(n, 1e-5f);
  return count;
}

// Runs a build that must fail and checks that the output bytes are untouched.
void expectRejected(const TriangleList& list, PfxInt32 expected) {
  PfxConvexMesh mesh;
  std::memset(static_cast<void*>(&mesh), 0x5A, sizeof(mesh));
  PfxConvexMesh before;
  std::memcpy(static_cast<void*>(&before), &mesh, sizeof(mesh));
  EXPECT_EQ(build(mesh, list), expected);
  EXPECT_EQ(std::memcmp(&before, &mesh, sizeof(mesh)), 0);
}

TriangleList reversedWinding(TriangleList list) {
  for (size_t i = 0; i < list.indices.size(); i += 3) std::swap(list.indices[i + 1], list.indices[i + 2]);
  return list;
}

}  // namespace

TEST(ConvexMesh, BoxOfTwelveTrianglesHasSixQuadFaces) {
  PfxConvexMesh m;
  ASSERT_EQ(build(m, pfx_test::makeBoxTriangles(1, 2, 3)), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 8);
  EXPECT_EQ(m.m_numFacets, 12);
  EXPECT_EQ(m.m_numFaces, 6);
  EXPECT_EQ(m.m_numEdges, 12);  // the diagonals inside each side are not edges
  for (int f = 0; f < m.m_numFaces; ++f) EXPECT_EQ(m.m_faceNumVerts[f], 4);
  // An already compact input keeps its vertex numbering.
  EXPECT_EQ(m.m_verts[0], PfxVector3(-1, -2, -3));
  EXPECT_EQ(m.m_verts[7], PfxVector3(1, 2, 3));
  const PfxFloat half[3] = {1, 2, 3};
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const PfxVector3 n = PfxVector3::Unit(axis) * PfxFloat(sign);
      ASSERT_EQ(countFacesWithNormal(m, n), 1);
      for (int f = 0; f < m.m_numFaces; ++f) {
        if (m.m_faceNormals[f].isApprox(n, 1e-5f)) {
          EXPECT_NEAR(m.m_facePlaneDist[f], half[axis], 1e-6f);
        }
      }
    }
  }
  EXPECT_TRUE(m.m_aabbCenter.isZero());
  EXPECT_EQ(m.m_aabbHalf, PfxVector3(1, 2, 3));
  expectWellFormed(m);
}

TEST(ConvexMesh, WindingIsMadeOutward) {
  TriangleList mixed = pfx_test::makeBoxTriangles(1, 1, 1);
  for (size_t i = 0; i < mixed.indices.size(); i += 9) std::swap(mixed.indices[i + 1], mixed.indices[i + 2]);
  PfxConvexMesh fromMixed, fromInward;
  ASSERT_EQ(build(fromMixed, mixed), PFX_OK);
  ASSERT_EQ(build(fromInward, reversedWinding(pfx_test::makeBoxTriangles(1, 1, 1))), PFX_OK);
  for (const PfxConvexMesh* m : {&fromMixed, &fromInward}) {
    EXPECT_EQ(m->m_numFaces, 6);
    EXPECT_EQ(m->m_numEdges, 12);
    expectWellFormed(*m);
  }
}

TEST(ConvexMesh, OverwritesEveryByteTheSameWay) {
  // Whatever the output held before, a successful build leaves the same bytes: no field is
  // left stale, and unused slots are deterministic for serialization.
  PfxConvexMesh zeroed, dirty;
  std::memset(static_cast<void*>(&zeroed), 0, sizeof(zeroed));
  std::memset(static_cast<void*>(&dirty), 0xC3, sizeof(dirty));
  const TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  ASSERT_EQ(build(zeroed, box), PFX_OK);
  ASSERT_EQ(build(dirty, box), PFX_OK);
  EXPECT_EQ(std::memcmp(&zeroed, &dirty, sizeof(zeroed)), 0);
}

TEST(ConvexMesh, TetrahedronWithMixedWinding) {
  PfxConvexMesh m;
  ASSERT_EQ(build(m, pfx_test::makeTetrahedronTriangles()), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 4);
  EXPECT_EQ(m.m_numFacets, 4);
  EXPECT_EQ(m.m_numFaces, 4);
  EXPECT_EQ(m.m_numEdges, 6);
  for (int f = 0; f < 4; ++f) {
    EXPECT_EQ(m.m_faceNumVerts[f], 3);
    // Face planes of this tetrahedron are at distance 1/sqrt(3) from the centre, along
    // normals (±1,±1,±1)/sqrt(3).
    EXPECT_NEAR(m.m_facePlaneDist[f], 1 / std::sqrt(3.0f), 1e-5f);
    EXPECT_NEAR(std::abs(m.m_faceNormals[f].x()), 1 / std::sqrt(3.0f), 1e-5f);
  }
  expectWellFormed(m);
}

TEST(ConvexMesh, Icosahedron) {
  PfxConvexMesh m;
  ASSERT_EQ(build(m, pfx_test::makeIcosahedronTriangles()), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 12);
  EXPECT_EQ(m.m_numFacets, 20);
  EXPECT_EQ(m.m_numFaces, 20);
  EXPECT_EQ(m.m_numEdges, 30);
  expectWellFormed(m);
}

TEST(ConvexMesh, TriangleSoupIsWeldedAndUnusedVerticesDropped) {
  // STL-style: every triangle has its own three vertices, 36 in all (more than the 34 a mesh
  // holds), plus two vertices no triangle uses.
  const TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  TriangleList soup;
  soup.vertices = {5, 5, 5};
  for (size_t i = 0; i < box.indices.size(); ++i) {
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(box.vertices[3 * box.indices[i] + k]);
    soup.indices.push_back(static_cast<PfxUInt16>(i + 1));
  }
  soup.vertices.insert(soup.vertices.end(), {7, 7, 7});
  PfxConvexMesh m;
  ASSERT_EQ(build(m, soup), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 8);
  EXPECT_EQ(m.m_numFaces, 6);
  EXPECT_EQ(m.m_numEdges, 12);
  EXPECT_EQ(m.m_aabbHalf, PfxVector3(1, 1, 1));
  expectWellFormed(m);
}

TEST(ConvexMesh, SideWithAnInteriorVertexIsOneQuad) {
  // The +Z side split into four triangles around its centre (vertex 8): the centre is
  // inside the face, so the face loop is still the four corners and no edge reaches it.
  TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  box.vertices.insert(box.vertices.end(), {0, 0, 1});
  box.indices.resize(30);  // drop the two +Z triangles
  box.indices.insert(box.indices.end(), {4, 5, 8, 5, 7, 8, 7, 6, 8, 6, 4, 8});
  PfxConvexMesh m;
  ASSERT_EQ(build(m, box), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 9);
  EXPECT_EQ(m.m_numFacets, 14);
  EXPECT_EQ(m.m_numFaces, 6);
  EXPECT_EQ(m.m_numEdges, 12);
  for (int f = 0; f < m.m_numFaces; ++f) {
    EXPECT_EQ(m.m_faceNumVerts[f], 4);
    for (int i = 0; i < m.m_faceNumVerts[f]; ++i) EXPECT_NE(m.m_faceVertIds[m.m_faceFirstVert[f] + i], 8);
  }
  expectWellFormed(m);
}

TEST(ConvexMesh, OctagonalPrismHasOctagonFaces) {
  // Caps triangulated as fans: 16 vertices, 6 + 6 cap triangles and 16 side triangles;
  // faces 2 octagons + 8 quads, edges 8 + 8 + 8.
  TriangleList prism;
  for (int z = -1; z <= 1; z += 2) {
    for (int i = 0; i < 8; ++i) {
      const double angle = i * PFX_PI / 4;
      prism.vertices.insert(prism.vertices.end(), {PfxFloat(std::cos(angle)),
                                                   PfxFloat(std::sin(angle)), PfxFloat(z)});
    }
  }
  for (int i = 1; i < 7; ++i) {
    prism.indices.insert(prism.indices.end(), {0, PfxUInt16(i + 1), PfxUInt16(i)});
    prism.indices.insert(prism.indices.end(), {8, PfxUInt16(8 + i), PfxUInt16(9 + i)});
  }
  for (int i = 0; i < 8; ++i) {
    const PfxUInt16 a = PfxUInt16(i), b = PfxUInt16((i + 1) % 8);
    prism.indices.insert(prism.indices.end(), {a, b, PfxUInt16(b + 8), a, PfxUInt16(b + 8), PfxUInt16(a + 8)});
  }
  PfxConvexMesh m;
  ASSERT_EQ(build(m, prism), PFX_OK);
  EXPECT_EQ(m.m_numVerts, 16);
  EXPECT_EQ(m.m_numFacets, 28);
  EXPECT_EQ(m.m_numFaces, 10);
  EXPECT_EQ(m.m_numEdges, 24);
  ASSERT_EQ(countFacesWithNormal(m, PfxVector3(0, 0, 1)), 1);
  for (int f = 0; f < m.m_numFaces; ++f) {
    const bool cap = std::abs(m.m_faceNormals[f].z()) > 0.5f;
    EXPECT_EQ(m.m_faceNumVerts[f], cap ? 8 : 4);
  }
  expectWellFormed(m);
}

TEST(ConvexMesh, RoundedCoordinatesStillMergeIntoQuads) {
  // Coordinates off by a few parts per million, as a text file with six digits leaves them.
  TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  box.vertices[3 * 7 + 0] = 1.000003f;
  box.vertices[3 * 5 + 2] = 0.999996f;
  PfxConvexMesh m;
  ASSERT_EQ(build(m, box), PFX_OK);
  EXPECT_EQ(m.m_numFaces, 6);
  EXPECT_EQ(m.m_numEdges, 12);
  expectWellFormed(m);
}

TEST(ConvexMeshRejects, NullPointers) {
  const TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  PfxConvexMesh mesh;
  std::memset(static_cast<void*>(&mesh), 0x5A, sizeof(mesh));
  PfxConvexMesh before;
  std::memcpy(static_cast<void*>(&before), &mesh, sizeof(mesh));
  EXPECT_EQ(pfxCreateConvexMesh(mesh, nullptr, 8, box.indices.data(), 36), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(pfxCreateConvexMesh(mesh, box.vertices.data(), 8, nullptr, 36), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(std::memcmp(&before, &mesh, sizeof(mesh)), 0);
}

TEST(ConvexMeshRejects, BadCountsAndIndices) {
  TriangleList box = pfx_test::makeBoxTriangles(1, 1, 1);
  TriangleList empty = box;
  empty.indices.clear();
  expectRejected(empty, PFX_ERR_OUT_OF_RANGE);

  TriangleList ragged = box;
  ragged.indices.pop_back();
  expectRejected(ragged, PFX_ERR_OUT_OF_RANGE);

  TriangleList badIndex = box;
  badIndex.indices[5] = 8;  // only 8 vertices
  expectRejected(badIndex, PFX_ERR_OUT_OF_RANGE);

  TriangleList tooManyTriangles = box;
  while (tooManyTriangles.indices.size() < 3 * 65) {
    tooManyTriangles.indices.insert(tooManyTriangles.indices.end(), box.indices.begin(),
                                    box.indices.begin() + 3);
  }
  tooManyTriangles.indices.resize(3 * 65);
  expectRejected(tooManyTriangles, PFX_ERR_OUT_OF_RANGE);
}

TEST(ConvexMeshRejects, MoreThanThirtyFourDistinctVertices) {
  // Twelve separate triangles with 36 distinct corners.
  TriangleList soup;
  for (int t = 0; t < 12; ++t) {
    soup.vertices.insert(soup.vertices.end(), {PfxFloat(t), 0, 0, PfxFloat(t), 1, 0, PfxFloat(t), 0, 1});
    soup.indices.insert(soup.indices.end(), {PfxUInt16(3 * t), PfxUInt16(3 * t + 1), PfxUInt16(3 * t + 2)});
  }
  expectRejected(soup, PFX_ERR_OUT_OF_RANGE);
}

TEST(ConvexMeshRejects, NonFiniteVertices) {
  TriangleList nan = pfx_test::makeBoxTriangles(1, 1, 1);
  nan.vertices[3 * 6 + 1] = std::numeric_limits<PfxFloat>::quiet_NaN();
  expectRejected(nan, PFX_ERR_INVALID_VALUE);
  TriangleList inf = pfx_test::makeBoxTriangles(1, 1, 1);
  inf.vertices[0] = -std::numeric_limits<PfxFloat>::infinity();
  expectRejected(inf, PFX_ERR_INVALID_VALUE);
}

TEST(ConvexMeshRejects, DegenerateTrianglesAndZeroVolume) {
  TriangleList repeated = pfx_test::makeBoxTriangles(1, 1, 1);
  repeated.indices[2] = repeated.indices[1];
  expectRejected(repeated, PFX_ERR_DEGENERATE);

  // A triangle whose corners lie on one line (vertex 8 halfway along the edge 0-1).
  TriangleList collinear = pfx_test::makeBoxTriangles(1, 1, 1);
  collinear.vertices.insert(collinear.vertices.end(), {0, -1, -1});
  collinear.indices.insert(collinear.indices.end(), {0, 8, 1});
  expectRejected(collinear, PFX_ERR_DEGENERATE);

  // Two triangles back to back: closed, but flat.
  TriangleList sheet;
  sheet.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  sheet.indices = {0, 1, 2, 0, 2, 1};
  expectRejected(sheet, PFX_ERR_DEGENERATE);
}

TEST(ConvexMeshRejects, OpenOrNonManifold) {
  TriangleList open = pfx_test::makeBoxTriangles(1, 1, 1);
  open.indices.resize(33);  // one triangle missing
  expectRejected(open, PFX_ERR_NOT_CONVEX);

  // The +Z diagonal used by a third triangle.
  TriangleList fin = pfx_test::makeBoxTriangles(1, 1, 1);
  fin.vertices.insert(fin.vertices.end(), {0, 0, 3});
  fin.indices.insert(fin.indices.end(), {4, 7, 8});
  expectRejected(fin, PFX_ERR_NOT_CONVEX);

  TriangleList twice = pfx_test::makeBoxTriangles(1, 1, 1);
  const std::vector<PfxUInt16> again = twice.indices;
  twice.indices.insert(twice.indices.end(), again.begin(), again.end());
  expectRejected(twice, PFX_ERR_NOT_CONVEX);
}

TEST(ConvexMeshRejects, Concave) {
  // Corner 7 pushed into the box: the closed surface has a dent.
  TriangleList dented = pfx_test::makeBoxTriangles(1, 1, 1);
  dented.vertices[21] = dented.vertices[22] = dented.vertices[23] = 0.5f;
  expectRejected(dented, PFX_ERR_NOT_CONVEX);

  // Two separate tetrahedra: each closed, together not one convex solid.
  TriangleList pair = pfx_test::makeTetrahedronTriangles();
  const TriangleList second = pfx_test::makeTetrahedronTriangles();
  for (size_t i = 0; i < second.vertices.size(); ++i) {
    pair.vertices.push_back(second.vertices[i] + (i % 3 == 0 ? 5.0f : 0.0f));
  }
  for (PfxUInt16 index : second.indices) pair.indices.push_back(PfxUInt16(index + 4));
  expectRejected(pair, PFX_ERR_NOT_CONVEX);

  // A shallow valley: corner 7 lowered by 0.02 folds the +Z side inward along its diagonal
  // 4-7, leaving corner 6 0.02 above the plane of (4,5,7), far beyond the tolerance
  // (1e-4 of the diagonal 2*sqrt(3)).
  TriangleList valley = pfx_test::makeBoxTriangles(1, 1, 1);
  valley.vertices[3 * 7 + 2] = 0.98f;
  expectRejected(valley, PFX_ERR_NOT_CONVEX);
}
