// PfxLargeTriMesh: building in every storage variant, sizes, bad input, ray casts against
// a brute-force reference, watertightness, and deformation by moving vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/base_level/collision/pfx_shape.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_object_bytes.h"

namespace {

using namespace pfx;
using namespace pfx_test;

// How the node links of a mesh are used, walking down from the root.
struct TreeShape {
  PfxUInt32 leaves = 0;
  PfxUInt32 emptySlots = 0;
  bool everyNodeReachedOnce = true;
};

template <class Node>
TreeShape treeShape(const Node* nodes, PfxUInt32 numNodes) {
  TreeShape shape;
  std::vector<PfxUInt32> reached(numNodes, 0);
  std::vector<PfxUInt32> pending = {0};
  reached[0] = 1;
  while (!pending.empty()) {
    const Node& node = nodes[pending.back()];
    pending.pop_back();
    for (const PfxUInt32 link : node.m_links) {
      if (link == 0xFFFFFFFFu) {
        ++shape.emptySlots;
        // An unused slot's box is inverted on every axis.
        continue;
      }
      if (link & 0x80000000u) {
        ++shape.leaves;
      } else if (link >= numNodes || reached[link]++ > 0) {
        shape.everyNodeReachedOnce = false;
      } else {
        pending.push_back(link);
      }
    }
  }
  for (const PfxUInt32 r : reached) shape.everyNodeReachedOnce &= r == 1;
  return shape;
}

TreeShape treeShape(const PfxLargeTriMesh& mesh) {
  return mesh.m_quantizedNodes ? treeShape(mesh.m_quantizedNodes, mesh.m_numNodes)
                               : treeShape(mesh.m_nodes, mesh.m_numNodes);
}

// Every island holds 1..64 triangles, the islands tile the stored triangles in order, every
// node hangs below the root once, and the maps between stored and caller's triangles are
// inverse to each other. pfxFindLargeTriMeshTriangle searches the islands in turn, so it is
// asked of each island's first and last triangle, where an island's bounds would show, and
// of every triangle only in a small mesh: asked of all 80,000 of the scrambled grid, it took
// 28 s under AddressSanitizer. Which caller's triangle each stored one is, is checked whole.
void expectWellFormed(const PfxLargeTriMesh& mesh, const MeshSource& src) {
  ASSERT_GE(mesh.m_numNodes, 1u);
  const TreeShape shape = treeShape(mesh);
  EXPECT_TRUE(shape.everyNodeReachedOnce);
  EXPECT_GE(shape.leaves, mesh.m_numIslands);
  constexpr PfxUInt32 kFindEveryTriangleUpTo = 4096;
  const bool findEvery = mesh.m_numTriangles <= kFindEveryTriangleUpTo;
  std::vector<bool> sourceSeen(src.numTriangles(), false);
  const PfxFloat tolerance = quantizationError(mesh) + PfxFloat(1e-6);
  PfxUInt32 next = 0;
  for (PfxUInt32 i = 0; i < mesh.m_numIslands; ++i) {
    const PfxLargeMeshIsland& island = mesh.m_islands[i];
    ASSERT_EQ(island.m_firstTriangle, next);
    ASSERT_GE(island.m_numTriangles, 1u);
    ASSERT_LE(island.m_numTriangles, PFX_LARGE_MESH_MAX_TRIANGLES_PER_ISLAND);
    const PfxUInt32 end = next + island.m_numTriangles;
    ASSERT_LE(end, mesh.m_numTriangles);
    for (PfxUInt32 t = next; t < end; ++t) {
      const PfxUInt32 source = pfxGetLargeTriMeshSourceTriangle(mesh, t);
      ASSERT_LT(source, src.numTriangles());
      ASSERT_FALSE(sourceSeen[source]) << "caller's triangle " << source << " stored twice";
      sourceSeen[source] = true;
      if (findEvery || t == island.m_firstTriangle || t + 1 == end) {
        ASSERT_EQ(pfxFindLargeTriMeshTriangle(mesh, source), t);
      }
      PfxVector3 v[3];
      pfxGetLargeTriMeshTriangle(mesh, t, v[0], v[1], v[2]);
      for (int k = 0; k < 3; ++k) {
        ASSERT_LE((v[k] - src.vertex(src.triangles[3 * source + k])).norm(), tolerance);
      }
    }
    next = end;
  }
  ASSERT_EQ(next, mesh.m_numTriangles);
}

TEST(LargeTriMesh, BuildsInEveryStorageVariant) {
  const MeshSource grid = makeFlatGrid(96, PfxFloat(0.5));  // 18,432 triangles
  for (const PfxUInt32 flags : kAllMeshFlagSets) {
    SCOPED_TRACE(flags);
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(flags)), PFX_OK);
    const PfxLargeTriMesh& mesh = owner.mesh;
    EXPECT_EQ(mesh.m_numTriangles, grid.numTriangles());
    EXPECT_EQ(mesh.m_numDroppedTriangles, 0u);
    EXPECT_EQ(mesh.m_numVertices, grid.numVertices());
    // At most 64 per island: at least 18432 / 64 = 288 islands.
    EXPECT_GE(mesh.m_numIslands, 288u);
    EXPECT_EQ(mesh.m_quantizedVertices != nullptr, (flags & PFX_MESH_FLAG_USE_QUANTIZED) != 0);
    // A row-major grid keeps each island's vertices and caller's indices within 16-bit
    // offsets.
    EXPECT_EQ(mesh.m_triangleOffsets != nullptr, (flags & PFX_MESH_FLAG_USE_QUANTIZED) != 0);
    EXPECT_EQ(mesh.m_triangleSourceOffsets != nullptr, (flags & PFX_MESH_FLAG_USE_QUANTIZED) != 0);
    EXPECT_NE(mesh.m_triangleSourceIds != nullptr, mesh.m_triangleSourceOffsets != nullptr);
    expectWellFormed(mesh, grid);
    // The grid spans x, z in [-24, 24] at y = 0.
    EXPECT_NEAR(mesh.m_aabbMin.x(), -24, 1e-4);
    EXPECT_NEAR(mesh.m_aabbMax.z(), 24, 1e-4);
    EXPECT_NEAR(mesh.m_aabbMax.y(), 0, 1e-6);
  }
}

