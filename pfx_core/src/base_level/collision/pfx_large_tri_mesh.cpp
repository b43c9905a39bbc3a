#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "base_level/collision/pfx_large_tri_mesh_access.h"
#include "pfx/base_level/base/pfx_utility_allocator.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kAllFlags =
    PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY;
// Below this depth the surface area heuristic may split as unevenly as it likes; deeper
// nodes split at the median so that the tree stays within PFX_LARGE_MESH_MAX_DEPTH.
constexpr PfxUInt32 kMaxSahDepth = 48;
constexpr int kSahBins = 16;
// A triangle whose height over its longest edge is below this is a zero-area sliver: its
// normal would be rounding noise.
constexpr double kDegenerateHeightRatio = 1e-6;

struct Box {
  PfxVector3 lo = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
  PfxVector3 hi = PfxVector3::Constant(-std::numeric_limits<PfxFloat>::max());
  void grow(const PfxVector3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void grow(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  PfxFloat halfArea() const {
    const PfxVector3 d = (hi - lo).cwiseMax(PfxVector3::Zero());
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
  }
};

struct BuildNode {
  Box box;
  PfxUInt32 link;
};

// Builds the hierarchy over the kept triangles: splits until a node holds at most the
// island size (that node starts an island), then, with a BVH, on down to small leaves.
class Builder {
 public:
  Builder(const std::vector<Box>& boxes, const std::vector<PfxVector3>& centroids,
          PfxUInt32 islandSize, bool useBvh, bool highQuality)
      : m_boxes(boxes), m_centroids(centroids), m_islandSize(islandSize),
        m_leafSize(useBvh ? std::min(islandSize, PFX_LARGE_MESH_MAX_TRIANGLES_PER_LEAF)
                          : islandSize),
        m_highQuality(highQuality) {
    m_order.resize(boxes.size());
    for (PfxUInt32 i = 0; i < m_order.size(); ++i) m_order[i] = i;
    m_nodes.reserve(2 * boxes.size() / std::max<PfxUInt32>(1, m_leafSize / 2) + 1);
  }

  // False when there would be more islands than the node encoding holds.
  bool build() {
    m_nodes.push_back(BuildNode());
    buildNode(0, static_cast<PfxUInt32>(m_order.size()), 0, kNoIsland, 0);
    return m_islands.size() <= PFX_LARGE_MESH_MAX_ISLANDS;
  }

  // Merges the binary tree into nodes of up to four children. Which descendants (at most
  // four, together covering the node) become a node's children is chosen bottom up for the
  // fewest nodes in all, and among as few the smallest sum of node surface areas (the
  // chance a ray enters each): a greedy merge from the top leaves a tree of odd depth with a
  // bottom level of half-empty nodes. Nodes come before their children, as refitting
  // expects, and children keep the binary tree's left-to-right order, so queries visit
  // triangles in the same order.
  void makeWide() {
    m_wideLinks.clear();
    if (pfxLargeMeshIsLeaf(m_nodes[0].link)) {
      m_wideLinks.push_back({m_nodes[0].link, PFX_LARGE_MESH_EMPTY_LINK, PFX_LARGE_MESH_EMPTY_LINK,
                             PFX_LARGE_MESH_EMPTY_LINK});
      return;
    }
    chooseWideChildren();
    makeWideNode(0);
  }

  std::vector<PfxUInt32> m_order;  // kept-triangle index per stored triangle
  std::vector<BuildNode> m_nodes;
  std::vector<PfxLargeMeshIsland> m_islands;
  std::vector<std::array<PfxUInt32, PFX_LARGE_MESH_NODE_WIDTH>> m_wideLinks;  // per wide node

 private:
  static constexpr PfxUInt32 kNoIsland = 0xFFFFFFFFu;

  // Fills node `index` (already allocated) and allocates its children as a pair.
  void buildNode(PfxUInt32 begin, PfxUInt32 end, PfxUInt32 depth, PfxUInt32 island,
                 PfxUInt32 index) {
    Box box;
    for (PfxUInt32 i = begin; i < end; ++i) box.grow(m_boxes[m_order[i]]);
    m_nodes[index].box = box;
    const PfxUInt32 count = end - begin;
    if (island == kNoIsland && count <= m_islandSize) {
      island = static_cast<PfxUInt32>(m_islands.size());
      m_islands.push_back({begin, 0, 0, count});
    }
    if (island != kNoIsland && count <= m_leafSize) {
      m_nodes[index].link =
          pfxLargeMeshMakeLeaf(island, begin - m_islands[island].m_firstTriangle, count);
      return;
    }
    const PfxUInt32 mid = split(begin, end, depth);
    const PfxUInt32 children = static_cast<PfxUInt32>(m_nodes.size());
    m_nodes.resize(children + 2);
    m_nodes[index].link = children;
    buildNode(begin, mid, depth + 1, island, children);
    buildNode(mid, end, depth + 1, island, children + 1);
  }

  PfxUInt32 split(PfxUInt32 begin, PfxUInt32 end, PfxUInt32 depth) {
    Box centres;
    for (PfxUInt32 i = begin; i < end; ++i) centres.grow(m_centroids[m_order[i]]);
    const PfxVector3 extent = centres.hi - centres.lo;
    if (m_highQuality && depth < kMaxSahDepth) {
      const PfxUInt32 mid = sahSplit(begin, end, centres);
      if (mid > begin && mid < end) return mid;
    }
    int axis = 0;
    if (extent[1] > extent[axis]) axis = 1;
    if (extent[2] > extent[axis]) axis = 2;
    const PfxUInt32 mid = begin + (end - begin) / 2;
    std::nth_element(m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end,
                     [&](PfxUInt32 a, PfxUInt32 b) {
                       return m_centroids[a][axis] < m_centroids[b][axis];
                     });
    return mid;
  }

  // Binned surface area heuristic (Wald 2007): the plane among kSahBins per axis that
  // minimises area(left) * count(left) + area(right) * count(right). Returns begin when
  // no plane separates the centroids.
  PfxUInt32 sahSplit(PfxUInt32 begin, PfxUInt32 end, const Box& centres) {
    PfxFloat bestCost = std::numeric_limits<PfxFloat>::max();
    int bestAxis = -1;
    int bestBin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const PfxFloat extent = centres.hi[axis] - centres.lo[axis];
      if (!(extent > 0)) continue;
      const PfxFloat scale = PfxFloat(kSahBins) / extent;
      Box bins[kSahBins];
      PfxUInt32 counts[kSahBins] = {};
      for (PfxUInt32 i = begin; i < end; ++i) {
        const PfxUInt32 t = m_order[i];
        const int b = binOf(m_centroids[t][axis], centres.lo[axis], scale);
        bins[b].grow(m_boxes[t]);
        ++counts[b];
      }
      PfxFloat rightArea[kSahBins];
      PfxUInt32 rightCount[kSahBins];
      Box acc;
      PfxUInt32 n = 0;
      for (int b = kSahBins - 1; b > 0; --b) {
        acc.grow(bins[b]);
        n += counts[b];
        rightArea[b] = acc.halfArea();
        rightCount[b] = n;
      }
      acc = Box();
      n = 0;
      for (int b = 1; b < kSahBins; ++b) {
        acc.grow(bins[b - 1]);
        n += counts[b - 1];
        if (n == 0 || rightCount[b] == 0) continue;
        const PfxFloat cost = acc.halfArea() * PfxFloat(n) + rightArea[b] * PfxFloat(rightCount[b]);
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBin = b;
        }
      }
    }
    if (bestAxis < 0) return begin;
    const PfxFloat scale = PfxFloat(kSahBins) / (centres.hi[bestAxis] - centres.lo[bestAxis]);
    const auto it = std::partition(m_order.begin() + begin, m_order.begin() + end,
                                   [&](PfxUInt32 t) {
                                     return binOf(m_centroids[t][bestAxis], centres.lo[bestAxis],
                                                  scale) < bestBin;
                                   });
    return static_cast<PfxUInt32>(it - m_order.begin());
  }

