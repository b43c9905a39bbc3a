// The rays scene on pfx: the terrain as a large triangle mesh in each storage variant,
// cast directly (pfxRayCastLargeTriMesh) and as the one body of a PfxWorld (castRay one at
// a time, castRays in one call).
#include <string>
#include <vector>

#include "bench_rays.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfxbench {

namespace {

using namespace pfx;

struct StorageVariant {
  const char* name;
  PfxUInt32 flags;
};

constexpr StorageVariant kStorageVariants[] = {
    {"array", 0},
    {"bvh", PFX_MESH_FLAG_USE_BVH},
    {"array_quantized", PFX_MESH_FLAG_USE_QUANTIZED},
    {"bvh_quantized", PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED},
    {"array_hq", PFX_MESH_FLAG_HIGH_QUALITY},
    {"bvh_hq", PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_HIGH_QUALITY},
    {"array_quantized_hq", PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY},
    {"bvh_quantized_hq",
     PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY},
};

// Releases the mesh however the scope is left.
struct MeshOwner {
  PfxLargeTriMesh mesh{};
  ~MeshOwner() { pfxReleaseLargeTriMesh(mesh); }
};

bool buildMesh(const RayTerrain& terrain, PfxUInt32 flags, MeshOwner& owner, double& seconds,
               std::string& error) {
  PfxCreateLargeTriMeshParam param;
  param.m_vertices = terrain.vertices.data();
  param.m_numVertices = PfxUInt32(terrain.numVertices());
  param.m_triangles = terrain.triangles.data();
  param.m_numTriangles = PfxUInt32(terrain.numTriangles());
  param.m_flags = flags;
  const double start = processCpuSeconds();
  const PfxInt32 result = pfxCreateLargeTriMesh(owner.mesh, param);
  seconds = processCpuSeconds() - start;
  if (result != PFX_OK) {
    error = "pfxCreateLargeTriMesh returned " + std::to_string(result);
    return false;
  }
  if (owner.mesh.m_numTriangles != terrain.numTriangles()) {
    error = "the mesh dropped " + std::to_string(owner.mesh.m_numDroppedTriangles) + " triangles";
    return false;
  }
  return true;
}

struct MeshRays {
  std::vector<PfxVector3> starts;
  std::vector<PfxVector3> directions;
};

MeshRays toPfx(const RaySet& rays) {
  MeshRays out;
  out.starts.reserve(rays.size());
  out.directions.reserve(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    out.starts.emplace_back(rays.starts[3 * i], rays.starts[3 * i + 1], rays.starts[3 * i + 2]);
    out.directions.emplace_back(rays.directions[3 * i], rays.directions[3 * i + 1],
                                rays.directions[3 * i + 2]);
  }
  return out;
}

double castMesh(const PfxLargeTriMesh& mesh, const MeshRays& meshRays, const RaySet& rays,
                RayDistances& distances) {
  distances.resize(rays.size());
  return timeFastestPass(distances, [&](RayDistances& out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      PfxFloat fraction;
      PfxVector3 normal;
      PfxUInt32 triangle;
      out[i] = pfxRayCastLargeTriMesh(mesh, meshRays.starts[i], meshRays.directions[i], fraction,
                                      normal, triangle)
                   ? fraction * rays.lengths[i]
                   : kRayMiss;
    }
  });
}

double distanceOf(const PfxRayOutput& hit, double length) {
  return hit.m_contactFlag ? hit.m_variable * length : kRayMiss;
}

// Casts through a world holding the mesh as its one fixed body; appends the one-at-a-time
// and the batch figures.
bool castWorld(const PfxLargeTriMesh& mesh, const MeshRays& meshRays, const RaySet& rays,
               const std::string& variant, RayEngineFigures& figures, std::string& error) {
  PfxWorld world;
  PfxWorldParam param;
  if (world.initialize(param) != PFX_OK) {
    error = "PfxWorld::initialize failed";
    return false;
  }
  PfxShape ground;
  ground.reset();
  ground.setLargeTriMesh(&mesh);
  PfxBodyInit init;
  init.mass = 0;
  if (const PfxInt32 result = pfxAddBody(world, ground, init); result != PFX_OK) {
    error = "pfxAddBody returned " + std::to_string(result);
    return false;
  }
  std::vector<PfxRayInput> inputs(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    inputs[i].reset();
    inputs[i].m_startPosition = meshRays.starts[i];
    inputs[i].m_direction = meshRays.directions[i];
  }
  // The first cast builds the world's ray hierarchy; the passes below only cast.
  PfxRayOutput first;
  if (const PfxInt32 result = world.castRay(inputs[0], first); result != PFX_OK) {
    error = "PfxWorld::castRay returned " + std::to_string(result);
    return false;
  }

  RayCastFigures single{"pfx_world", variant, 0, RayDistances(rays.size())};
  single.secondsPerBatch = timeFastestPass(single.distances, [&](RayDistances& out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      PfxRayOutput hit;
      world.castRay(inputs[i], hit);
      out[i] = distanceOf(hit, rays.lengths[i]);
    }
  });

  std::vector<PfxRayOutput> outputs(rays.size());
  PfxInt32 batchResult = PFX_OK;
  RayCastFigures batch{"pfx_batch", variant, 0, RayDistances(rays.size())};
  batch.secondsPerBatch = timeFastestPass(batch.distances, [&](RayDistances& out) {
    batchResult = world.castRays(inputs.data(), outputs.data(), PfxUInt32(inputs.size()));
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = distanceOf(outputs[i], rays.lengths[i]);
  });
  if (batchResult != PFX_OK) {
    error = "PfxWorld::castRays returned " + std::to_string(batchResult);
    return false;
  }
  figures.casts.push_back(std::move(single));
  figures.casts.push_back(std::move(batch));
  return true;
}

}  // namespace

bool castPfxReferenceRays(const RayTerrain& terrain, const RaySet& rays, RayDistances& distances,
                          std::string& error) {
  MeshOwner owner;
  double seconds = 0;
  if (!buildMesh(terrain, 0, owner, seconds, error)) return false;
  castMesh(owner.mesh, toPfx(rays), rays, distances);
  return true;
}

bool runPfxRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                std::string& error) {
  const MeshRays meshRays = toPfx(rays);
  for (const StorageVariant& variant : kStorageVariants) {
    MeshOwner owner;
    RayBuildFigures build{"pfx", variant.name, 0, 0};
    if (!buildMesh(terrain, variant.flags, owner, build.buildSeconds, error)) {
      error = std::string(variant.name) + ": " + error;
      return false;
    }
    build.bytesPerTriangle = double(owner.mesh.m_bytes) / double(owner.mesh.m_numTriangles);
    figures.builds.push_back(build);

    RayCastFigures direct{"pfx", variant.name, 0, {}};
    direct.secondsPerBatch = castMesh(owner.mesh, meshRays, rays, direct.distances);
    figures.casts.push_back(std::move(direct));
    if (!castWorld(owner.mesh, meshRays, rays, variant.name, figures, error)) {
      error = std::string(variant.name) + ": " + error;
      return false;
    }
  }
  return true;
}

}  // namespace pfxbench