TEST(LargeTriMesh, BvhHasSmallLeavesAndArrayOneLeafPerIsland) {
  const MeshSource grid = makeFlatGrid(32, 1);
  MeshOwner array, bvh;
  ASSERT_EQ(pfxCreateLargeTriMesh(array.mesh, grid.param(0)), PFX_OK);
  ASSERT_EQ(pfxCreateLargeTriMesh(bvh.mesh, grid.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  const TreeShape arrayShape = treeShape(array.mesh);
  const TreeShape bvhShape = treeShape(bvh.mesh);
  EXPECT_EQ(arrayShape.leaves, array.mesh.m_numIslands);
  // Leaves of at most four triangles: at least 2048 / 4 = 512 of them.
  EXPECT_GE(bvhShape.leaves, 512u);
  // Four-wide nodes: a node per three more leaves, give or take the nodes left part full.
  for (const PfxLargeTriMesh* mesh : {&array.mesh, &bvh.mesh}) {
    const TreeShape shape = treeShape(*mesh);
    EXPECT_EQ(4 * mesh->m_numNodes, shape.leaves + shape.emptySlots + mesh->m_numNodes - 1);
    // Every node but a lone leaf's root holds at least two children.
    EXPECT_LE(shape.emptySlots, 2 * mesh->m_numNodes);
  }
}

TEST(LargeTriMesh, QuantizedKeepsVerticesNodesAndIndicesIn16Bits) {
  const MeshSource terrain = makeHeightField(128, 128, 1, [](PfxFloat x, PfxFloat z) {
    return std::sin(x * PfxFloat(0.2)) * std::cos(z * PfxFloat(0.15)) * 3;
  });
  for (const PfxUInt32 base : {0u, PFX_MESH_FLAG_USE_BVH}) {
    MeshOwner expanded, quantized;
    ASSERT_EQ(pfxCreateLargeTriMesh(expanded.mesh, terrain.param(base)), PFX_OK);
    ASSERT_EQ(pfxCreateLargeTriMesh(quantized.mesh,
                                    terrain.param(base | PFX_MESH_FLAG_USE_QUANTIZED)),
              PFX_OK);
    const double perTriangleExpanded = double(expanded.mesh.m_bytes) / terrain.numTriangles();
    const double perTriangleQuantized = double(quantized.mesh.m_bytes) / terrain.numTriangles();
    std::printf("%s: %.1f bytes per triangle expanded, %.1f quantized (%.0f%%)\n",
                base ? "bvh" : "array", perTriangleExpanded, perTriangleQuantized,
                100 * perTriangleQuantized / perTriangleExpanded);
    // Vertices and node bounds go from PfxFloat to 16 bits, corners and the caller's
    // triangle indices from 32-bit indices to 16-bit offsets (a height field's islands fit
    // them); the edge flags and the islands keep their size. Each array is padded to
    // PFX_BUFFER_ALIGNMENT and the block to 64 bytes, which moves the total by no more
    // than that.
    ASSERT_NE(quantized.mesh.m_triangleOffsets, nullptr);
    ASSERT_NE(quantized.mesh.m_triangleSourceOffsets, nullptr);
    ASSERT_EQ(quantized.mesh.m_numNodes, expanded.mesh.m_numNodes);
    ASSERT_EQ(quantized.mesh.m_numIslands, expanded.mesh.m_numIslands);
    const std::size_t numTriangles = expanded.mesh.m_numTriangles;
    const std::size_t saved =
        3 * std::size_t(expanded.mesh.m_numVertices) * (sizeof(PfxFloat) - sizeof(PfxUInt16)) +
        expanded.mesh.m_numNodes * (sizeof(PfxLargeMeshNode) - sizeof(PfxLargeMeshQuantizedNode)) +
        (3 * numTriangles + numTriangles) * (sizeof(PfxUInt32) - sizeof(PfxUInt16));
    ASSERT_GT(expanded.mesh.m_bytes, quantized.mesh.m_bytes);
    EXPECT_NEAR(double(expanded.mesh.m_bytes - quantized.mesh.m_bytes), double(saved),
                4.0 * PFX_BUFFER_ALIGNMENT + 64);
    // About half in float; less in double, where the values that shrink took 8 bytes.
    EXPECT_LT(perTriangleQuantized, 0.57 * perTriangleExpanded);
  }
}

TEST(LargeTriMesh, FlatGridEdgesAreInternalAndBorderEdgesAreNot) {
  const MeshSource grid = makeFlatGrid(4, 1);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(0)), PFX_OK);
  // Cell (1,1), first triangle (a, d, c): every edge is shared with a neighbour.
  const PfxUInt32 inner = pfxFindLargeTriMeshTriangle(owner.mesh, 2 * (1 * 4 + 1));
  EXPECT_EQ(owner.mesh.m_edgeFlags[inner], 0x3F);
  // Cell (0,0), first triangle (a, d, c): edge a-d lies on the border x = -2, edge d-c is
  // shared with cell (0,1), and c-a is the diagonal.
  const PfxUInt32 corner = pfxFindLargeTriMeshTriangle(owner.mesh, 0);
  const PfxUInt8 flags = owner.mesh.m_edgeFlags[corner];
  EXPECT_EQ(flags & (PFX_LARGE_MESH_EDGE_INTERNAL_0 | PFX_LARGE_MESH_EDGE_SHARED_0), 0);
  EXPECT_NE(flags & PFX_LARGE_MESH_EDGE_INTERNAL_1, 0);
  EXPECT_NE(flags & PFX_LARGE_MESH_EDGE_INTERNAL_2, 0);
}

