// Triangle meshes from files (assimp: STL, Collada, OBJ and the rest it reads), and the two
// shapes a mesh becomes: a convex hull for a moving body (qhull), a large mesh for a static
// one. No ROS here: URIs are resolved by the URDF loader before a path reaches these.
#pragma once

#include <string>
#include <vector>

#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

// Depth of the prism below each face of a large mesh made from a mesh file (m). Mesh files
// mostly describe closed solids, and a prism deeper than the solid is thick reaches out of
// its far side, where it pushes a body resting there into the solid; 2 mm stays inside
// sheet-metal parts. Bodies that sink deeper are still pushed out as long as their centre
// stays in front of the face: the contact routines measure the overlap, not the prism.
constexpr PfxFloat PFX_MESH_DEFAULT_THICKNESS = PfxFloat(0.002);

// A plain triangle list: xyz per vertex, three vertex indices per triangle.
struct PfxTriangleMesh {
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
};

// Reads every mesh of the file's scene, node transforms applied, each vertex multiplied by
// `scale` per axis. Collada's <unit> scales the scene, as assimp reads it; its <up_axis> is
// ignored, as rviz and MoveIt ignore it (assimp would turn Z-up files to Y-up), so that
// collision geometry lies where rviz draws the same file. Polygons are triangulated; points
// and lines are dropped. Corners with identical coordinates become one vertex across the
// whole scene (an STL cube gives 8 vertices, 12 triangles), and a triangle left with a
// repeated corner is dropped. On error returns a PFX_ERR_* code, leaves `mesh` untouched and
// writes "<file>: <reason>" into *message (when not null): a scale that is not positive and
// finite, a missing file or one assimp cannot read (PFX_ERR_INVALID_VALUE), a NaN or
// infinite vertex (PFX_ERR_INVALID_VALUE), a scene without triangles (PFX_ERR_DEGENERATE).
PfxInt32 pfxLoadMeshFile(const std::string& path, const PfxVector3& scale, PfxTriangleMesh& mesh,
                         std::string* message = nullptr);

// What pfxCreateConvexHull made, for logs and warnings.
struct PfxConvexHullInfo {
  PfxUInt32 numHullVertices = 0;  // corners of the true hull
  double hullVolume = 0;          // of the true hull
  double volume = 0;              // of the convex mesh made: less when it was simplified
};

// The convex hull of the mesh's vertices (qhull) as a PfxConvexMesh. When the hull has more
// than PFX_CONVEX_MESH_MAX_VERTICES corners it is replaced by the hull of 34 of them, chosen
// greedily, each the corner that adds the most volume to the hull of those already chosen:
// it lies inside the true hull (volume lost on the KUKA iiwa links: see the README).
// Rejects a vertex array whose length is not a multiple of 3 (PFX_ERR_OUT_OF_RANGE), a NaN
// or infinite vertex (PFX_ERR_INVALID_VALUE), fewer than 4 vertices, and vertices that lie
// on one point, line or plane within 1e-4 of their bounds' diagonal (PFX_ERR_DEGENERATE).
// On error `hull` is untouched and *message says "convex hull: <reason>" (the caller knows
// the file). qhull prints nothing. On success *info (when not null) says how far the hull
// was simplified.
PfxInt32 pfxCreateConvexHull(const PfxTriangleMesh& mesh, PfxConvexMesh& hull,
                             std::string* message = nullptr, PfxConvexHullInfo* info = nullptr);

// A large mesh (for a static body) from the triangle list, through pfxCreateLargeTriMesh:
// zero-area triangles are dropped and counted in m_numDroppedTriangles; `flags` are the
// PFX_MESH_FLAG_* and `thickness` the depth of the prism below each face
// (PfxCreateLargeTriMeshParam::m_thickness). Rejects what pfxCreateLargeTriMesh rejects,
// with its code, and an empty mesh (PFX_ERR_OUT_OF_RANGE); `largeMesh` is only written on
// success and must not hold a live mesh. Release it with pfxReleaseLargeTriMesh.
PfxInt32 pfxCreateLargeTriMeshFromMesh(const PfxTriangleMesh& mesh, PfxUInt32 flags,
                                       PfxLargeTriMesh& largeMesh, std::string* message = nullptr,
                                       PfxFloat thickness = PFX_MESH_DEFAULT_THICKNESS);

}  // namespace pfx