  struct WideChoice {
    PfxUInt32 numNodes = 0;  // wide nodes in the subtree, this one included
    PfxFloat area = 0;       // their surface areas added up
    PfxUInt32 slots[PFX_LARGE_MESH_NODE_WIDTH] = {};
    PfxUInt32 count = 0;
  };

  bool isInner(PfxUInt32 binary) const { return !pfxLargeMeshIsLeaf(m_nodes[binary].link); }

  // Children are allocated after their parent, so reverse order sees every subtree's
  // choice before the node above it.
  void chooseWideChildren() {
    m_wideChoices.assign(m_nodes.size(), WideChoice());
    for (PfxUInt32 b = static_cast<PfxUInt32>(m_nodes.size()); b-- > 0;) {
      if (!isInner(b)) continue;
      WideChoice& best = m_wideChoices[b];
      best.numNodes = 0xFFFFFFFFu;
      const PfxUInt32 first = m_nodes[b].link;
      const PfxUInt32 start[2] = {first, first + 1};
      tryCovers(b, start, 2, best);
    }
  }

  // Scores the cover `slots` of node b and every cover it opens into, keeping the best.
  void tryCovers(PfxUInt32 b, const PfxUInt32* slots, PfxUInt32 count, WideChoice& best) {
    WideChoice choice;
    choice.numNodes = 1;
    choice.area = m_nodes[b].box.halfArea();
    for (PfxUInt32 i = 0; i < count; ++i) {
      if (!isInner(slots[i])) continue;
      choice.numNodes += m_wideChoices[slots[i]].numNodes;
      choice.area += m_wideChoices[slots[i]].area;
    }
    if (choice.numNodes < best.numNodes ||
        (choice.numNodes == best.numNodes && choice.area < best.area)) {
      best = choice;
      std::copy(slots, slots + count, best.slots);
      best.count = count;
    }
    if (count == PFX_LARGE_MESH_NODE_WIDTH) return;
    for (PfxUInt32 open = 0; open < count; ++open) {
      if (!isInner(slots[open])) continue;
      PfxUInt32 opened[PFX_LARGE_MESH_NODE_WIDTH];
      std::copy(slots, slots + open, opened);
      opened[open] = m_nodes[slots[open]].link;
      opened[open + 1] = opened[open] + 1;
      std::copy(slots + open + 1, slots + count, opened + open + 2);
      tryCovers(b, opened, count + 1, best);
    }
  }