TEST(LargeTriMesh, RidgeIsSharedButNotInternalAndValleyIsInternal) {
  // Two triangles folded along the z axis: a ridge (roof) and, mirrored, a valley.
  for (const PfxFloat fold : {PfxFloat(1), PfxFloat(-1)}) {
    MeshSource m;
    m.vertices = {0, 0, 0, 0, 0, 1, -1, -fold, 0, 1, -fold, 0};
    // (v2 - v0) x (v1 - v0) = (-1,-f,0) x (0,0,1) = (-f,1,0) and (v1 - v0) x (v3 - v0) =
    // (f,1,0): both face up. Fold 1 puts the outer corners below the shared edge (a ridge),
    // fold -1 above it (a valley).
    m.triangles = {0, 2, 1, 0, 1, 3};
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, m.param(0)), PFX_OK);
    for (PfxUInt32 t = 0; t < 2; ++t) {
      const PfxUInt8 flags = owner.mesh.m_edgeFlags[t];
      const bool shared = (flags & 0x38) != 0;
      const bool internal = (flags & 0x07) != 0;
      EXPECT_TRUE(shared);
      EXPECT_EQ(internal, fold < 0) << "fold " << fold;
    }
  }
}

TEST(LargeTriMesh, ShapeBoundsCoverTheMeshAndItsThickness) {
  const MeshSource grid = makeFlatGrid(8, 1);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(0, PfxFloat(0.25))), PFX_OK);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&owner.mesh);
  shape.setOffsetPosition(PfxVector3(1, 2, 3));
  PfxVector3 centre, half;
  shape.getAabb(centre, half);
  // x, z in [-4, 4], y = 0, grown by the thickness 0.25, moved by the offset.
  EXPECT_NEAR(centre.x(), 1, 1e-6);
  EXPECT_NEAR(centre.y(), 2, 1e-6);
  EXPECT_NEAR(half.x(), 4.25, 1e-6);
  EXPECT_NEAR(half.y(), 0.25, 1e-6);
  EXPECT_NEAR(half.z(), 4.25, 1e-6);
}

