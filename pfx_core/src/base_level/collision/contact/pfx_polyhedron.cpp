#include "base_level/collision/contact/pfx_polyhedron.h"

#include <cstring>

namespace pfx {

namespace {

// Vertex k of a box has coordinate i at +half when bit i of k is set, else at -half.
// Faces +X, -X, +Y, -Y, +Z, -Z, each counter-clockwise seen from outside.
const PfxVector3 kBoxFaceNormals[6] = {PfxVector3(1, 0, 0),  PfxVector3(-1, 0, 0),
                                       PfxVector3(0, 1, 0),  PfxVector3(0, -1, 0),
                                       PfxVector3(0, 0, 1),  PfxVector3(0, 0, -1)};
const PfxUInt8 kBoxFaceFirstVert[6] = {0, 4, 8, 12, 16, 20};
const PfxUInt8 kBoxFaceNumVerts[6] = {4, 4, 4, 4, 4, 4};
const PfxUInt8 kBoxFaceVertIds[24] = {1, 3, 7, 5, 0, 4, 6, 2, 2, 6, 7, 3,
                                      0, 1, 5, 4, 4, 5, 7, 6, 0, 2, 3, 1};
const PfxUInt8 kBoxEdgeVertIds[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                         {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
const PfxUInt8 kBoxEdgeFaces[12][2] = {{3, 5}, {2, 5}, {3, 4}, {2, 4}, {1, 5}, {0, 5},
                                       {1, 4}, {0, 4}, {1, 3}, {0, 3}, {1, 2}, {0, 2}};

}  // namespace

void PfxPolyhedron::build(const PfxShape& shape) {
  if (shape.getType() == kPfxShapeBox) {
    const PfxVector3 half = shape.getBox().m_half;
    for (int k = 0; k < 8; ++k) {
      m_boxVerts[k] = PfxVector3((k & 1) ? half[0] : -half[0], (k & 2) ? half[1] : -half[1],
                                 (k & 4) ? half[2] : -half[2]);
    }
    for (int f = 0; f < 6; ++f) m_boxPlaneDist[f] = half[f / 2];
    m_numVerts = 8;
    m_numFaces = 6;
    m_numEdges = 12;
    m_verts = m_boxVerts;
    m_faceNormals = kBoxFaceNormals;
    m_facePlaneDist = m_boxPlaneDist;
    m_faceFirstVert = kBoxFaceFirstVert;
    m_faceNumVerts = kBoxFaceNumVerts;
    m_faceVertIds = kBoxFaceVertIds;
    m_edgeVertIds = kBoxEdgeVertIds;
    m_edgeFaces = kBoxEdgeFaces;
    m_centroid.setZero();
    return;
  }

  const PfxConvexMesh& mesh = *shape.getConvexMesh();
  m_numVerts = mesh.m_numVerts;
  m_numFaces = mesh.m_numFaces;
  m_numEdges = mesh.m_numEdges;
  m_verts = mesh.m_verts;
  m_faceNormals = mesh.m_faceNormals;
  m_facePlaneDist = mesh.m_facePlaneDist;
  m_faceFirstVert = mesh.m_faceFirstVert;
  m_faceNumVerts = mesh.m_faceNumVerts;
  m_faceVertIds = mesh.m_faceVertIds;
  m_edgeVertIds = mesh.m_edgeVertIds;

  // Each directed edge a->b of a counter-clockwise face loop belongs to that face; the
  // undirected edge's other face walks it as b->a.
  PfxUInt8 faceOfDirectedEdge[PFX_CONVEX_MESH_MAX_VERTICES][PFX_CONVEX_MESH_MAX_VERTICES];
  std::memset(faceOfDirectedEdge, PFX_POLYHEDRON_NO_FACE, sizeof(faceOfDirectedEdge));
  for (PfxUInt32 f = 0; f < m_numFaces; ++f) {
    const PfxUInt32 first = mesh.m_faceFirstVert[f];
    const PfxUInt32 count = mesh.m_faceNumVerts[f];
    for (PfxUInt32 k = 0; k < count; ++k) {
      const PfxUInt8 a = mesh.m_faceVertIds[first + k];
      const PfxUInt8 b = mesh.m_faceVertIds[first + (k + 1) % count];
      if (a < PFX_CONVEX_MESH_MAX_VERTICES && b < PFX_CONVEX_MESH_MAX_VERTICES) {
        faceOfDirectedEdge[a][b] = static_cast<PfxUInt8>(f);
      }
    }
  }
  for (PfxUInt32 e = 0; e < m_numEdges; ++e) {
    const PfxUInt8 a = mesh.m_edgeVertIds[e][0];
    const PfxUInt8 b = mesh.m_edgeVertIds[e][1];
    const bool inRange = a < PFX_CONVEX_MESH_MAX_VERTICES && b < PFX_CONVEX_MESH_MAX_VERTICES;
    m_meshEdgeFaces[e][0] = inRange ? faceOfDirectedEdge[a][b] : PFX_POLYHEDRON_NO_FACE;
    m_meshEdgeFaces[e][1] = inRange ? faceOfDirectedEdge[b][a] : PFX_POLYHEDRON_NO_FACE;
  }
  m_edgeFaces = m_meshEdgeFaces;

  PfxVector3 sum = PfxVector3::Zero();
  for (PfxUInt32 v = 0; v < m_numVerts; ++v) sum += m_verts[v];
  m_centroid = m_numVerts > 0 ? PfxVector3(sum / PfxFloat(m_numVerts)) : PfxVector3::Zero();
}

}  // namespace pfx
