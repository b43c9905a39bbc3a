// Mesh files through assimp, and the large mesh a static body gets from them.
#include "pfx/loaders/pfx_mesh_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <unordered_map>

namespace pfx {

namespace {

void setMessage(std::string* message, const std::string& text) {
  if (message) *message = text;
}

// Exact coordinates as a key: welding joins only corners that are the same point, so that
// no geometry moves and a mesh with deliberately close vertices keeps them apart. -0 and +0
// are one point.
struct VertexKey {
  PfxFloat xyz[3];
  bool operator==(const VertexKey& o) const {
    return xyz[0] == o.xyz[0] && xyz[1] == o.xyz[1] && xyz[2] == o.xyz[2];
  }
};

struct VertexKeyHash {
  std::size_t operator()(const VertexKey& k) const {
    std::size_t h = 0;
    for (PfxFloat c : k.xyz) {
      const PfxFloat v = c == 0 ? PfxFloat(0) : c;
      std::size_t bits = 0;
      std::memcpy(&bits, &v, sizeof(v));
      h = h * 1000003u ^ std::hash<std::size_t>()(bits);
    }
    return h;
  }
};

class MeshCollector {
 public:
  explicit MeshCollector(const PfxVector3& scale) : m_scale(scale) {}

  // Adds the node's meshes under its accumulated transform, then its children. Returns
  // false at the first vertex that is not finite once transformed and scaled.
  bool addNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent) {
    const aiMatrix4x4 transform = parent * node.mTransformation;
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
      if (!addMesh(*scene.mMeshes[node.mMeshes[m]], transform)) return false;
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) {
      if (!addNode(scene, *node.mChildren[c], transform)) return false;
    }
    return true;
  }

  PfxTriangleMesh m_mesh;

 private:
  bool addMesh(const aiMesh& mesh, const aiMatrix4x4& transform) {
    std::vector<PfxUInt32> ids(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      VertexKey key;
      for (int k = 0; k < 3; ++k) key.xyz[k] = static_cast<PfxFloat>(p[k] * m_scale[k]);
      if (!std::isfinite(key.xyz[0]) || !std::isfinite(key.xyz[1]) || !std::isfinite(key.xyz[2])) {
        return false;
      }
      const auto found = m_ids.emplace(key, static_cast<PfxUInt32>(m_mesh.vertices.size() / 3));
      if (found.second) m_mesh.vertices.insert(m_mesh.vertices.end(), key.xyz, key.xyz + 3);
      ids[v] = found.first->second;
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines have no surface
      const PfxUInt32 a = ids[face.mIndices[0]], b = ids[face.mIndices[1]],
                      c = ids[face.mIndices[2]];
      // A triangle that welding collapsed onto an edge has no area and no normal.
      if (a == b || b == c || c == a) continue;
      m_mesh.triangles.insert(m_mesh.triangles.end(), {a, b, c});
    }
    return true;
  }

  PfxVector3 m_scale;
  std::unordered_map<VertexKey, PfxUInt32, VertexKeyHash> m_ids;
};

}  // namespace

PfxInt32 pfxLoadMeshFile(const std::string& path, const PfxVector3& scale, PfxTriangleMesh& mesh,
                         std::string* message) {
  if (!pfxIsFinite(scale) || !(scale.minCoeff() > 0)) {
    std::ostringstream text;
    text << path << ": scale must be positive and finite, got (" << scale[0] << ", " << scale[1]
         << ", " << scale[2] << ")";
    setMessage(message, text.str());
    return PFX_ERR_INVALID_VALUE;
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    setMessage(message,
               path + ": " +
                   (std::filesystem::exists(path, error) ? "not a regular file" : "no such file"));
    return PFX_ERR_INVALID_VALUE;
  }

  Assimp::Importer importer;
  // Only positions matter for collision. Dropping normals and texture coordinates before
  // the vertices are joined lets assimp join the corners that an STL repeats per face.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_COLORS | aiComponent_TEXCOORDS |
                                  aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                  aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
  // assimp turns a Z-up Collada file into Y-up by rotating its root node; rviz and MoveIt
  // undo that rotation (and keep the unit's scale), so robots' meshes are drawn as their
  // authors wrote them. Collision geometry must lie where rviz draws it.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                                     aiProcess_JoinIdenticalVertices |
                                                     aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode) {
    const char* reason = importer.GetErrorString();
    setMessage(message, path + ": cannot read as a mesh (" +
                            std::string(reason && *reason ? reason : "unknown format") + ")");
    return PFX_ERR_INVALID_VALUE;
  }

  MeshCollector collector(scale);
  if (!collector.addNode(*scene, *scene->mRootNode, aiMatrix4x4())) {
    setMessage(message, path + ": a vertex is NaN or infinite");
    return PFX_ERR_INVALID_VALUE;
  }
  if (collector.m_mesh.triangles.empty()) {
    setMessage(message, path + ": the file holds no triangles");
    return PFX_ERR_DEGENERATE;
  }
  mesh = std::move(collector.m_mesh);
  return PFX_OK;
}

PfxInt32 pfxCreateLargeTriMeshFromMesh(const PfxTriangleMesh& mesh, PfxUInt32 flags,
                                       PfxLargeTriMesh& largeMesh, std::string* message,
                                       PfxFloat thickness) {
  if (mesh.vertices.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    setMessage(message, "large mesh: vertex or index count is not a multiple of 3");
    return PFX_ERR_OUT_OF_RANGE;
  }
  if (mesh.triangles.empty()) {
    setMessage(message, "large mesh: no triangles");
    return PFX_ERR_OUT_OF_RANGE;
  }
  PfxCreateLargeTriMeshParam param;
  param.m_vertices = mesh.vertices.data();
  param.m_numVertices = static_cast<PfxUInt32>(mesh.vertices.size() / 3);
  param.m_triangles = mesh.triangles.data();
  param.m_numTriangles = static_cast<PfxUInt32>(mesh.triangles.size() / 3);
  param.m_flags = flags;
  param.m_thickness = thickness;
  PfxLargeTriMesh created{};
  const PfxInt32 err = pfxCreateLargeTriMesh(created, param);
  if (err != PFX_OK) {
    setMessage(message, std::string("large mesh: ") + pfxErrorString(err));
    return err;
  }
  largeMesh = created;
  return PFX_OK;
}

}  // namespace pfx