// A mesh filled with a byte pattern, to see that a rejected call wrote nothing.
struct Sentinel {
  PfxLargeTriMesh mesh;
  Sentinel() { std::memset(static_cast<void*>(&mesh), 0xAB, sizeof(mesh)); }
  bool untouched() const {
    const unsigned char* bytes = reinterpret_cast<const unsigned char*>(&mesh);
    return std::all_of(bytes, bytes + sizeof(mesh), [](unsigned char b) { return b == 0xAB; });
  }
};

TEST(LargeTriMesh, RejectsBadInputAndWritesNothing) {
  const MeshSource grid = makeFlatGrid(2, 1);
  const auto check = [](const PfxCreateLargeTriMeshParam& p, PfxInt32 expected) {
    Sentinel s;
    EXPECT_EQ(pfxCreateLargeTriMesh(s.mesh, p), expected);
    EXPECT_TRUE(s.untouched());
  };
  PfxCreateLargeTriMeshParam p = grid.param(0);
  p.m_vertices = nullptr;
  check(p, PFX_ERR_NULL_POINTER);
  p = grid.param(0);
  p.m_triangles = nullptr;
  check(p, PFX_ERR_NULL_POINTER);
  p = grid.param(0);
  p.m_numTriangles = 0;
  check(p, PFX_ERR_OUT_OF_RANGE);
  p = grid.param(0);
  p.m_numVertices = 0;
  check(p, PFX_ERR_OUT_OF_RANGE);
  p = grid.param(0);
  p.m_flags = 1u << 7;
  check(p, PFX_ERR_INVALID_FLAG);
  p = grid.param(0);
  p.m_thickness = -1;
  check(p, PFX_ERR_INVALID_VALUE);
  p = grid.param(0);
  p.m_thickness = std::nanf("");
  check(p, PFX_ERR_INVALID_VALUE);
  p = grid.param(0);
  p.m_islandSize = 0;
  check(p, PFX_ERR_OUT_OF_RANGE);
  p = grid.param(0);
  p.m_islandSize = 65;
  check(p, PFX_ERR_OUT_OF_RANGE);

  MeshSource bad = grid;
  bad.vertices[4] = std::nanf("");
  check(bad.param(0), PFX_ERR_INVALID_VALUE);
  bad = grid;
  bad.vertices[0] = std::numeric_limits<PfxFloat>::infinity();
  check(bad.param(0), PFX_ERR_INVALID_VALUE);
  bad = grid;
  bad.triangles[5] = grid.numVertices();  // one past the last vertex
  check(bad.param(0), PFX_ERR_OUT_OF_RANGE);

  // Nothing but zero-area triangles: a repeated corner and three points on a line.
  MeshSource flat;
  flat.vertices = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  flat.triangles = {0, 1, 2, 0, 0, 1};
  check(flat.param(0), PFX_ERR_DEGENERATE);
}

TEST(LargeTriMesh, DropsAndCountsZeroAreaTriangles) {
  MeshSource m = makeFlatGrid(2, 1);  // 8 triangles over 9 vertices
  m.triangles.insert(m.triangles.end(), {0, 0, 4, 0, 1, 2});  // repeated corner; collinear row
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, m.param(0)), PFX_OK);
  EXPECT_EQ(owner.mesh.m_numTriangles, 8u);
  EXPECT_EQ(owner.mesh.m_numDroppedTriangles, 2u);
  EXPECT_EQ(owner.mesh.m_numSourceTriangles, 10u);
  EXPECT_EQ(pfxFindLargeTriMeshTriangle(owner.mesh, 8), 0xFFFFFFFFu);
  EXPECT_EQ(pfxFindLargeTriMeshTriangle(owner.mesh, 9), 0xFFFFFFFFu);
  EXPECT_EQ(pfxFindLargeTriMeshTriangle(owner.mesh, 10), 0xFFFFFFFFu);
  EXPECT_LT(pfxFindLargeTriMeshTriangle(owner.mesh, 7), 8u);
}

