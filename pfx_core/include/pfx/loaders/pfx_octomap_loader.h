// OctoMap files (.bt and .ot, through liboctomap) into static collision geometry: one fixed
// body holding a large mesh of the faces between occupied and not-occupied cells, merged
// per plane into rectangles (a room of 100,000 voxels becomes a few hundred triangles).
// Bodies rest on it and rays hit it through the large mesh's hierarchy; see
// pfx_octomap_loader.cpp for why this and not a box per voxel.
#pragma once

#include <string>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_world.h"

namespace pfx {

struct PfxOctomapLoadParam {
  PfxVector3 position = PfxVector3::Zero();  // pose of the map's frame in the world
  PfxQuat orientation = PfxQuat::Identity();
  PfxFloat friction = PfxFloat(0.6);
  PfxFloat restitution = 0;
  PfxUInt32 meshFlags = PFX_MESH_FLAG_USE_BVH;  // PFX_MESH_FLAG_* of the large mesh
  // Depth of the prism below each face (PfxCreateLargeTriMeshParam::m_thickness), in voxels
  // of the finest resolution, in (0, 1). Occupied structures are one voxel thick at least;
  // a deeper prism would reach out of a wall's far side and push bodies resting there into
  // the wall. Bodies that sink deeper than the prism are pushed out all the same while
  // their centre is in front of the face.
  PfxFloat thicknessPerVoxel = PfxFloat(0.1);
};

// The occupied voxels of a map as one fixed body. The map owns its geometry: keep it alive
// as long as the world holds the body; its destructor releases the mesh.
struct PfxOctomap {
  PfxUInt32 bodyId = 0;
  PfxUInt64 numOccupiedVoxels = 0;  // at the finest resolution (a pruned leaf counts its cells)
  PfxFloat resolution = 0;          // m
  PfxLargeTriMesh mesh{};
  bool meshCreated = false;
  PfxOctomap() = default;
  PfxOctomap(const PfxOctomap&) = delete;
  PfxOctomap& operator=(const PfxOctomap&) = delete;
  ~PfxOctomap();
};

// Reads the map (the format is told by the file's first line, not by its extension) and
// adds its occupied cells as one fixed body at param's pose, in whatever up convention the
// world uses (OctoMaps are usually Z up: give the world a gravity along -Z). Occupied
// means liboctomap's isNodeOccupied; a pruned leaf is a cube of its own size; free and
// unknown space and the map's outside are open. `map` must not hold a loaded map.
// On error returns a code, writes "<file>: <reason>" into *message (when not null) and
// leaves the world and `map` unchanged: PFX_ERR_INVALID_VALUE for a missing or unreadable
// file, a file that is not an OctoMap, a broken header, node data cut off or deeper than
// the tree's 16 levels, a .ot tree that is not an OcTree, a NaN or non-unit pose, negative
// friction or restitution, a thickness outside (0, 1), or a `map` already loaded;
// PFX_ERR_DEGENERATE for a map without occupied voxels; what pfxCreateLargeTriMesh and
// PfxWorld::addRigidBody reject, with their codes. Files are checked before liboctomap
// reads them, so a corrupted one is refused rather than read past its end, and nothing is
// printed.
PfxInt32 pfxLoadOctomapFile(PfxWorld& world, const std::string& path,
                            const PfxOctomapLoadParam& param, PfxOctomap& map,
                            std::string* message = nullptr);

}  // namespace pfx