  // Wide node for binary inner node `binary`, from its chosen cover; returns its index.
  PfxUInt32 makeWideNode(PfxUInt32 binary) {
    const PfxUInt32 wide = static_cast<PfxUInt32>(m_wideLinks.size());
    m_wideLinks.emplace_back();
    const WideChoice& choice = m_wideChoices[binary];
    for (PfxUInt32 i = 0; i < PFX_LARGE_MESH_NODE_WIDTH; ++i) {
      PfxUInt32 link = PFX_LARGE_MESH_EMPTY_LINK;
      if (i < choice.count) {
        const PfxUInt32 slot = choice.slots[i];
        link = isInner(slot) ? makeWideNode(slot) : m_nodes[slot].link;
      }
      m_wideLinks[wide][i] = link;
    }
    return wide;
  }

  static int binOf(PfxFloat c, PfxFloat lo, PfxFloat scale) {
    const int b = static_cast<int>((c - lo) * scale);
    return std::min(std::max(b, 0), kSahBins - 1);
  }

  const std::vector<Box>& m_boxes;
  const std::vector<PfxVector3>& m_centroids;
  std::vector<WideChoice> m_wideChoices;  // per binary node
  PfxUInt32 m_islandSize;
  PfxUInt32 m_leafSize;
  bool m_highQuality;
};

PfxVector3 readVertex(const PfxFloat* vertices, PfxUInt32 v) {
  return PfxVector3(vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]);
}

bool isDegenerate(const PfxFloat* vertices, const PfxUInt32* ids) {
  Eigen::Vector3d p[3];
  for (int k = 0; k < 3; ++k) p[k] = readVertex(vertices, ids[k]).cast<double>();
  const Eigen::Vector3d e0 = p[1] - p[0];
  const Eigen::Vector3d e1 = p[2] - p[1];
  const Eigen::Vector3d e2 = p[0] - p[2];
  const double longestSq = std::max({e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()});
  const double areaTwice = e0.cross(-e2).norm();
  // height = areaTwice / longest, compared as squares without a division.
  return areaTwice * areaTwice <= kDegenerateHeightRatio * kDegenerateHeightRatio *
                                      longestSq * longestSq;
}