TEST(LargeTriMesh, ScrambledVertexOrderFallsBackToFullIndices) {
  // 40,000 triangles of their own three vertices in random places: an island's triangles
  // come from all over the vertex list, beyond 16-bit offsets.
  const MeshSource soup = makeRandomTriangles(40000, 50, 1, 7);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, soup.param(PFX_MESH_FLAG_USE_QUANTIZED)), PFX_OK);
  EXPECT_EQ(owner.mesh.m_triangleOffsets, nullptr);
  EXPECT_NE(owner.mesh.m_triangleVertices, nullptr);
  expectWellFormed(owner.mesh, soup);
}

TEST(LargeTriMesh, ScrambledTriangleOrderFallsBackToFullSourceIndices) {
  // A 200 x 200 grid (80,000 triangles) listed in random order: an island's neighbouring
  // triangles sit up to the whole list apart, beyond 16-bit offsets, while their vertices
  // stay close in the row-major vertex list.
  MeshSource grid = makeFlatGrid(200, 1);
  std::vector<PfxUInt32> order(grid.numTriangles());
  for (PfxUInt32 t = 0; t < order.size(); ++t) order[t] = t;
  std::shuffle(order.begin(), order.end(), std::mt19937(4));
  std::vector<PfxUInt32> shuffled(grid.triangles.size());
  for (PfxUInt32 t = 0; t < order.size(); ++t) {
    std::copy_n(grid.triangles.begin() + 3 * order[t], 3, shuffled.begin() + 3 * t);
  }
  grid.triangles = shuffled;
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_QUANTIZED)), PFX_OK);
  EXPECT_EQ(owner.mesh.m_triangleSourceOffsets, nullptr);
  EXPECT_NE(owner.mesh.m_triangleSourceIds, nullptr);
  EXPECT_NE(owner.mesh.m_triangleOffsets, nullptr);
  expectWellFormed(owner.mesh, grid);
  // A ray still reports the caller's index: the cell under (0.3, 0.6) is 100 + 0, 100 + 0
  // from the corner (-100, -100), first triangle (z' > x'), listed at order^-1.
  PfxFloat fraction;
  PfxVector3 normal;
  PfxUInt32 triangle;
  ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0.3f, 5, 0.6f), PfxVector3(0, -10, 0),
                                     fraction, normal, triangle));
  EXPECT_EQ(order[triangle], 2u * (100 * 200 + 100));
}

// A stored triangle in double, as the reference below meets it: read once per mesh, since
// every ray meets every triangle (1,500 rays over 3,000 triangles in six variants took 54 s
// under AddressSanitizer when each ray read them through the mesh again).
struct ReferenceTriangle {
  Eigen::Vector3d a, e1, e2;
  PfxUInt32 source;
};

std::vector<ReferenceTriangle> referenceTriangles(const PfxLargeTriMesh& mesh) {
  std::vector<ReferenceTriangle> triangles(mesh.m_numTriangles);
  for (PfxUInt32 t = 0; t < mesh.m_numTriangles; ++t) {
    PfxVector3 v[3];
    pfxGetLargeTriMeshTriangle(mesh, t, v[0], v[1], v[2]);
    const Eigen::Vector3d a = v[0].cast<double>();
    triangles[t] = {a, v[1].cast<double>() - a, v[2].cast<double>() - a,
                    pfxGetLargeTriMeshSourceTriangle(mesh, t)};
  }
  return triangles;
}

// Closest hit over all stored triangles, in double (Moller-Trumbore), and how far inside
// its triangle the hit lies (the smallest barycentric weight).
struct ReferenceHit {
  bool hit = false;
  double fraction = 2;
  double margin = 0;
  PfxUInt32 triangle = 0;
};

