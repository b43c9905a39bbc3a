#include "pfx/base_level/collision/pfx_convex_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "pfx/base_level/base/pfx_utility_allocator.h"

namespace pfx {

namespace {

// The geometry is checked in double: every input coordinate is exact there, so the plane
// tests below measure the input, not our own round-off.
using Vec3d = Eigen::Vector3d;

constexpr int kMaxIndices = 3 * PFX_CONVEX_MESH_MAX_FACETS;
constexpr int kConvexMeshMaxVertices = PFX_CONVEX_MESH_MAX_VERTICES;
constexpr int kMaxFacets = PFX_CONVEX_MESH_MAX_FACETS;

// Distances are measured against the diagonal of the mesh's bounds. A vertex this far
// outside a triangle's plane (relative) still counts as on it: exporters write coordinates
// with about six significant digits, and a bump this small is invisible to a contact.
constexpr double kPlaneTolerance = 1e-4;
// Round-off level of the double arithmetic, relative to the diagonal (for lengths) or its
// square (for twice a triangle's area): below it a triangle has no well-defined normal and
// a point no well-defined side of a plane.
constexpr double kRelativeZero = 1e-12;
// Adjacent triangles join one face only if their normals are also within about 0.01 rad:
// the distance test alone would fold a small bevel triangle into the large face next to it
// and lose the bevel's edges.
constexpr double kCoplanarCos = 0.99995;

struct WorkMesh {
  Vec3d verts[kConvexMeshMaxVertices];
  PfxFloat floatVerts[kConvexMeshMaxVertices][3];
  int numVerts = 0;
  int tris[kMaxFacets][3];
  Vec3d triNormals[kMaxFacets];  // unit
  Vec3d triAreaVectors[kMaxFacets];  // cross products, twice the area
  int neighbors[kMaxFacets][3];  // across edge (tris[t][k], tris[t][(k+1)%3])
  int numTris = 0;
  double scale = 0;  // diagonal of the bounds
  int triFace[kMaxFacets];
};

// Maps every referenced input vertex to a compact id. Vertices with identical coordinates
// become one: triangle soups (STL, or meshes split for texture seams) repeat a corner once
// per triangle, and without welding no edge would be shared. Ids follow the input vertex
// order, so an already compact input keeps its numbering.
PfxInt32 compactVertices(const PfxFloat* vertices, const PfxUInt16* indices, int numIndices,
                         WorkMesh& work) {
  PfxUInt16 used[kMaxIndices];
  std::copy(indices, indices + numIndices, used);
  std::sort(used, used + numIndices);
  const int numUsed = static_cast<int>(std::unique(used, used + numIndices) - used);

  for (int u = 0; u < numUsed; ++u) {
    const PfxFloat* p = vertices + 3 * used[u];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      return PFX_ERR_INVALID_VALUE;
    }
  }

  int compactIdOfUsed[kMaxIndices];
  for (int u = 0; u < numUsed; ++u) {
    const PfxFloat* p = vertices + 3 * used[u];
    int id = 0;
    while (id < work.numVerts && !(work.floatVerts[id][0] == p[0] &&
                                   work.floatVerts[id][1] == p[1] &&
                                   work.floatVerts[id][2] == p[2])) {
      ++id;
    }
    if (id == work.numVerts) {
      if (work.numVerts == kConvexMeshMaxVertices) return PFX_ERR_OUT_OF_RANGE;
      std::copy(p, p + 3, work.floatVerts[id]);
      work.verts[id] = Vec3d(p[0], p[1], p[2]);
      ++work.numVerts;
    }
    compactIdOfUsed[u] = id;
  }

