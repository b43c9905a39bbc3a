// OctoMap files into one fixed body holding a large mesh of the map's exposed voxel faces.
//
// Why a surface mesh and not a box per voxel: a body then meets one shape, the large mesh,
// whose island hierarchy finds the few triangles near it in logarithmic time, and a ray
// descends that same hierarchy; 100,000 boxes would be 100,000 broad-phase proxies, each a
// candidate pair and a node of the rays' hierarchy, and a box per voxel also offers the
// solver the internal faces between neighbouring voxels, on which a sliding body catches.
// Only faces between an occupied and a not-occupied cell (free, unknown, or outside the
// map) are kept, and the faces of one plane are merged into rectangles (greedy meshing), so
// a floor of 40,000 voxels becomes a handful of triangles, not 480,000. Rectangles are
// split where a neighbour's corner meets their edge, so every edge is shared by exactly
// the triangles on both sides: the mesh knows which edges are flat or concave (no catching)
// and a ray cannot slip through a crack between two rectangles.
//
// The files are checked before liboctomap reads them: its readers trust the node counts and
// child bits and, on a cut-off or corrupted file, read past the end and build trees of
// arbitrary depth. The checks follow the same format that liboctomap writes.
#include "pfx/loaders/pfx_octomap_loader.h"

#include <octomap/OcTree.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "loaders/pfx_voxel_surface.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfx {

namespace {

constexpr int kTreeDepth = 16;  // every OcTree has 16 levels of keys
constexpr PfxInt32 kKeyOrigin = 1 << (kTreeDepth - 1);
const char kBinaryHeader[] = "# Octomap OcTree binary file";
const char kFullHeader[] = "# Octomap OcTree file";
const char kNoOccupiedVoxel[] = "the map has no occupied voxel";

struct Header {
  bool binary = false;
  std::string id;
  PfxUInt64 size = 0;
  double resolution = 0;
  std::size_t dataOffset = 0;
};

bool startsWith(const std::string& s, std::size_t pos, const char* prefix) {
  return s.compare(pos, std::char_traits<char>::length(prefix), prefix) == 0;
}

// The text header both formats share: the first line names the format, then "id", "size"
// and "res" lines in any order (comments start with '#'), and a "data" line after which the
// nodes follow.
bool parseHeader(const std::string& content, Header& header, std::string& reason) {
  if (startsWith(content, 0, kBinaryHeader)) {
    header.binary = true;
  } else if (!startsWith(content, 0, kFullHeader)) {
    reason = "not an OctoMap file (neither the .bt nor the .ot header)";
    return false;
  }
  bool haveId = false, haveSize = false, haveResolution = false;
  std::size_t pos = content.find('\n');
  while (pos != std::string::npos) {
    const std::size_t start = pos + 1;
    pos = content.find('\n', start);
    std::istringstream line(
        content.substr(start, pos == std::string::npos ? std::string::npos : pos - start));
    std::string token;
    if (!(line >> token) || token[0] == '#') continue;
    if (token == "data") {
      if (!haveId || !haveSize || !haveResolution) {
        reason = "header lacks its id, size or res line";
        return false;
      }
      if (pos == std::string::npos) {
        reason = "file ends after the header";
        return false;
      }
      header.dataOffset = pos + 1;
      return true;
    }
    if (token == "id") {
      haveId = static_cast<bool>(line >> header.id);
    } else if (token == "size") {
      long long size = -1;
      haveSize = (line >> size) && size >= 0;
      header.size = static_cast<PfxUInt64>(size);
    } else if (token == "res") {
      haveResolution = static_cast<bool>(line >> header.resolution);
    }
  }
  reason = "header has no 'data' line";
  return false;
}

// .bt: two bytes per node, two bits per child: 01 occupied leaf, 10 free leaf, 11 a node
// with children (whose bytes follow, depth first), 00 no child.
bool checkBinaryNode(const std::string& data, std::size_t& pos, int depth, PfxUInt64& count) {
  if (data.size() - pos < 2) return false;
  const unsigned bits = static_cast<unsigned char>(data[pos]) |
                        static_cast<unsigned>(static_cast<unsigned char>(data[pos + 1])) << 8;
  pos += 2;
  for (int child = 0; child < 8; ++child) {
    const unsigned code = (bits >> (2 * child)) & 3u;
    if (code == 0) continue;
    ++count;
    if (code == 3 && (depth + 1 >= kTreeDepth || !checkBinaryNode(data, pos, depth + 1, count))) {
      return false;
    }
  }
  return true;
}

// .ot of an OcTree: a node is its float log-odds and a byte of child bits, children follow.
bool checkFullNode(const std::string& data, std::size_t& pos, int depth, PfxUInt64& count) {
  if (data.size() - pos < sizeof(float) + 1) return false;
  const unsigned children = static_cast<unsigned char>(data[pos + sizeof(float)]);
  pos += sizeof(float) + 1;
  for (int child = 0; child < 8; ++child) {
    if (!(children & (1u << child))) continue;
    ++count;
    if (depth + 1 > kTreeDepth || !checkFullNode(data, pos, depth + 1, count)) return false;
  }
  return true;
}

// The nodes after the header: as many as the header says, none reaching below the finest
// depth, none cut off by the end of the file.
bool checkNodes(const std::string& content, const Header& header, std::string& reason) {
  std::size_t pos = header.dataOffset;
  PfxUInt64 count = 1;
  const bool complete = header.binary ? checkBinaryNode(content, pos, 0, count)
                                      : checkFullNode(content, pos, 0, count);
  if (!complete) {
    reason = "node data is cut off or deeper than 16 levels";
    return false;
  }
  if (count != header.size) {
    reason = "header says " + std::to_string(header.size) + " nodes, the data holds " +
             std::to_string(count);
    return false;
  }
  return true;
}

std::unique_ptr<octomap::OcTree> readTree(const std::string& path, PfxInt32& code,
                                          std::string& reason) {
  code = PFX_ERR_INVALID_VALUE;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    reason = std::filesystem::exists(path, error) ? "not a regular file" : "no such file";
    return nullptr;
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    reason = "cannot open the file";
    return nullptr;
  }
  std::ostringstream buffer;
  buffer << file.rdbuf();
  const std::string content = buffer.str();
  Header header;
  if (!parseHeader(content, header, reason)) return nullptr;
  if (!std::isfinite(header.resolution) || !(header.resolution > 0)) {
    reason = "resolution must be positive and finite";
    return nullptr;
  }
  // Binary files hold occupancy only, whatever tree wrote them, and read into an OcTree.
  // "1" is the OcTree's id in files of liboctomap before 1.4.
  if (!header.binary && header.id != "OcTree" && header.id != "1") {
    reason = "holds a " + header.id + ", not an OcTree";
    return nullptr;
  }
  // An empty tree has no node data at all, which liboctomap's .ot reader would read anyway.
  if (header.size == 0) {
    code = PFX_ERR_DEGENERATE;
    reason = kNoOccupiedVoxel;
    return nullptr;
  }
  if (!checkNodes(content, header, reason)) return nullptr;

