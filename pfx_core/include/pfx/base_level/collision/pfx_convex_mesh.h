// A closed convex polyhedron of at most 64 triangles, built by pfxCreateConvexMesh().
// Coplanar triangles are merged into polygon faces, so that a box given as 12 triangles
// collides as six quads and rests on a full four-point manifold.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

constexpr PfxUInt32 PFX_CONVEX_MESH_MAX_FACE_VERTICES = 3 * PFX_CONVEX_MESH_MAX_FACETS;

struct PfxConvexMesh {
  PfxUInt8 m_numVerts;
  PfxUInt8 m_numFacets;  // triangles
  PfxUInt8 m_numEdges;   // unique edges between non-coplanar faces
  PfxUInt8 m_numFaces;   // planar polygons made of one or more coplanar triangles
  PfxVector3 m_verts[PFX_CONVEX_MESH_MAX_VERTICES];
  PfxUInt8 m_facetVertIds[PFX_CONVEX_MESH_MAX_FACETS][3];  // counter-clockwise from outside
  PfxUInt8 m_edgeVertIds[PFX_CONVEX_MESH_MAX_EDGES][2];
  PfxVector3 m_faceNormals[PFX_CONVEX_MESH_MAX_FACETS];  // outward unit normals
  PfxFloat m_facePlaneDist[PFX_CONVEX_MESH_MAX_FACETS];  // dot(normal, point on face)
  PfxUInt8 m_faceFirstVert[PFX_CONVEX_MESH_MAX_FACETS];  // into m_faceVertIds
  PfxUInt8 m_faceNumVerts[PFX_CONVEX_MESH_MAX_FACETS];
  PfxUInt8 m_faceVertIds[PFX_CONVEX_MESH_MAX_FACE_VERTICES];  // polygon loops, counter-clockwise
  PfxVector3 m_aabbCenter;  // local bounds
  PfxVector3 m_aabbHalf;
};

// Builds a convex mesh from a triangle list. Rejects (PFX_ERR_NOT_CONVEX) a mesh with a
// vertex outside any face plane by more than a relative tolerance, or one that is not
// closed, and rejects too many vertices or triangles (PFX_ERR_OUT_OF_RANGE), out-of-range
// indices, NaN vertices (PFX_ERR_INVALID_VALUE) and zero-area triangles or zero volume
// (PFX_ERR_DEGENERATE). Triangle winding may be either way: it is made outward here.
// `mesh` is only written on success.
PfxInt32 pfxCreateConvexMesh(PfxConvexMesh& mesh, const PfxFloat* vertices, PfxUInt32 numVertices,
                             const PfxUInt16* indices, PfxUInt32 numIndices);

}  // namespace pfx