ReferenceHit bruteForceRay(const std::vector<ReferenceTriangle>& triangles,
                           const PfxVector3& start, const PfxVector3& dir) {
  ReferenceHit best;
  const Eigen::Vector3d o = start.cast<double>();
  const Eigen::Vector3d d = dir.cast<double>();
  for (const ReferenceTriangle& triangle : triangles) {
    const Eigen::Vector3d& e1 = triangle.e1;
    const Eigen::Vector3d& e2 = triangle.e2;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) continue;
    const Eigen::Vector3d s = o - triangle.a;
    const double u = s.dot(p) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    const double f = e2.dot(q) / det;
    const double w = 1 - u - v;
    const double margin = std::min({u, v, w});
    if (margin < -1e-9 || f < 0 || f > 1) continue;
    if (f < best.fraction) best = {true, f, margin, triangle.source};
  }
  return best;
}

// Under the sanitizers a third of the rays: each still walks the tree of every variant,
// which is where a memory error would be, and the reference's 27 million ray-triangle
// tests took 30 s there; the release and double builds cast them all.
#if defined(PFX_TEST_SANITIZED)
constexpr int kBruteForceRays = 500;
#else
constexpr int kBruteForceRays = 1500;
#endif

TEST(LargeTriMesh, RayCastMatchesBruteForceInEveryVariant) {
  const MeshSource soup = makeRandomTriangles(3000, 20, PfxFloat(1.5), 11);
  std::mt19937 rng(3);
  std::uniform_real_distribution<PfxFloat> u(-1, 1);
  for (const PfxUInt32 flags : kAllMeshFlagSets) {
    SCOPED_TRACE(flags);
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, soup.param(flags)), PFX_OK);
    const std::vector<ReferenceTriangle> triangles = referenceTriangles(owner.mesh);
    PfxUInt32 hits = 0;
    for (int r = 0; r < kBruteForceRays; ++r) {
      const PfxVector3 start{u(rng) * 25, u(rng) * 8 + 10, u(rng) * 25};
      const PfxVector3 dir{u(rng) * 20, -30 + u(rng) * 5, u(rng) * 20};
      const ReferenceHit ref = bruteForceRay(triangles, start, dir);
      PfxFloat fraction = -1;
      PfxVector3 normal;
      PfxUInt32 triangle = 0;
      const bool hit = pfxRayCastLargeTriMesh(owner.mesh, start, dir, fraction, normal, triangle);
      // Hits within 1e-6 of an edge may fall to either side in float; clear ones must agree.
      if (ref.hit && ref.margin > 1e-6) {
        ASSERT_TRUE(hit) << "ray " << r;
        EXPECT_NEAR(fraction, ref.fraction, 1e-5 * (1 + ref.fraction)) << "ray " << r;
        ++hits;
      } else if (!ref.hit) {
        ASSERT_FALSE(hit) << "ray " << r;
      }
      if (hit) {
        EXPECT_NEAR(normal.norm(), 1, 1e-5);
        EXPECT_LE(normal.dot(dir), 0);
        ASSERT_LT(triangle, soup.numTriangles());
      }
    }
    EXPECT_GT(hits, PfxUInt32(kBruteForceRays / 5));  // the rays do meet the ground
  }
}

TEST(LargeTriMesh, RayReportsTheCallersTriangleAndTheFaceNormal) {
  // A 4 x 4 grid of unit cells at y = 2; the ray from (0.3, 5, 0.6) down by 10 meets it at
  // y = 2, fraction (5 - 2) / 10 = 0.3. Grid corner (-2, -2); the point lies in cell
  // i = 2, j = 2 (x - x0 = 2.3, z - z0 = 2.6), and z' = 0.6 > x' = 0.3 puts it in the first
  // triangle (a, d, c) of that cell: index 2 * (2 * 4 + 2) = 20.
  const MeshSource grid = makeHeightField(4, 4, 1, [](PfxFloat, PfxFloat) { return PfxFloat(2); });
  for (const PfxUInt32 flags : kAllMeshFlagSets) {
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(flags)), PFX_OK);
    PfxFloat fraction;
    PfxVector3 normal;
    PfxUInt32 triangle;
    ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0.3f, 5, 0.6f), PfxVector3(0, -10, 0),
                                       fraction, normal, triangle));
    EXPECT_NEAR(fraction, 0.3, 1e-5);
    EXPECT_EQ(triangle, 20u);
    EXPECT_NEAR(normal.y(), 1, 1e-6);
    // From below the back face is hit, the normal turned toward the ray.
    ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0.3f, -1, 0.6f), PfxVector3(0, 10, 0),
                                       fraction, normal, triangle));
    EXPECT_NEAR(fraction, 0.3, 1e-5);
    EXPECT_NEAR(normal.y(), -1, 1e-6);
    // Too short, beside, NaN and zero rays miss.
    EXPECT_FALSE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0.3f, 5, 0.6f),
                                        PfxVector3(0, -2.9f, 0), fraction, normal, triangle));
    EXPECT_FALSE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(3, 5, 0), PfxVector3(0, -10, 0),
                                        fraction, normal, triangle));
    EXPECT_FALSE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0, std::nanf(""), 0),
                                        PfxVector3(0, -10, 0), fraction, normal, triangle));
    EXPECT_FALSE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0, 5, 0), PfxVector3::Zero(),
                                        fraction, normal, triangle));
  }
}

