// A box or a convex mesh seen the same way by the separating-axis test: vertices, polygon
// faces with outward planes, and edges that know their two faces (for the Gauss-map test
// that skips edge pairs which cannot separate).
#pragma once

#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

// Marks an edge face that could not be found (a mesh whose edges and face loops disagree);
// such an edge is tested against every edge of the other shape.
constexpr PfxUInt8 PFX_POLYHEDRON_NO_FACE = 0xFF;

struct PfxPolyhedron {
  PfxUInt32 m_numVerts;
  PfxUInt32 m_numFaces;
  PfxUInt32 m_numEdges;
  const PfxVector3* m_verts;
  const PfxVector3* m_faceNormals;
  const PfxFloat* m_facePlaneDist;
  const PfxUInt8* m_faceFirstVert;
  const PfxUInt8* m_faceNumVerts;
  const PfxUInt8* m_faceVertIds;
  const PfxUInt8 (*m_edgeVertIds)[2];
  const PfxUInt8 (*m_edgeFaces)[2];
  PfxVector3 m_centroid;  // strictly inside unless the shape is flat; orients edge axes

  // A box's own vertices and planes live here; a mesh's are referenced in place.
  PfxVector3 m_boxVerts[8];
  PfxFloat m_boxPlaneDist[6];
  PfxUInt8 m_meshEdgeFaces[PFX_CONVEX_MESH_MAX_EDGES][2];

  // Builds the view of a box or convex-mesh shape, in the shape's own frame.
  void build(const PfxShape& shape);

  PfxVector3 faceVertex(PfxUInt32 face, PfxUInt32 k) const {
    return m_verts[m_faceVertIds[m_faceFirstVert[face] + k]];
  }
};

}  // namespace pfx