  // liboctomap reads the nodes; the header is parsed above, which also keeps its readers'
  // progress messages (readBinary and AbstractOcTree::read print them) off the terminal.
  auto tree = std::make_unique<octomap::OcTree>(header.resolution);
  std::istringstream stream(content);
  stream.seekg(static_cast<std::streamoff>(header.dataOffset));
  if (header.binary) {
    tree->readBinaryData(stream);
  } else {
    tree->readData(stream);
  }
  if (!stream || tree->size() != header.size) {
    reason = "liboctomap could not read the nodes";
    return nullptr;
  }
  return tree;
}

class FaceCollector {
 public:
  explicit FaceCollector(const octomap::OcTree& tree) : m_tree(tree) {}

  // The six faces of an occupied cube of `size` cells whose lowest key is `low`, at `depth`.
  void addCube(const octomap::OcTreeKey& low, PfxUInt32 size, unsigned depth) {
    for (PfxUInt8 axis = 0; axis < 3; ++axis) {
      for (PfxUInt8 positive = 0; positive < 2; ++positive) {
        PfxVoxelFace face;
        face.axis = axis;
        face.positive = positive;
        face.plane = low[axis] + (positive ? size : 0);
        face.u = low[(axis + 1) % 3];
        face.v = low[(axis + 2) % 3];
        face.size = size;
        const PfxInt64 neighbor =
            PfxInt64(low[axis]) + (positive ? PfxInt64(size) : -PfxInt64(size));
        if (neighbor < 0 || neighbor + size > (PfxInt64(1) << kTreeDepth)) {
          m_faces.push_back(face);  // the key space ends here: nothing lies beyond
          continue;
        }
        octomap::OcTreeKey across = low;
        across[axis] = static_cast<octomap::key_type>(neighbor);
        addFace(face, across, depth);
      }
    }
  }

  std::vector<PfxVoxelFace> m_faces;

