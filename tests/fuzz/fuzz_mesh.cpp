// Mesh files (pfxLoadMeshFile through assimp: binary and ASCII STL, OBJ, Collada), then
// the two shapes a mesh becomes: the convex hull of a moving link and the large mesh of a
// static one. The file is named after the format its first bytes suggest, as a mesh on
// disk would be, so that assimp's importer for that format reads it.
//
// Collada is read only with PFX_FUZZ_COLLADA set in the environment: Debian's assimp 5.2
// allocates 800 MB and runs past 10 s on a Collada file with one index digit changed
// (assimp's own parser, before pfx sees a scene), which would fail every short run on a
// defect pfx cannot fix. Long campaigns by hand set it; other inputs starting with '<' are
// then read as STL, which refuses them.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "pfx/loaders/pfx_mesh_loader.h"
#include "pfx_fuzz_util.h"

namespace {

bool startsWith(const std::uint8_t* data, std::size_t size, const char* prefix) {
  const std::size_t n = std::strlen(prefix);
  return size >= n && std::memcmp(data, prefix, n) == 0;
}

const char* fileNameFor(const std::uint8_t* data, std::size_t size) {
  if (startsWith(data, size, "solid")) return "mesh.stl";
  static const bool readCollada = std::getenv("PFX_FUZZ_COLLADA") != nullptr;
  if (readCollada && startsWith(data, size, "<")) return "mesh.dae";
  if (size > 0 && std::strchr("#vfogmus", data[0]) != nullptr) return "mesh.obj";
  return "mesh.stl";  // binary STL: an 80-byte header of any content
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pfx;
  const std::string path = pfx_fuzz::writeScratchFile(fileNameFor(data, size), data, size);
  PfxTriangleMesh mesh;
  std::string message;
  if (pfxLoadMeshFile(path, PfxVector3(1, 2, PfxFloat(0.5)), mesh, &message) != PFX_OK) {
    if (message.empty()) pfx_fuzz::fail("mesh refused without a message");
    if (!mesh.vertices.empty() || !mesh.triangles.empty()) pfx_fuzz::fail("refused mesh written");
    return 0;
  }
  if (mesh.vertices.size() % 3 != 0 || mesh.triangles.empty() || mesh.triangles.size() % 3 != 0) {
    pfx_fuzz::fail("mesh arrays of the wrong length");
  }
  const PfxUInt32 numVertices = static_cast<PfxUInt32>(mesh.vertices.size() / 3);
  for (PfxUInt32 index : mesh.triangles) {
    if (index >= numVertices) pfx_fuzz::fail("triangle corner out of range");
  }

  PfxConvexMesh hull{};
  if (pfxCreateConvexHull(mesh, hull, &message) == PFX_OK &&
      (hull.m_numVerts < 4 || hull.m_numVerts > PFX_CONVEX_MESH_MAX_VERTICES)) {
    pfx_fuzz::fail("convex hull with a bad corner count");
  }
  PfxLargeTriMesh largeMesh{};
  if (pfxCreateLargeTriMeshFromMesh(mesh, PFX_MESH_FLAG_USE_BVH, largeMesh, &message) == PFX_OK) {
    pfxReleaseLargeTriMesh(largeMesh);
  }
  return 0;
}