// Edge flags from the shared edges of the kept triangles (ids: three per stored triangle).
void computeEdgeFlags(const std::vector<PfxUInt32>& ids, const PfxFloat* vertices,
                      PfxFloat flatEdgeAngle, PfxUInt8* flags) {
  struct EdgeRecord {
    PfxUInt64 key;
    PfxUInt32 triangle;
    PfxUInt32 edge;
  };
  const PfxUInt32 numTriangles = static_cast<PfxUInt32>(ids.size() / 3);
  std::vector<EdgeRecord> edges(ids.size());
  for (PfxUInt32 t = 0; t < numTriangles; ++t) {
    for (PfxUInt32 e = 0; e < 3; ++e) {
      const PfxUInt64 a = ids[3 * t + e];
      const PfxUInt64 b = ids[3 * t + (e + 1) % 3];
      edges[3 * t + e] = {std::min(a, b) << 32 | std::max(a, b), t, e};
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeRecord& x, const EdgeRecord& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  const auto normalOf = [&](PfxUInt32 t) {
    const Eigen::Vector3d p0 = readVertex(vertices, ids[3 * t]).cast<double>();
    const Eigen::Vector3d p1 = readVertex(vertices, ids[3 * t + 1]).cast<double>();
    const Eigen::Vector3d p2 = readVertex(vertices, ids[3 * t + 2]).cast<double>();
    return Eigen::Vector3d((p1 - p0).cross(p2 - p0).normalized());
  };
  const double flatCosine = std::cos(static_cast<double>(flatEdgeAngle));
  std::memset(flags, 0, numTriangles);
  std::size_t i = 0;
  while (i < edges.size()) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    // Only an edge of exactly two triangles wound the same way (the edge runs opposite
    // ways in them) is a fold between two faces; anything else is a boundary.
    if (j - i == 2) {
      const EdgeRecord& ra = edges[i];
      const EdgeRecord& rb = edges[i + 1];
      const PfxUInt32 a0 = ids[3 * ra.triangle + ra.edge];
      const PfxUInt32 b0 = ids[3 * rb.triangle + rb.edge];
      if (a0 != b0) {
        const Eigen::Vector3d na = normalOf(ra.triangle);
        const Eigen::Vector3d nb = normalOf(rb.triangle);
        const Eigen::Vector3d edgePoint = readVertex(vertices, a0).cast<double>();
        const Eigen::Vector3d farA =
            readVertex(vertices, ids[3 * ra.triangle + (ra.edge + 2) % 3]).cast<double>();
        const Eigen::Vector3d farB =
            readVertex(vertices, ids[3 * rb.triangle + (rb.edge + 2) % 3]).cast<double>();
        // Concave: each face's far corner lies above the other's plane (a valley).
        const bool flat = na.dot(nb) >= flatCosine;
        const bool concave = na.dot(farB - edgePoint) > 0 && nb.dot(farA - edgePoint) > 0;
        const PfxUInt8 bitA = static_cast<PfxUInt8>(1u << ra.edge);
        const PfxUInt8 bitB = static_cast<PfxUInt8>(1u << rb.edge);
        flags[ra.triangle] |= static_cast<PfxUInt8>(bitA << 3);
        flags[rb.triangle] |= static_cast<PfxUInt8>(bitB << 3);
        if (flat || concave) {
          flags[ra.triangle] |= bitA;
          flags[rb.triangle] |= bitB;
        }
      }
    }
    i = j;
  }
}

PfxUInt16 quantize(PfxFloat x, PfxFloat origin, PfxFloat step) {
  const PfxFloat q = std::round((x - origin) / step);
  return static_cast<PfxUInt16>(std::min(std::max(q, PfxFloat(0)), PfxFloat(65535)));
}

// Bounds of every slot from the current vertices, children before parents (a node is
// always allocated before its children, so reverse order will do), and the mesh bounds
// from the root. Works in the nodes' own units: floats, or quantization steps, where the
// box of quantized vertices is exact.
template <class Node, class Coordinate, class ReadCoordinate>
void refitNodesOf(PfxLargeTriMesh& mesh, Node* nodes, Coordinate emptyMin, Coordinate emptyMax,
                  ReadCoordinate&& coordinate) {
  for (PfxUInt32 i = mesh.m_numNodes; i-- > 0;) {
    Node& node = nodes[i];
    for (PfxUInt32 c = 0; c < PFX_LARGE_MESH_NODE_WIDTH; ++c) {
      Coordinate lo[3] = {emptyMin, emptyMin, emptyMin};
      Coordinate hi[3] = {emptyMax, emptyMax, emptyMax};
      const PfxUInt32 link = node.m_links[c];
      if (link == PFX_LARGE_MESH_EMPTY_LINK) {
        // Left inverted, so that no box test passes it.
      } else if (pfxLargeMeshIsLeaf(link)) {
        const PfxLargeMeshIsland& island = mesh.m_islands[pfxLargeMeshLeafIsland(link)];
        const PfxUInt32 first = island.m_firstTriangle + pfxLargeMeshLeafOffset(link);
        for (PfxUInt32 t = first; t < first + pfxLargeMeshLeafCount(link); ++t) {
          PfxUInt32 corners[3];
          pfxLargeMeshCorners(mesh, island, t, corners);
          for (PfxUInt32 v : corners) {
            for (int k = 0; k < 3; ++k) {
              lo[k] = std::min(lo[k], coordinate(v, k));
              hi[k] = std::max(hi[k], coordinate(v, k));
            }
          }
        }
      } else {
        const Node& child = nodes[link];
        for (PfxUInt32 g = 0; g < PFX_LARGE_MESH_NODE_WIDTH; ++g) {
          if (child.m_links[g] == PFX_LARGE_MESH_EMPTY_LINK) continue;
          for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], child.m_min[k][g]);
            hi[k] = std::max(hi[k], child.m_max[k][g]);
          }
        }
      }
      for (int k = 0; k < 3; ++k) {
        node.m_min[k][c] = lo[k];
        node.m_max[k][c] = hi[k];
      }
    }
  }
}

