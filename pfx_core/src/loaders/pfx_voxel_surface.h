// The surface of a set of voxels as one triangle mesh: exposed squares of cube faces are
// merged per plane into rectangles, and the rectangles are triangulated so that every edge
// they share is an edge of both sides' triangles.
#pragma once

#include <vector>

#include "pfx/loaders/pfx_mesh_loader.h"

namespace pfx {

// An exposed square on the face of a cube, in units of the finest cell. Cell boundaries are
// numbered so that a cube [k, k + size) along an axis has faces on planes k and k + size.
struct PfxVoxelFace {
  PfxUInt8 axis;      // of the face normal, 0..2
  PfxUInt8 positive;  // 1: the normal points along +axis
  PfxUInt32 plane;    // boundary index along `axis`
  PfxUInt32 u;        // lower corner along (axis + 1) % 3
  PfxUInt32 v;        // lower corner along (axis + 2) % 3
  PfxUInt32 size;     // side length in cells, a power of two
};

// Boundary indices must be below 2^17. Vertex i of `mesh` lies at
// (boundary index - origin) * cellSize per axis. Triangles are counter-clockwise seen from
// the side the face normal points to. `faces` is reordered.
void pfxMeshVoxelFaces(std::vector<PfxVoxelFace>& faces, PfxInt32 origin, double cellSize,
                       PfxTriangleMesh& mesh);

}  // namespace pfx