 private:
  // The part of `face` not covered by occupied cells of the cube `across` (same size, at
  // `depth`): all of it when that cube is free or unknown, none when it is an occupied
  // leaf, and face by face of its four children that touch the face when it is divided.
  void addFace(const PfxVoxelFace& face, const octomap::OcTreeKey& across, unsigned depth) {
    const octomap::OcTreeNode* node = m_tree.search(across, depth);
    if (node && m_tree.nodeHasChildren(node)) {
      const PfxUInt32 half = face.size / 2;
      const int ua = (face.axis + 1) % 3, va = (face.axis + 2) % 3;
      for (PfxUInt32 du = 0; du < 2; ++du) {
        for (PfxUInt32 dv = 0; dv < 2; ++dv) {
          PfxVoxelFace part = face;
          part.size = half;
          part.u = face.u + du * half;
          part.v = face.v + dv * half;
          octomap::OcTreeKey child = across;
          child[ua] = static_cast<octomap::key_type>(part.u);
          child[va] = static_cast<octomap::key_type>(part.v);
          // The children that touch the face: the near layer of the neighbouring cube.
          if (!face.positive)
            child[face.axis] = static_cast<octomap::key_type>(across[face.axis] + half);
          addFace(part, child, depth + 1);
        }
      }
      return;
    }
    if (!node || !m_tree.isNodeOccupied(node)) m_faces.push_back(face);
  }

  const octomap::OcTree& m_tree;
};

bool validParam(const PfxOctomapLoadParam& param, std::string& reason) {
  if (!pfxIsFinite(param.position) || !pfxIsUnitQuat(param.orientation)) {
    reason = "pose must be finite with a unit orientation";
    return false;
  }
  if (!std::isfinite(param.friction) || param.friction < 0 || !std::isfinite(param.restitution) ||
      param.restitution < 0) {
    reason = "friction and restitution must be finite and not negative";
    return false;
  }
  if (!(param.thicknessPerVoxel > 0 && param.thicknessPerVoxel < 1)) {
    reason = "thicknessPerVoxel must lie between 0 and 1";
    return false;
  }
  return true;
}

}  // namespace

PfxOctomap::~PfxOctomap() {
  if (meshCreated) pfxReleaseLargeTriMesh(mesh);
}

PfxInt32 pfxLoadOctomapFile(PfxWorld& world, const std::string& path,
                            const PfxOctomapLoadParam& param, PfxOctomap& map,
                            std::string* message) {
  const auto fail = [&](PfxInt32 code, const std::string& reason) {
    if (message) *message = path + ": " + reason;
    return code;
  };
  std::string reason;
  if (!validParam(param, reason)) return fail(PFX_ERR_INVALID_VALUE, reason);
  if (map.meshCreated)
    return fail(PFX_ERR_INVALID_VALUE, "the map object holds a loaded map already");
  PfxInt32 code = PFX_OK;
  const std::unique_ptr<octomap::OcTree> tree = readTree(path, code, reason);
  if (!tree) return fail(code, reason);

  FaceCollector collector(*tree);
  PfxUInt64 numVoxels = 0;
  for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
    if (!tree->isNodeOccupied(*it)) continue;
    const unsigned depth = it.getDepth();
    const PfxUInt32 size = 1u << (kTreeDepth - depth);
    numVoxels += PfxUInt64(size) * size * size;
    collector.addCube(it.getIndexKey(), size, depth);
  }
  if (numVoxels == 0) return fail(PFX_ERR_DEGENERATE, kNoOccupiedVoxel);

  PfxTriangleMesh surface;
  pfxMeshVoxelFaces(collector.m_faces, kKeyOrigin, tree->getResolution(), surface);
  PfxLargeTriMesh mesh{};
  std::string meshMessage;
  const PfxFloat thickness = static_cast<PfxFloat>(tree->getResolution()) * param.thicknessPerVoxel;
  if (const PfxInt32 err =
          pfxCreateLargeTriMeshFromMesh(surface, param.meshFlags, mesh, &meshMessage, thickness);
      err != PFX_OK) {
    return fail(err, meshMessage);
  }

  // The shape points at map.mesh, so the mesh moves there before the body is added, and
  // back out if the world refuses it.
  const PfxLargeTriMesh previous = map.mesh;
  map.mesh = mesh;
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&map.mesh);
  PfxBodyInit init;
  init.mass = 0;
  init.position = param.position;
  init.orientation = param.orientation.normalized();
  init.friction = param.friction;
  init.restitution = param.restitution;
  PfxUInt32 bodyId = 0;
  if (const PfxInt32 err = pfxAddBody(world, &shape, 1, init, &bodyId); err != PFX_OK) {
    map.mesh = previous;
    pfxReleaseLargeTriMesh(mesh);
    return fail(err, std::string("the world refused the map's body: ") + pfxErrorString(err));
  }
  map.bodyId = bodyId;
  map.numOccupiedVoxels = numVoxels;
  map.resolution = static_cast<PfxFloat>(tree->getResolution());
  map.meshCreated = true;
  return PFX_OK;
}

}  // namespace pfx