// The union of the root's slots, in the mesh's frame.
template <class Node, class ToFrame>
void rootBounds(PfxLargeTriMesh& mesh, const Node& root, ToFrame&& toFrame) {
  for (int k = 0; k < 3; ++k) {
    PfxFloat lo = std::numeric_limits<PfxFloat>::max();
    PfxFloat hi = -std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 c = 0; c < PFX_LARGE_MESH_NODE_WIDTH; ++c) {
      if (root.m_links[c] == PFX_LARGE_MESH_EMPTY_LINK) continue;
      lo = std::min(lo, toFrame(k, root.m_min[k][c]));
      hi = std::max(hi, toFrame(k, root.m_max[k][c]));
    }
    mesh.m_aabbMin[k] = lo;
    mesh.m_aabbMax[k] = hi;
  }
}

}  // namespace

void pfxRefitLargeTriMesh(PfxLargeTriMesh& mesh) {
  if (pfxLargeMeshIsQuantized(mesh)) {
    const PfxUInt16* q = mesh.m_quantizedVertices;
    refitNodesOf(mesh, mesh.m_quantizedNodes, PfxUInt16(65535), PfxUInt16(0),
                 [q](PfxUInt32 v, int k) { return q[3 * v + k]; });
    rootBounds(mesh, mesh.m_quantizedNodes[0], [&mesh](int k, PfxUInt16 x) {
      return mesh.m_quantOrigin[k] + PfxFloat(x) * mesh.m_quantStep[k];
    });
  } else {
    const PfxFloat* p = mesh.m_vertices;
    refitNodesOf(mesh, mesh.m_nodes, std::numeric_limits<PfxFloat>::max(),
                 -std::numeric_limits<PfxFloat>::max(),
                 [p](PfxUInt32 v, int k) { return p[3 * v + k]; });
    rootBounds(mesh, mesh.m_nodes[0], [](int, PfxFloat x) { return x; });
  }
}

namespace {

// Where the block is aligned, and so the node array at its start: a quantized node is then
// exactly one cache line.
constexpr std::size_t kBlockAlignment = 64;

// Carves the arrays out of one block, or only adds up its size when block is null.
std::size_t layOut(PfxLargeTriMesh& mesh, const PfxLargeMeshStorage& storage, char* block) {
  std::size_t bytes = 0;
  const auto take = [&](auto*& pointer, std::size_t count) {
    using T = std::remove_reference_t<decltype(*pointer)>;
    pointer = block ? reinterpret_cast<T*>(block + bytes) : nullptr;
    bytes += pfxAlignBytes(count * sizeof(T));
  };
  mesh.m_vertices = nullptr;
  mesh.m_quantizedVertices = nullptr;
  mesh.m_triangleVertices = nullptr;
  mesh.m_triangleOffsets = nullptr;
  mesh.m_triangleSourceIds = nullptr;
  mesh.m_triangleSourceOffsets = nullptr;
  mesh.m_nodes = nullptr;
  mesh.m_quantizedNodes = nullptr;
  if (storage.quantized) {
    take(mesh.m_quantizedNodes, mesh.m_numNodes);
    take(mesh.m_quantizedVertices, 3 * std::size_t(mesh.m_numVertices));
  } else {
    take(mesh.m_nodes, mesh.m_numNodes);
    take(mesh.m_vertices, 3 * std::size_t(mesh.m_numVertices));
  }
  if (storage.cornerOffsets) {
    take(mesh.m_triangleOffsets, 3 * std::size_t(mesh.m_numTriangles));
  } else {
    take(mesh.m_triangleVertices, 3 * std::size_t(mesh.m_numTriangles));
  }
  if (storage.sourceOffsets) {
    take(mesh.m_triangleSourceOffsets, mesh.m_numTriangles);
  } else {
    take(mesh.m_triangleSourceIds, mesh.m_numTriangles);
  }
  take(mesh.m_edgeFlags, mesh.m_numTriangles);
  take(mesh.m_islands, mesh.m_numIslands);
  return (bytes + kBlockAlignment - 1) & ~(kBlockAlignment - 1);
}

}  // namespace