// A closed latitude-longitude sphere of radius 1 with shared vertices, outward winding.
MeshSource makeSphereMesh(PfxUInt32 rings, PfxUInt32 segments) {
  MeshSource m;
  m.vertices.insert(m.vertices.end(), {0, 1, 0});
  for (PfxUInt32 r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (PfxUInt32 s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      m.vertices.insert(m.vertices.end(),
                        {PfxFloat(std::sin(theta) * std::cos(phi)), PfxFloat(std::cos(theta)),
                         PfxFloat(std::sin(theta) * std::sin(phi))});
    }
  }
  const PfxUInt32 south = static_cast<PfxUInt32>(m.vertices.size() / 3);
  m.vertices.insert(m.vertices.end(), {0, -1, 0});
  const auto ring = [&](PfxUInt32 r, PfxUInt32 s) { return 1 + (r - 1) * segments + s % segments; };
  for (PfxUInt32 s = 0; s < segments; ++s) {
    m.triangles.insert(m.triangles.end(), {0, ring(1, s + 1), ring(1, s)});
    for (PfxUInt32 r = 1; r + 1 < rings; ++r) {
      const PfxUInt32 a = ring(r, s), b = ring(r, s + 1), c = ring(r + 1, s + 1), d = ring(r + 1, s);
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
    m.triangles.insert(m.triangles.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});
  }
  return m;
}

TEST(LargeTriMesh, RaysAimedAtTheCentreOfAClosedSphereAllHit) {
  const MeshSource sphere = makeSphereMesh(40, 80);
  std::mt19937 rng(5);
  std::normal_distribution<PfxFloat> g(0, 1);
  for (const PfxUInt32 flags : {0u, PFX_MESH_FLAG_USE_BVH,
                                PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED}) {
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, sphere.param(flags)), PFX_OK);
    PfxUInt32 misses = 0;
    for (int r = 0; r < 20000; ++r) {
      PfxVector3 d{g(rng), g(rng), g(rng)};
      d.normalize();
      // Every fourth ray aims at a vertex (the pole or a ring point), where most triangles meet.
      PfxVector3 target = PfxVector3::Zero();
      if (r % 4 == 0) target = sphere.vertex(static_cast<PfxUInt32>(r / 4) % sphere.numVertices()) * PfxFloat(0.5);
      const PfxVector3 start = target + d * 3;
      PfxFloat fraction;
      PfxVector3 normal;
      PfxUInt32 triangle;
      if (!pfxRayCastLargeTriMesh(owner.mesh, start, (target - start) * PfxFloat(1.2), fraction,
                                  normal, triangle)) {
        ++misses;
      }
    }
    EXPECT_EQ(misses, 0u) << "flags " << flags;
  }
}