  work.numTris = numIndices / 3;
  for (int i = 0; i < numIndices; ++i) {
    const int u = static_cast<int>(std::lower_bound(used, used + numUsed, indices[i]) - used);
    work.tris[i / 3][i % 3] = compactIdOfUsed[u];
  }
  return PFX_OK;
}

PfxInt32 computeTriangleNormals(WorkMesh& work) {
  Vec3d lo = work.verts[0], hi = work.verts[0];
  for (int v = 1; v < work.numVerts; ++v) {
    lo = lo.cwiseMin(work.verts[v]);
    hi = hi.cwiseMax(work.verts[v]);
  }
  work.scale = (hi - lo).norm();

  for (int t = 0; t < work.numTris; ++t) {
    const int* tri = work.tris[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return PFX_ERR_DEGENERATE;
    const Vec3d& a = work.verts[tri[0]];
    const Vec3d areaVector = (work.verts[tri[1]] - a).cross(work.verts[tri[2]] - a);
    const double twiceArea = areaVector.norm();
    if (twiceArea <= kRelativeZero * work.scale * work.scale) return PFX_ERR_DEGENERATE;
    work.triAreaVectors[t] = areaVector;
    work.triNormals[t] = areaVector / twiceArea;
  }
  return PFX_OK;
}

int countUndirectedEdge(const WorkMesh& work, int a, int b) {
  int count = 0;
  for (int t = 0; t < work.numTris; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int p = work.tris[t][k], q = work.tris[t][(k + 1) % 3];
      if ((p == a && q == b) || (p == b && q == a)) ++count;
    }
  }
  return count;
}

// A closed surface uses every edge in exactly two triangles.
bool isClosedManifold(const WorkMesh& work) {
  for (int t = 0; t < work.numTris; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (countUndirectedEdge(work, work.tris[t][k], work.tris[t][(k + 1) % 3]) != 2) return false;
    }
  }
  return true;
}

// All vertices within tolerance of the plane of the largest triangle: the solid has no
// volume.
bool isFlat(const WorkMesh& work) {
  int largest = 0;
  for (int t = 1; t < work.numTris; ++t) {
    if (work.triAreaVectors[t].squaredNorm() > work.triAreaVectors[largest].squaredNorm()) {
      largest = t;
    }
  }
  const Vec3d& normal = work.triNormals[largest];
  const double planeDist = normal.dot(work.verts[work.tris[largest][0]]);
  for (int v = 0; v < work.numVerts; ++v) {
    if (std::abs(normal.dot(work.verts[v]) - planeDist) > kPlaneTolerance * work.scale) {
      return false;
    }
  }
  return true;
}

// The mean of the vertices of a convex solid lies strictly inside it, so each triangle can
// be turned to face away from it on its own; a triangle whose plane passes through the mean
// cannot belong to a convex solid with volume.
PfxInt32 orientOutward(WorkMesh& work) {
  Vec3d centroid = Vec3d::Zero();
  for (int v = 0; v < work.numVerts; ++v) centroid += work.verts[v];
  centroid /= work.numVerts;
  for (int t = 0; t < work.numTris; ++t) {
    const double side = work.triNormals[t].dot(work.verts[work.tris[t][0]] - centroid);
    if (std::abs(side) <= kRelativeZero * work.scale) return PFX_ERR_NOT_CONVEX;
    if (side < 0) {
      std::swap(work.tris[t][1], work.tris[t][2]);
      work.triNormals[t] = -work.triNormals[t];
      work.triAreaVectors[t] = -work.triAreaVectors[t];
    }
  }
  return PFX_OK;
}

// Once outward, two triangles sharing an edge run along it in opposite directions; a
// surface that folds back over itself does not. Fills the neighbour across each edge.
bool findNeighbors(WorkMesh& work) {
  for (int t = 0; t < work.numTris; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = work.tris[t][k], b = work.tris[t][(k + 1) % 3];
      int numReverse = 0;
      for (int u = 0; u < work.numTris; ++u) {
        for (int j = 0; j < 3; ++j) {
          if (work.tris[u][j] == b && work.tris[u][(j + 1) % 3] == a) {
            work.neighbors[t][k] = u;
            ++numReverse;
          }
        }
      }
      if (numReverse != 1) return false;
    }
  }
  return true;
}

bool isConvex(const WorkMesh& work) {
  for (int t = 0; t < work.numTris; ++t) {
    const Vec3d& normal = work.triNormals[t];
    const double planeDist = normal.dot(work.verts[work.tris[t][0]]);
    for (int v = 0; v < work.numVerts; ++v) {
      if (normal.dot(work.verts[v]) - planeDist > kPlaneTolerance * work.scale) return false;
    }
  }
  return true;
}