PfxInt32 pfxAllocateLargeTriMeshArrays(PfxLargeTriMesh& mesh, const PfxLargeMeshStorage& storage) {
  PfxLargeTriMesh sized = mesh;
  const std::size_t bytes = layOut(sized, storage, nullptr);
  char* block = static_cast<char*>(pfxUtilityAllocate(bytes, kBlockAlignment));
  if (!block) return PFX_ERR_OUT_OF_BUFFER;
  std::memset(block, 0, bytes);
  layOut(mesh, storage, block);
  mesh.m_block = block;
  mesh.m_bytes = bytes;
  return PFX_OK;
}

namespace {

PfxInt32 validateParam(const PfxCreateLargeTriMeshParam& param) {
  if (!param.m_vertices || !param.m_triangles) return PFX_ERR_NULL_POINTER;
  if (param.m_numVertices == 0 || param.m_numTriangles == 0) return PFX_ERR_OUT_OF_RANGE;
  if (param.m_islandSize == 0 || param.m_islandSize > PFX_LARGE_MESH_MAX_TRIANGLES_PER_ISLAND) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  if ((param.m_flags & ~kAllFlags) != 0) return PFX_ERR_INVALID_FLAG;
  if (!pfxIsFinite(param.m_thickness) || param.m_thickness < 0 ||
      !pfxIsFinite(param.m_flatEdgeAngle) || param.m_flatEdgeAngle < 0 ||
      !pfxIsFinite(param.m_deformationMargin) || param.m_deformationMargin < 0) {
    return PFX_ERR_INVALID_VALUE;
  }
  // Three indices per triangle must fit in a 32-bit count of corners.
  if (param.m_numTriangles > 0xFFFFFFFFu / 3 || param.m_numVertices > 0xFFFFFFFFu / 3) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  for (PfxUInt64 i = 0; i < 3ull * param.m_numVertices; ++i) {
    if (!pfxIsFinite(param.m_vertices[i])) return PFX_ERR_INVALID_VALUE;
  }
  for (PfxUInt64 i = 0; i < 3ull * param.m_numTriangles; ++i) {
    if (param.m_triangles[i] >= param.m_numVertices) return PFX_ERR_OUT_OF_RANGE;
  }
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxCreateLargeTriMesh(PfxLargeTriMesh& mesh, const PfxCreateLargeTriMeshParam& param) {
  if (const PfxInt32 err = validateParam(param); err != PFX_OK) return err;
  const bool quantized = (param.m_flags & PFX_MESH_FLAG_USE_QUANTIZED) != 0;

  std::vector<PfxUInt32> kept;
  kept.reserve(param.m_numTriangles);
  for (PfxUInt32 t = 0; t < param.m_numTriangles; ++t) {
    if (!isDegenerate(param.m_vertices, param.m_triangles + 3 * t)) kept.push_back(t);
  }
  if (kept.empty()) return PFX_ERR_DEGENERATE;

  std::vector<Box> boxes(kept.size());
  std::vector<PfxVector3> centroids(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const PfxUInt32* ids = param.m_triangles + 3 * kept[i];
    PfxVector3 sum = PfxVector3::Zero();
    for (int k = 0; k < 3; ++k) {
      const PfxVector3 p = readVertex(param.m_vertices, ids[k]);
      boxes[i].grow(p);
      sum += p;
    }
    centroids[i] = sum / PfxFloat(3);
  }
  Builder builder(boxes, centroids, param.m_islandSize,
                  (param.m_flags & PFX_MESH_FLAG_USE_BVH) != 0,
                  (param.m_flags & PFX_MESH_FLAG_HIGH_QUALITY) != 0);
  if (!builder.build()) return PFX_ERR_OUT_OF_RANGE;

  builder.makeWide();

  // Corners and caller's indices in island order, and whether every island's fit 16-bit
  // offsets from the island's lowest.
  const PfxUInt32 numTriangles = static_cast<PfxUInt32>(kept.size());
  std::vector<PfxUInt32> corners(3 * std::size_t(numTriangles));
  std::vector<PfxUInt32> sources(numTriangles);
  for (PfxUInt32 t = 0; t < numTriangles; ++t) {
    sources[t] = kept[builder.m_order[t]];
    const PfxUInt32* ids = param.m_triangles + 3 * std::size_t(sources[t]);
    std::copy(ids, ids + 3, corners.begin() + 3 * std::size_t(t));
  }
  PfxLargeMeshStorage storage{quantized, quantized, quantized};
  for (PfxLargeMeshIsland& island : builder.m_islands) {
    const auto first = corners.begin() + 3 * std::size_t(island.m_firstTriangle);
    const auto range = std::minmax_element(first, first + 3 * std::size_t(island.m_numTriangles));
    island.m_baseVertex = *range.first;
    if (*range.second - *range.first > 0xFFFFu) storage.cornerOffsets = false;
    const auto firstSource = sources.begin() + island.m_firstTriangle;
    const auto sourceRange = std::minmax_element(firstSource, firstSource + island.m_numTriangles);
    island.m_baseSource = *sourceRange.first;
    if (*sourceRange.second - *sourceRange.first > 0xFFFFu) storage.sourceOffsets = false;
  }

  PfxLargeTriMesh built;
  std::memset(static_cast<void*>(&built), 0, sizeof(built));
  built.m_flags = param.m_flags;
  built.m_numVertices = param.m_numVertices;
  built.m_numTriangles = numTriangles;
  built.m_numSourceTriangles = param.m_numTriangles;
  built.m_numDroppedTriangles = param.m_numTriangles - numTriangles;
  built.m_numIslands = static_cast<PfxUInt32>(builder.m_islands.size());
  built.m_numNodes = static_cast<PfxUInt32>(builder.m_wideLinks.size());
  built.m_thickness = param.m_thickness;

  if (const PfxInt32 err = pfxAllocateLargeTriMeshArrays(built, storage); err != PFX_OK) {
    return err;
  }

  std::copy(builder.m_islands.begin(), builder.m_islands.end(), built.m_islands);
  if (quantized) {
    // The step of an axis of zero extent is arbitrary (every vertex sits at 0); 1 keeps it
    // finite.
    Box all;
    for (PfxUInt32 v = 0; v < param.m_numVertices; ++v) all.grow(readVertex(param.m_vertices, v));
    all.lo -= PfxVector3::Constant(param.m_deformationMargin);
    all.hi += PfxVector3::Constant(param.m_deformationMargin);
    built.m_quantOrigin = all.lo;
    for (int k = 0; k < 3; ++k) {
      const PfxFloat extent = all.hi[k] - all.lo[k];
      built.m_quantStep[k] = extent > 0 ? extent / PfxFloat(65535) : PfxFloat(1);
    }
    for (PfxUInt32 v = 0; v < param.m_numVertices; ++v) {
      for (int k = 0; k < 3; ++k) {
        built.m_quantizedVertices[3 * v + k] =
            quantize(param.m_vertices[3 * v + k], built.m_quantOrigin[k], built.m_quantStep[k]);
      }
    }
    for (PfxUInt32 i = 0; i < built.m_numNodes; ++i) {
      std::copy(builder.m_wideLinks[i].begin(), builder.m_wideLinks[i].end(),
                built.m_quantizedNodes[i].m_links);
    }
  } else {
    std::copy(param.m_vertices, param.m_vertices + 3 * std::size_t(param.m_numVertices),
              built.m_vertices);
    for (PfxUInt32 i = 0; i < built.m_numNodes; ++i) {
      std::copy(builder.m_wideLinks[i].begin(), builder.m_wideLinks[i].end(),
                built.m_nodes[i].m_links);
    }
  }
  for (const PfxLargeMeshIsland& island : builder.m_islands) {
    const std::size_t first = island.m_firstTriangle;
    for (std::size_t t = first; t < first + island.m_numTriangles; ++t) {
      if (storage.cornerOffsets) {
        for (std::size_t c = 3 * t; c < 3 * t + 3; ++c) {
          built.m_triangleOffsets[c] = static_cast<PfxUInt16>(corners[c] - island.m_baseVertex);
        }
      }
      if (storage.sourceOffsets) {
        built.m_triangleSourceOffsets[t] = static_cast<PfxUInt16>(sources[t] - island.m_baseSource);
      }
    }
  }
  if (!storage.cornerOffsets) std::copy(corners.begin(), corners.end(), built.m_triangleVertices);
  if (!storage.sourceOffsets) std::copy(sources.begin(), sources.end(), built.m_triangleSourceIds);
  computeEdgeFlags(corners, param.m_vertices, param.m_flatEdgeAngle, built.m_edgeFlags);
  pfxRefitLargeTriMesh(built);
  mesh = built;
  return PFX_OK;
}

void pfxReleaseLargeTriMesh(PfxLargeTriMesh& mesh) {
  pfxUtilityFree(mesh.m_block);
  std::memset(static_cast<void*>(&mesh), 0, sizeof(mesh));
}

PfxLargeTriMesh* pfxNewLargeTriMesh() {
  auto* mesh = static_cast<PfxLargeTriMesh*>(
      pfxUtilityAllocate(sizeof(PfxLargeTriMesh), PFX_BUFFER_ALIGNMENT));
  if (mesh) std::memset(static_cast<void*>(mesh), 0, sizeof(*mesh));
  return mesh;
}

void pfxDeleteLargeTriMesh(PfxLargeTriMesh* mesh) {
  if (!mesh) return;
  pfxReleaseLargeTriMesh(*mesh);
  pfxUtilityFree(mesh);
}

PfxInt32 pfxUpdateLargeTriMeshVertices(PfxLargeTriMesh& mesh, const PfxFloat* vertices,
                                       PfxUInt32 numVertices) {
  if (!vertices || !mesh.m_block) return PFX_ERR_NULL_POINTER;
  if (numVertices != mesh.m_numVertices) return PFX_ERR_OUT_OF_RANGE;
  const bool quantized = pfxLargeMeshIsQuantized(mesh);
  for (std::size_t i = 0; i < 3 * std::size_t(numVertices); ++i) {
    if (!pfxIsFinite(vertices[i])) return PFX_ERR_INVALID_VALUE;
    if (quantized) {
      // Half a step of slack: a vertex that rounds onto the box's edge is representable.
      const int k = static_cast<int>(i % 3);
      const PfxFloat q = (vertices[i] - mesh.m_quantOrigin[k]) / mesh.m_quantStep[k];
      if (!(q >= PfxFloat(-0.5)) || !(q <= PfxFloat(65535.5))) return PFX_ERR_OUT_OF_RANGE;
    }
  }
  if (quantized) {
    for (std::size_t i = 0; i < 3 * std::size_t(numVertices); ++i) {
      const int k = static_cast<int>(i % 3);
      mesh.m_quantizedVertices[i] = quantize(vertices[i], mesh.m_quantOrigin[k], mesh.m_quantStep[k]);
    }
  } else {
    std::copy(vertices, vertices + 3 * std::size_t(numVertices), mesh.m_vertices);
  }
  pfxRefitLargeTriMesh(mesh);
  return PFX_OK;
}

PfxUInt32 pfxFindLargeTriMeshTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 sourceIndex) {
  for (PfxUInt32 i = 0; i < mesh.m_numIslands; ++i) {
    const PfxLargeMeshIsland& island = mesh.m_islands[i];
    const PfxUInt32 first = island.m_firstTriangle;
    for (PfxUInt32 t = first; t < first + island.m_numTriangles; ++t) {
      if (pfxLargeMeshSource(mesh, island, t) == sourceIndex) return t;
    }
  }
  return PFX_LARGE_MESH_NO_TRIANGLE;
}

PfxUInt32 pfxGetLargeTriMeshSourceTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 triangleIndex) {
  return pfxLargeMeshSource(mesh, mesh.m_islands[pfxLargeMeshIslandOf(mesh, triangleIndex)],
                            triangleIndex);
}

void pfxGetLargeTriMeshTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 triangleIndex,
                                PfxVector3& v0, PfxVector3& v1, PfxVector3& v2) {
  const PfxLargeMeshIsland& island = mesh.m_islands[pfxLargeMeshIslandOf(mesh, triangleIndex)];
  PfxUInt32 corners[3];
  pfxLargeMeshCorners(mesh, island, triangleIndex, corners);
  v0 = pfxLargeMeshVertex(mesh, corners[0]);
  v1 = pfxLargeMeshVertex(mesh, corners[1]);
  v2 = pfxLargeMeshVertex(mesh, corners[2]);
}

}  // namespace pfx