TEST(LargeTriMesh, DeformationRefitsBoundsAndRays) {
  const MeshSource grid = makeFlatGrid(40, 1);
  std::vector<PfxFloat> moved = grid.vertices;
  // A bump of height 2 at the centre: y = 2 exp(-(x^2 + z^2) / 8).
  for (std::size_t v = 0; v < moved.size(); v += 3) {
    moved[v + 1] = 2 * std::exp(-(moved[v] * moved[v] + moved[v + 2] * moved[v + 2]) / 8);
  }
  for (const PfxUInt32 flags : kAllMeshFlagSets) {
    SCOPED_TRACE(flags);
    MeshOwner owner;
    PfxCreateLargeTriMeshParam p = grid.param(flags);
    p.m_deformationMargin = 3;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, p), PFX_OK);
    ASSERT_EQ(pfxUpdateLargeTriMeshVertices(owner.mesh, moved.data(), grid.numVertices()), PFX_OK);
    const PfxFloat tolerance = quantizationError(owner.mesh) + PfxFloat(1e-5);
    EXPECT_NEAR(owner.mesh.m_aabbMax.y(), 2, tolerance);
    PfxFloat fraction;
    PfxVector3 normal;
    PfxUInt32 triangle;
    // Straight down onto the top of the bump (the vertex at the origin, y = 2) from y = 5.
    ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0, 5, 0), PfxVector3(0, -10, 0),
                                       fraction, normal, triangle));
    EXPECT_NEAR(5 - 10 * fraction, 2, tolerance);
    // The nodes were refitted: every ray agrees with the brute force on the moved mesh.
    const std::vector<ReferenceTriangle> triangles = referenceTriangles(owner.mesh);
    std::mt19937 rng(9);
    std::uniform_real_distribution<PfxFloat> u(-15, 15);
    for (int r = 0; r < 200; ++r) {
      const PfxVector3 start{u(rng), 4, u(rng)};
      const PfxVector3 dir{u(rng) * PfxFloat(0.2), -6, u(rng) * PfxFloat(0.2)};
      const ReferenceHit ref = bruteForceRay(triangles, start, dir);
      if (!ref.hit || ref.margin < 1e-6) continue;
      ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, start, dir, fraction, normal, triangle));
      EXPECT_NEAR(fraction, ref.fraction, 1e-5);
    }
  }
}

TEST(LargeTriMesh, RejectsBadDeformationAndKeepsTheMesh) {
  const MeshSource grid = makeFlatGrid(4, 1);
  for (const PfxUInt32 flags : {0u, PFX_MESH_FLAG_USE_QUANTIZED}) {
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(flags)), PFX_OK);
    const std::vector<unsigned char> before = objectBytes(owner.mesh);
    const std::vector<unsigned char> data(static_cast<unsigned char*>(owner.mesh.m_block),
                                          static_cast<unsigned char*>(owner.mesh.m_block) +
                                              owner.mesh.m_bytes);
    std::vector<PfxFloat> v = grid.vertices;
    EXPECT_EQ(pfxUpdateLargeTriMeshVertices(owner.mesh, nullptr, grid.numVertices()),
              PFX_ERR_NULL_POINTER);
    EXPECT_EQ(pfxUpdateLargeTriMeshVertices(owner.mesh, v.data(), grid.numVertices() - 1),
              PFX_ERR_OUT_OF_RANGE);
    v[7] = std::nanf("");
    EXPECT_EQ(pfxUpdateLargeTriMeshVertices(owner.mesh, v.data(), grid.numVertices()),
              PFX_ERR_INVALID_VALUE);
    if (flags & PFX_MESH_FLAG_USE_QUANTIZED) {
      // Without a margin the quantization box is the creation bounds, x in [-2, 2].
      v = grid.vertices;
      v[0] -= 1;  // x = -3
      EXPECT_EQ(pfxUpdateLargeTriMeshVertices(owner.mesh, v.data(), grid.numVertices()),
                PFX_ERR_OUT_OF_RANGE);
    }
    EXPECT_TRUE(sameBytes(before, owner.mesh));
    EXPECT_TRUE(std::equal(data.begin(), data.end(),
                           static_cast<unsigned char*>(owner.mesh.m_block)));
  }
}

TEST(LargeTriMesh, ReleaseZeroesAndIsSafeTwice) {
  const MeshSource grid = makeFlatGrid(2, 1);
  PfxLargeTriMesh mesh;
  ASSERT_EQ(pfxCreateLargeTriMesh(mesh, grid.param(0)), PFX_OK);
  EXPECT_GT(mesh.m_bytes, 0u);
  pfxReleaseLargeTriMesh(mesh);
  EXPECT_EQ(mesh.m_block, nullptr);
  EXPECT_EQ(mesh.m_numTriangles, 0u);
  pfxReleaseLargeTriMesh(mesh);
  PfxFloat fraction;
  PfxVector3 normal;
  PfxUInt32 triangle;
  EXPECT_FALSE(pfxRayCastLargeTriMesh(mesh, PfxVector3(0, 1, 0), PfxVector3(0, -2, 0), fraction,
                                      normal, triangle));
}

}  // namespace
