// OctoMap files (.bt and .ot, through liboctomap) into static collision geometry.
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
  PfxUInt32 meshFlags = PFX_MESH_FLAG_USE_BVH;
};

// The occupied voxels of a map as one fixed body. The map owns its geometry: keep it alive
// as long as the world holds the body; its destructor releases the mesh.
struct PfxOctomap {
  PfxUInt32 bodyId = 0;
  PfxUInt32 numOccupiedVoxels = 0;  // leaves at the finest resolution
  PfxFloat resolution = 0;          // m
  PfxLargeTriMesh mesh{};
  bool meshCreated = false;
  PfxOctomap() = default;
  PfxOctomap(const PfxOctomap&) = delete;
  PfxOctomap& operator=(const PfxOctomap&) = delete;
  ~PfxOctomap();
};

// Same error contract as the URDF loader: code, message naming the file and reason, world
// and `map` unchanged on error.
PfxInt32 pfxLoadOctomapFile(PfxWorld& world, const std::string& path,
                            const PfxOctomapLoadParam& param, PfxOctomap& map,
                            std::string* message = nullptr);

}  // namespace pfx
