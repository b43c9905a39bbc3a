// Triangle meshes from files (assimp: STL, Collada, OBJ and the rest it reads), and the two
// shapes a mesh becomes: a convex hull for a moving body (qhull), a large mesh for a static
// one. No ROS here: URIs are resolved by the URDF loader before a path reaches these.
#pragma once

#include <string>
#include <vector>

#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

// A plain triangle list: xyz per vertex, three vertex indices per triangle.
struct PfxTriangleMesh {
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
};

// Reads every mesh of the file's scene, node transforms applied, each vertex multiplied by
// `scale` per axis. On error returns a PFX_ERR_* code, leaves `mesh` untouched and writes a
// sentence naming the file and the reason into *message (when not null).
PfxInt32 pfxLoadMeshFile(const std::string& path, const PfxVector3& scale, PfxTriangleMesh& mesh,
                         std::string* message = nullptr);

// The convex hull of the mesh's vertices as a PfxConvexMesh, simplified to the convex mesh's
// limits (vertices and triangles) when the hull has more. Same error contract as above.
PfxInt32 pfxCreateConvexHull(const PfxTriangleMesh& mesh, PfxConvexMesh& hull,
                             std::string* message = nullptr);

}  // namespace pfx