bool isCoplanarWith(const WorkMesh& work, int t, const Vec3d& normal, double planeDist) {
  if (work.triNormals[t].dot(normal) < kCoplanarCos) return false;
  for (int k = 0; k < 3; ++k) {
    const double offPlane = normal.dot(work.verts[work.tris[t][k]]) - planeDist;
    if (std::abs(offPlane) > kPlaneTolerance * work.scale) return false;
  }
  return true;
}

// Grows each face from its first triangle across shared edges, testing every new triangle
// against the seed's plane rather than its neighbour's, so that a slowly curving strip of
// almost coplanar triangles cannot chain into one bent face.
int groupFaces(WorkMesh& work) {
  std::fill(work.triFace, work.triFace + work.numTris, -1);
  int numFaces = 0;
  for (int seed = 0; seed < work.numTris; ++seed) {
    if (work.triFace[seed] >= 0) continue;
    const int face = numFaces++;
    const Vec3d& normal = work.triNormals[seed];
    const double planeDist = normal.dot(work.verts[work.tris[seed][0]]);
    int queue[kMaxFacets];
    int head = 0, tail = 0;
    queue[tail++] = seed;
    work.triFace[seed] = face;
    while (head < tail) {
      const int t = queue[head++];
      for (int k = 0; k < 3; ++k) {
        const int u = work.neighbors[t][k];
        if (work.triFace[u] >= 0 || !isCoplanarWith(work, u, normal, planeDist)) continue;
        work.triFace[u] = face;
        queue[tail++] = u;
      }
    }
  }
  return numFaces;
}

// Writes the boundary of a face as one counter-clockwise loop starting at its lowest vertex
// id. The face's triangles run counter-clockwise seen from outside, so their edges that
// border other faces chain head to tail in that same sense. Returns the loop length, or 0
// when the boundary is not one simple loop.
int traceFaceLoop(const WorkMesh& work, int face, PfxUInt8* loop) {
  int next[kConvexMeshMaxVertices];
  std::fill(next, next + kConvexMeshMaxVertices, -1);
  int numBoundaryEdges = 0;
  int start = kConvexMeshMaxVertices;
  for (int t = 0; t < work.numTris; ++t) {
    if (work.triFace[t] != face) continue;
    for (int k = 0; k < 3; ++k) {
      if (work.triFace[work.neighbors[t][k]] == face) continue;
      const int a = work.tris[t][k], b = work.tris[t][(k + 1) % 3];
      if (next[a] >= 0) return 0;
      next[a] = b;
      start = std::min(start, a);
      ++numBoundaryEdges;
    }
  }
  if (numBoundaryEdges == 0) return 0;
  int length = 0;
  int v = start;
  do {
    if (length == numBoundaryEdges || next[v] < 0) return 0;
    loop[length++] = static_cast<PfxUInt8>(v);
    v = next[v];
  } while (v != start);
  return length == numBoundaryEdges ? length : 0;
}

