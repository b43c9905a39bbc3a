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

// Builds a convex mesh from a triangle list (xyz per vertex, three indices per triangle).
// Vertices no triangle uses are dropped and vertices with identical coordinates are
// welded, so a triangle soup works. Rejects null arrays (PFX_ERR_NULL_POINTER); no
// triangles, an index count that is not a multiple of 3, an out-of-range index, more than
// 64 triangles or 34 distinct vertices (PFX_ERR_OUT_OF_RANGE); a NaN or infinite vertex
// (PFX_ERR_INVALID_VALUE); a zero-area triangle or zero volume (PFX_ERR_DEGENERATE); a
// surface that is not closed (every edge in exactly two triangles) or a vertex outside any
// triangle's plane by more than 1e-4 of the bounds' diagonal (PFX_ERR_NOT_CONVEX).
// Triangle winding may be either way: it is made outward here. `mesh` is only written on
// success.
PfxInt32 pfxCreateConvexMesh(PfxConvexMesh& mesh, const PfxFloat* vertices, PfxUInt32 numVertices,
                             const PfxUInt16* indices, PfxUInt32 numIndices);

// A zeroed convex mesh from the utility allocator (pfx_utility_allocator.h), for meshes
// that live on the heap (a loader's, a serialized file's); null when out of memory.
PfxConvexMesh* pfxNewConvexMesh();
// Frees a mesh that pfxNewConvexMesh made. Safe on null.
void pfxDeleteConvexMesh(PfxConvexMesh* mesh);

}  // namespace pfx