PfxInt32 buildFaces(WorkMesh& work, PfxConvexMesh& out) {
  const int numFaces = groupFaces(work);
  int numFaceVerts = 0;
  for (int face = 0; face < numFaces; ++face) {
    Vec3d areaVector = Vec3d::Zero();
    for (int t = 0; t < work.numTris; ++t) {
      if (work.triFace[t] == face) areaVector += work.triAreaVectors[t];
    }
    const Vec3d normal = areaVector.normalized();
    // The plane is put through the outermost vertex, so that it supports the mesh exactly
    // as the vertices do and a separating-axis test along it agrees with one on the vertices.
    double planeDist = normal.dot(work.verts[0]);
    for (int v = 1; v < work.numVerts; ++v) planeDist = std::max(planeDist, normal.dot(work.verts[v]));

    const int length = traceFaceLoop(work, face, out.m_faceVertIds + numFaceVerts);
    if (length == 0) return PFX_ERR_NOT_CONVEX;
    out.m_faceNormals[face] = normal.cast<PfxFloat>();
    out.m_facePlaneDist[face] = static_cast<PfxFloat>(planeDist);
    out.m_faceFirstVert[face] = static_cast<PfxUInt8>(numFaceVerts);
    out.m_faceNumVerts[face] = static_cast<PfxUInt8>(length);
    numFaceVerts += length;
  }
  out.m_numFaces = static_cast<PfxUInt8>(numFaces);

  // Each edge once, from the triangle that runs along it from the lower id to the higher,
  // and only where two faces meet at an angle: edges inside a face are no separating axis.
  int numEdges = 0;
  for (int t = 0; t < work.numTris; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = work.tris[t][k], b = work.tris[t][(k + 1) % 3];
      if (a > b || work.triFace[work.neighbors[t][k]] == work.triFace[t]) continue;
      out.m_edgeVertIds[numEdges][0] = static_cast<PfxUInt8>(a);
      out.m_edgeVertIds[numEdges][1] = static_cast<PfxUInt8>(b);
      ++numEdges;
    }
  }
  out.m_numEdges = static_cast<PfxUInt8>(numEdges);
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxCreateConvexMesh(PfxConvexMesh& mesh, const PfxFloat* vertices, PfxUInt32 numVertices,
                             const PfxUInt16* indices, PfxUInt32 numIndices) {
  if (!vertices || !indices) return PFX_ERR_NULL_POINTER;
  if (numIndices == 0 || numIndices % 3 != 0 || numIndices > PfxUInt32(kMaxIndices)) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  for (PfxUInt32 i = 0; i < numIndices; ++i) {
    if (indices[i] >= numVertices) return PFX_ERR_OUT_OF_RANGE;
  }

  WorkMesh work;
  PfxInt32 err = compactVertices(vertices, indices, static_cast<int>(numIndices), work);
  if (err != PFX_OK) return err;
  err = computeTriangleNormals(work);
  if (err != PFX_OK) return err;
  if (!isClosedManifold(work)) return PFX_ERR_NOT_CONVEX;
  if (isFlat(work)) return PFX_ERR_DEGENERATE;
  err = orientOutward(work);
  if (err != PFX_OK) return err;
  if (!findNeighbors(work) || !isConvex(work)) return PFX_ERR_NOT_CONVEX;

  // Built aside and copied at the end, so that a mesh rejected half-way leaves `mesh` as it
  // was. Zeroed first so that unused slots are the same bytes every time (serialization).
  PfxConvexMesh out;
  std::memset(static_cast<void*>(&out), 0, sizeof(out));
  err = buildFaces(work, out);
  if (err != PFX_OK) return err;

  out.m_numVerts = static_cast<PfxUInt8>(work.numVerts);
  for (int v = 0; v < work.numVerts; ++v) {
    out.m_verts[v] = PfxVector3(work.floatVerts[v][0], work.floatVerts[v][1], work.floatVerts[v][2]);
  }
  PfxVector3 lo = out.m_verts[0], hi = out.m_verts[0];
  for (int v = 1; v < work.numVerts; ++v) {
    lo = lo.cwiseMin(out.m_verts[v]);
    hi = hi.cwiseMax(out.m_verts[v]);
  }
  out.m_aabbCenter = (lo + hi) * PfxFloat(0.5);
  out.m_aabbHalf = (hi - lo) * PfxFloat(0.5);

  out.m_numFacets = static_cast<PfxUInt8>(work.numTris);
  for (int t = 0; t < work.numTris; ++t) {
    for (int k = 0; k < 3; ++k) out.m_facetVertIds[t][k] = static_cast<PfxUInt8>(work.tris[t][k]);
  }

  // Byte copy, padding included, so that equal meshes serialize to equal bytes.
  std::memcpy(static_cast<void*>(&mesh), &out, sizeof(out));
  return PFX_OK;
}

PfxConvexMesh* pfxNewConvexMesh() {
  auto* mesh =
      static_cast<PfxConvexMesh*>(pfxUtilityAllocate(sizeof(PfxConvexMesh), PFX_BUFFER_ALIGNMENT));
  if (mesh) std::memset(static_cast<void*>(mesh), 0, sizeof(*mesh));
  return mesh;
}

void pfxDeleteConvexMesh(PfxConvexMesh* mesh) { pfxUtilityFree(mesh); }

}  // namespace pfx
